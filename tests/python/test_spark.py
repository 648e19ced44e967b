"""`urwire spark` (python/urwire/data/spark.py) in Spark's local[2] mode: a folder of captures of
robots, raw streams, .pcap and .pcapng, gives the dataset that exporting each capture in turn
gives (dataset.capture_parts, then dataset.write_parts, with the file's name, the raw streams'
robot and the file's day: what `urwire export --dataset` does), file for file and row for row; its manifest counts those rows, and a second run over the same
folder replaces the parts instead of adding rows. One Spark session serves the module."""
from __future__ import annotations

import datetime
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("pyspark", reason="needs pyspark (pip install urwire[spark])")
pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
duckdb = pytest.importorskip("duckdb")
if shutil.which("java") is None and not os.environ.get("JAVA_HOME"):
    pytest.skip("Spark needs a Java runtime (java on PATH or JAVA_HOME)", allow_module_level=True)

from tests.tools import capture  # noqa: E402
from tests.tools.robot_inputs import real_states  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "dissector" / "samples"


@pytest.fixture(scope="module")
def spark():
    from pyspark.sql import SparkSession

    before = os.environ.get("PYSPARK_PYTHON")
    os.environ["PYSPARK_PYTHON"] = sys.executable   # the executors import urwire as this process does:
    tree = os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")])   # this tree's, not an install's
    session = (SparkSession.builder.master("local[2]").appName("urwire-test")
               .config("spark.ui.enabled", "false").config("spark.sql.shuffle.partitions", "2")
               .config("spark.executorEnv.PYTHONPATH", tree).getOrCreate())
    session.sparkContext.setLogLevel("ERROR")
    yield session
    session.stop()
    if before is None:
        del os.environ["PYSPARK_PYTHON"]
    else:
        os.environ["PYSPARK_PYTHON"] = before


@pytest.fixture(scope="module")
def captures(tmp_path_factory) -> Path:
    """Two folders: the bundled primary capture (.pcapng) and a raw stream of real states in one;
    the bundled capture of a whole cell and a .pcap of real states from another robot address
    in the other."""
    folder = tmp_path_factory.mktemp("captures")
    states = real_states()
    (folder / "robot-a").mkdir()
    (folder / "robot-b").mkdir()
    shutil.copy(SAMPLES / "primary_session.pcapng", folder / "robot-a" / "primary_session.pcapng")
    (folder / "robot-a" / "states.bin").write_bytes(b"".join(states[:40]))
    shutil.copy(SAMPLES / "cell_session.pcapng", folder / "robot-b" / "cell_session.pcapng")
    capture.write(folder / "robot-b" / "states.pcap", capture.robot_session(states[10:60], robot="192.168.56.102"))
    return folder


RAW_ROBOT = "robot-raw"


def sequential_export(captures: Path, out: Path) -> Path:
    from urwire.data import dataset
    from urwire.data.spark import utc_date

    for path in sorted(p for p in captures.rglob("*") if p.is_file()):
        data = path.read_bytes()
        day = utc_date(datetime.datetime.fromtimestamp(path.stat().st_mtime, datetime.timezone.utc))
        dataset.write_parts(out, dataset.capture_parts(data, path.name, None, RAW_ROBOT, day),
                            dataset.capture_id(data))
    return out


def part_files(root: Path) -> dict[str, Path]:
    return {str(p.relative_to(root)): p for p in root.rglob("*.parquet")}


@pytest.fixture(scope="module", params=[False, True], ids=["tasks-read-files", "bytes-through-jvm"])
def exported(request, spark, captures, tmp_path_factory):
    """The dataset of `urwire spark`, each task reading its local file itself (the default for a
    local folder) or given its bytes by binaryFile (as from s3a://)."""
    from urwire.data.spark import export_folder

    out = tmp_path_factory.mktemp("spark-dataset")
    manifest = export_folder(spark, str(captures), str(out), robot=RAW_ROBOT, through_jvm=request.param).collect()
    return out, manifest


def test_same_part_files_as_the_export(exported, captures, tmp_path):
    out, _ = exported
    reference = part_files(sequential_export(captures, tmp_path / "export"))
    written = part_files(out)
    assert sorted(written) == sorted(reference)
    robots = {name.split("robot=")[1].split("/")[0] for name in written}
    assert RAW_ROBOT in robots and len(robots) >= 2
    assert any(name.startswith("interface=ur_realtime/") for name in written)   # from the cell capture
    for name, path in reference.items():
        expected, got = pq.read_table(path), pq.read_table(written[name])
        assert got.schema == expected.schema, name
        assert got.to_pylist() == expected.to_pylist(), name
        # A capture's rows name their conversation; a raw stream has none.
        assert (set(got.column("conversation").to_pylist()) == {None}) == (f"robot={RAW_ROBOT}/" in name), name


def test_joint_data_row_for_row_through_duckdb(exported, captures, tmp_path):
    out, _ = exported
    reference = sequential_export(captures, tmp_path / "export")

    def rows(root: Path):
        return duckdb.sql(f"SELECT robot, date, * EXCLUDE (robot, date, interface, kind) FROM read_parquet("
                          f"'{root}/interface=ur/kind=joint_data/*/*/*.parquet', hive_partitioning = true, union_by_name = true) "
                          f"ORDER BY ALL").fetchall()

    got = rows(out)
    assert got == rows(reference)
    assert len({robot for robot, *_ in got}) >= 2
    assert len(got) > 90     # every robot state of the four captures has a joint_data row


def test_manifest_counts_the_rows_written(exported):
    out, manifest = exported
    assert {Path(row.path).name for row in manifest} >= {"primary_session.pcapng", "states.bin",
                                                       "cell_session.pcapng", "states.pcap"}
    for interface, kind in {(row.interface, row.kind) for row in manifest}:
        files = list(out.glob(f"interface={interface}/kind={kind}/*/*/*.parquet"))
        assert sum(pq.read_metadata(f).num_rows for f in files) == \
            sum(row.rows for row in manifest if (row.interface, row.kind) == (interface, kind))


def test_a_second_run_replaces_its_parts(spark, captures, tmp_path):
    from urwire.data.spark import export_folder

    out = tmp_path / "twice"
    export_folder(spark, str(captures), str(out), robot=RAW_ROBOT).collect()
    once = {name: pq.read_metadata(p).num_rows for name, p in part_files(out).items()}
    export_folder(spark, str(captures), str(out), robot=RAW_ROBOT).collect()
    assert {name: pq.read_metadata(p).num_rows for name, p in part_files(out).items()} == once


def test_command_line_without_pyspark_says_how_to_install(tmp_path):
    env = {**os.environ, "PYTHONPATH": f"{tmp_path}:{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
    (tmp_path / "pyspark").mkdir()
    (tmp_path / "pyspark" / "__init__.py").write_text("raise ImportError('no pyspark here')\n")
    result = subprocess.run([sys.executable, "-m", "urwire", "spark", "--out", str(tmp_path / "o"), str(tmp_path)],
                            capture_output=True, text=True, env=env, timeout=60)
    assert result.returncode == 2
    assert "pip install urwire[spark]" in result.stderr


def test_tasks_read_only_what_they_can_open():
    from urwire.data.spark import local_path, reads_locally

    assert reads_locally("/plant/captures") and reads_locally("file:///plant/captures")
    assert not reads_locally("s3a://plant/captures") and not reads_locally("hdfs://nn/captures")
    assert local_path("file:/plant/robot%201/day.pcap") == "/plant/robot 1/day.pcap"
    assert local_path("s3a://plant/day.pcap") is None
