"""Reading in flat memory: decode_file, the command and decode_stream hold a bounded part of
their input, whatever its size. Each runs in its own process on N and 3N megabytes of real robot
states (raw, .pcap, .pcapng, built once in build/); its peak resident memory (wait4, through the
watcher of tests/tools/measure.py) must stay under PEAK_LIMIT and grow by less than GROWTH_LIMIT
from the small input to the large one. Every state is decoded: each run says how many records
it made.

The sizes are the smallest that show the bound: reading is at its peak from a few megabytes on
(the same peak at 3, 8, 24 and 60 MB), so 6 MB against 18 MB, where keeping the input, or the
records, would grow by more than twice GROWTH_LIMIT. Export reaches its peak only once every
table has filled a batch of rows to write (export.BATCH_ROWS) and its memory has settled, from
about 12 MB of states on (Parquet: 103, 114, 125, 126, 130 and 131 MiB at 3, 8, 12, 24, 36 and
60 MB; CSV: 43, 50, 58, 62, 62 and 61 MiB), so it compares 12 MB with 36, where keeping the
input would grow by twice EXPORT_GROWTH_LIMIT."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from tests.tools import measure, robot_inputs

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
SIZES = (6, 18)
EXPORT_SIZES = (12, 24)
MIB = 1 << 20
PEAK_LIMIT = 120 * MIB
GROWTH_LIMIT = 6 * MIB         # half of what keeping the larger input would add
EXPORT_GROWTH_LIMIT = 12 * MIB
PYARROW = 70 * MIB  # what importing pyarrow.parquet takes on its own

COUNT_FILE = "import sys, urwire; print(sum(1 for _ in urwire.decode_file(sys.argv[1])))"
COUNT_STREAM = ("import sys, urwire; data = open(sys.argv[1], 'rb').read(); "
                "print(sum(1 for _ in urwire.decode_stream(data)))")
COMMAND = ["-m", "urwire", "decode", "--no-progress"]


def run(args: list[str]) -> measure.Usage:
    usage = measure.watch([sys.executable, *args], ENV)
    assert usage.returncode == 0, args
    return usage


@pytest.fixture(scope="module")
def states() -> list[bytes]:
    return robot_inputs.real_states()


# The captures' runs take 5-12 s each: make test-deep
@pytest.mark.parametrize("how, form", [("decode_file", "bin"),
                                       pytest.param("decode_file", "pcap", marks=pytest.mark.deep),
                                       pytest.param("command", "pcapng", marks=pytest.mark.deep)])
def test_reading_a_file_takes_flat_memory(states, how, form):
    peaks = []
    for megabytes in SIZES:
        if form == "bin":
            path = robot_inputs.raw_stream(megabytes, states)
        else:
            path = robot_inputs.capture(megabytes, pcapng=form == "pcapng", states=states)
        if how == "decode_file":
            usage = run(["-c", COUNT_FILE, str(path)])
            records = int(usage.last)
        else:
            usage = run([*COMMAND, str(path)])
            records = usage.lines
        assert records == robot_inputs.message_count(megabytes, states)
        peaks.append(usage.peak)
    assert peaks[-1] < PEAK_LIMIT, f"{peaks[-1] / MIB:.0f} MiB"
    assert peaks[-1] - peaks[0] < GROWTH_LIMIT, f"{peaks[0] / MIB:.0f} -> {peaks[-1] / MIB:.0f} MiB"


def test_decode_stream_holds_its_buffer_and_a_bounded_part_of_its_records(states):
    """The buffer is the caller's; beyond it, the same memory for three times the records."""
    beyond = []
    for megabytes in SIZES:
        path = robot_inputs.raw_stream(megabytes, states)
        usage = run(["-c", COUNT_STREAM, str(path)])
        assert int(usage.last) == robot_inputs.message_count(megabytes, states)
        beyond.append(usage.peak - path.stat().st_size)
    assert beyond[-1] - beyond[0] < GROWTH_LIMIT, f"{beyond[0] / MIB:.0f} -> {beyond[-1] / MIB:.0f} MiB"


@pytest.mark.deep  # a long export (about 40 s of a core): make test-deep
@pytest.mark.parametrize("form", ["parquet", "csv"])
def test_export_takes_flat_memory(states, tmp_path, form):
    """`urwire export` keeps its rows on disk until the tables are written, a batch at a time:
    twice the capture, the same memory, and every state a row."""
    if form == "parquet":
        pytest.importorskip("pyarrow")
    peaks = []
    for megabytes in EXPORT_SIZES:
        out = tmp_path / f"{megabytes}-{form}"
        usage = run(["-m", "urwire", "export", str(robot_inputs.capture(megabytes, states=states)),
                     "--format", form, "--out", str(out)])
        assert rows(out / f"robot_state.{form}") == robot_inputs.message_count(megabytes, states)
        assert not [p for p in out.iterdir() if p.name.startswith(".")]  # the spilled rows are gone
        peaks.append(usage.peak)
    limit = PEAK_LIMIT + (PYARROW if form == "parquet" else 0)
    assert peaks[-1] < limit, f"{peaks[-1] / MIB:.0f} MiB"
    assert peaks[-1] - peaks[0] < EXPORT_GROWTH_LIMIT, f"{peaks[0] / MIB:.0f} -> {peaks[-1] / MIB:.0f} MiB"


def rows(table: Path) -> int:
    if table.suffix == ".csv":
        with open(table, "rb") as fh:
            return sum(1 for _ in fh) - 1  # the header
    import pyarrow.parquet as pq
    return pq.read_metadata(table).num_rows


@pytest.mark.deep  # a long plot (about 5 s): make test-deep
def test_plot_takes_flat_memory(states, tmp_path):
    """`urwire plot` decimates as it reads (min/max per run of points): three times the capture,
    the same memory, and every state a point."""
    pytest.importorskip("matplotlib")
    peaks = []
    for megabytes in SIZES:
        path = robot_inputs.capture(megabytes, states=states)
        usage = measure.watch([sys.executable, "-m", "urwire", "plot", str(path), "--field", "joint_data.q_actual",
                               "--out", str(tmp_path / f"{megabytes}.png")], ENV)
        assert usage.returncode == 0
        peaks.append(usage.peak)
    assert peaks[-1] - peaks[0] < GROWTH_LIMIT, f"{peaks[0] / MIB:.0f} -> {peaks[-1] / MIB:.0f} MiB"
