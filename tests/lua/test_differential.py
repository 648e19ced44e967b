"""Random and mutated streams through tshark and through the Python decoder: same records.
Also: mutated and truncated pcaps never make a Lua error, and the samples decode cleanly."""
from __future__ import annotations

import random

import pytest

from tests.lua.harness import (PLUGIN, ROOT, comparable, run_tshark, to_records, tshark_json, ur_items_by_stream,
                               write_sessions, F32_TOL)
from tests.tools import amplify, capture
from tests.tools.streams import streams
from tests.vectors import all_cases, mismatches

import urwire

MESSAGES = [m for c in all_cases() for m in [c.data] if 5 <= len(m) <= 4000]
COUNT = 400


@pytest.mark.parametrize("seed,max_len", [(11, 300),
                                          pytest.param(12, 5, marks=pytest.mark.deep)])  # 16 s: make test-deep
def test_random_and_mutated_streams_agree_with_python(tmp_path, seed, max_len):
    """Cut anywhere: into segments of up to 300 bytes, and of up to 5 (headers split often)."""
    data = list(streams(MESSAGES, COUNT, seed=seed))
    sessions = [capture.random_cuts([d], seed=i, max_len=max_len) for i, d in enumerate(data)]
    # -Y ur: only the frames that complete a message (most 5-byte segments do not) are printed
    by_stream = ur_items_by_stream(tshark_json(write_sessions(tmp_path / "diff.pcap", sessions), "-Y", "ur"))
    failures = []
    for i, d in enumerate(data):
        expected = comparable([urwire.to_dict(r) for r in urwire.decode_stream(d)])
        actual = [r for u in by_stream.get(i, []) for r in to_records(u)]
        problems = mismatches(expected, actual, partial=False, tolerance=F32_TOL)
        if problems:
            failures.append(f"stream {i} ({d.hex()[:80]}...): " + "; ".join(problems[:5]))
    assert not failures, f"{len(failures)} of {COUNT} streams differ:\n" + "\n".join(failures[:10])


# Rounds of mutation per sample: one in `make test`, the three of the long version in test-deep.
@pytest.mark.parametrize("rounds", [1, pytest.param(3, marks=pytest.mark.deep)])
def test_mutated_and_truncated_pcaps_never_raise_a_lua_error(tmp_path, rounds):
    import dpkt
    rng = random.Random(5)
    for sample in ("primary_session.pcapng", "secondary_session.pcap"):
        path = ROOT / "dissector" / "samples" / sample
        with path.open("rb") as fh:
            reader = dpkt.pcapng.Reader(fh) if sample.endswith("ng") else dpkt.pcap.Reader(fh)
            frames = [bytes(buf) for _, buf in reader]
        for k in range(rounds):
            out = []
            for fr in frames[: rng.randrange(len(frames) // 2, len(frames))]:   # truncated capture
                b = bytearray(fr)
                if len(b) > 54 and rng.random() < 0.5:   # damage the TCP payload only
                    for _ in range(rng.randint(1, 12)):
                        b[rng.randrange(54, len(b))] = rng.randrange(256)
                out.append(bytes(b))
            out[-1] = out[-1][: max(54, len(out[-1]) - 7)]   # and a last frame cut short
            mutated = capture.write(tmp_path / f"mut{k}.pcap", out)
            for opts in (("-2", "-V"), ("-q", "-z", "io,stat,0"), ("-T", "fields", "-e", "ur.type")):
                run_tshark(mutated, *opts)   # raises on any Lua error


def test_hostile_bytes_are_caught(tmp_path):
    """Deep nesting, huge counts, every type byte: experts, never a Lua error."""
    rng = random.Random(9)
    sessions = []
    for _ in range(60):
        body = bytes([rng.choice((16, 20, 25))]) + bytes(rng.randrange(256) for _ in range(rng.randrange(0, 60)))
        deep = b"\x00" * 8 + b"\x01\x00\x00" + b"\x11\x00\x01" * 40
        huge = b"\x00" * 8 + b"\x01\x00\x00" + b"\x11\x7f\xff" * 40
        for payload in (body, b"\x19" + deep, b"\x19" + huge):
            msg = (5 + len(payload) - 1).to_bytes(4, "big") + payload
            sessions.append([msg])
    out = run_tshark(write_sessions(tmp_path / "hostile.pcap", sessions), "-2", "-V")
    assert "nesting deeper than 8" in out
    assert "variables[0] at offset 17: 32767 items need more than the 117 bytes left" in out


def test_counts_past_their_bytes_print_no_more_than_legal_values(tmp_path):
    """Matrices of 32767 empty rows, five bytes each: experts, not millions of tree items."""
    hostile = capture.write(tmp_path / "hostile.pcap", capture.robot_session(amplify.hostile_messages()))
    legal = capture.write(tmp_path / "legal.pcap", capture.robot_session([amplify.legal_stream()]))
    size = len(amplify.hostile_stream())
    cap = amplify.OUTPUT_PER_INPUT * size
    runs = [amplify.run(["tshark", "-r", str(pcap), "-X", f"lua_script:{PLUGIN}", "-2", "-V"], cap=cap)
            for pcap in (hostile, legal)]
    assert runs[0].printed <= cap
    assert runs[0].code == 0 and runs[1].code == 0
    assert runs[0].peak <= 2 * runs[1].peak


def test_samples_decode_without_faults():
    for sample in ("primary_session.pcapng", "secondary_session.pcap"):
        out = run_tshark(ROOT / "dissector" / "samples" / sample, "-q", "-z", "expert,error")
        assert "Malformed" not in out, out
        fields = run_tshark(ROOT / "dissector" / "samples" / sample, "-Y", "ur.robot_mode_data.robot_mode == \"RUNNING\"",
                            "-T", "fields", "-e", "frame.number")
        assert fields.split(), "no RUNNING robot state found by its value string"
    q = run_tshark(ROOT / "dissector" / "samples" / "primary_session.pcapng", "-Y", "ur.joint_data.q_actual > 1.5")
    assert q.strip()
    script = run_tshark(ROOT / "dissector" / "samples" / "primary_session.pcapng", "-Y", "ur.urscript",
                        "-T", "fields", "-e", "ur.urscript")
    assert "movej" in script


def test_a_lua_error_is_caught_and_shown(tmp_path):
    """The pcall guard: make a copy of the plugin whose robot-side path throws; tshark shows an
    expert on the packet and no Lua error reaches the user."""
    from tests.lua.harness import INTERNAL_TEXT
    import subprocess
    text = PLUGIN.read_text(encoding="utf-8")
    anchor = "    local raw = tvb:raw()\n"
    assert text.count(anchor) == 1
    broken = tmp_path / "broken.lua"
    broken.write_text(text.replace(anchor, anchor + '    if #raw > 0 then error("boom") end\n'), encoding="utf-8")
    res = subprocess.run(["tshark", "-r", str(ROOT / "dissector" / "samples" / "primary_session.pcapng"),
                          "-X", f"lua_script:{broken}", "-V"], capture_output=True, text=True)
    assert "Lua: Error" not in res.stderr and "_ws.lua.error" not in res.stdout
    assert INTERNAL_TEXT in res.stdout and "boom" in res.stdout
