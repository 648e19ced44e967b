"""urwire's data tools, over captures already made: `urwire export` (export.py: a table per kind,
CSV or Parquet; export_dataset.py: the Hive-partitioned dataset of dataset.py), `urwire spark`
(spark.py: a folder of captures into that dataset on Apache Spark) and `urwire plot` (plot.py, over
decimate.py). They decode with the core package (urwire) and import nothing from urwire.live;
pyarrow, pyspark and matplotlib are optional extras that they import only where they need them.
"""
