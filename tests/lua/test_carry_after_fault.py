"""After a bad header the dissector carries the stream by hand until it is back in step. A
large message sent in tiny segments right after one must cost tshark memory linear in the
bytes carried: about what TCP reassembly of the same message costs without the fault."""
from __future__ import annotations

from tests.lua.harness import run_tshark_peak_rss
from tests.tools import after_fault

MIB = 1 << 20
PEAK_LIMIT = 600 * MIB   # tshark's peak RSS for 100 KB carried in 1-7 byte segments


def decoded(pcap):
    out, peak = run_tshark_peak_rss(pcap, "-2", "-T", "fields", "-e", "_ws.col.Info", "-e", "ur.text.text")
    rows = [line.split("\t") for line in out.splitlines()]
    return [info for info, _ in rows if info.startswith("Bad header")], [t for _, t in rows if t], peak


def test_a_100_kb_message_after_a_bad_header_in_1_to_7_byte_segments(tmp_path):
    faults, texts, peak = decoded(after_fault.write(tmp_path / "bad.pcap", size=100_000))
    assert faults == [f"Bad header: {after_fault.BAD_HEADER_TEXT}"]
    assert texts == [after_fault.text(100_000).decode()], "the message after the fault, whole"
    assert peak < PEAK_LIMIT, f"tshark peaked at {peak / MIB:.0f} MiB"
    # The same message without the fault goes through TCP reassembly instead.
    faults, texts, clean = decoded(after_fault.write(tmp_path / "clean.pcap", size=100_000, bad_header=False))
    assert not faults and texts == [after_fault.text(100_000).decode()]
    assert peak < 1.5 * clean, f"{peak / MIB:.0f} MiB after the fault, {clean / MIB:.0f} MiB without"
