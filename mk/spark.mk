# Apache Spark: `urwire spark` (python/urwire/data/spark.py) and its benchmark. Its tests are
# tests/python/test_spark.py, run with the other Python tests (skipped without pyspark or java).

BENCH_TARGETS += bench-spark
BENCH_SPARK_DAYS ?= 10
# raw: the primary port's bytes as `urwire listen --raw` records them, which the C backend reads
# whole; pcap: the same states in a .pcap, whose frames and TCP segments Python still reads
BENCH_SPARK_FORMAT ?= raw
# each robot-day in hourly files, as a recorder that starts a file an hour writes them: Spark holds
# a file whole in memory, and one task per 1.2 GB day leaves its 8 GB driver short of heap
BENCH_SPARK_HOURS ?= 24

.PHONY: bench-spark

## bench-spark: BENCH_SPARK_DAYS robot-days (864,000 real robot states each, in BENCH_SPARK_FORMAT,
## built once under build/bench-spark/) to a dataset by `urwire spark` in Spark local[2] and by a
## sequential export of the same files, in one run: seconds, states/s and the ratio (BENCH_SMALL=1:
## 2,000 states a day)
bench-spark:
	PYTHONPATH=python:generated/python $(PYTHON) tests/bench/bench_spark.py --days $(BENCH_SPARK_DAYS) --format $(BENCH_SPARK_FORMAT) \
		--hours $(BENCH_SPARK_HOURS)
