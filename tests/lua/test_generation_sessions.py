"""Every controller generation through tshark and the Python decoder: sessions of random valid
messages of each generation (tests/tools/valid.py), cut into TCP segments of several sizes,
with and without their Version message, give the same records."""
from __future__ import annotations

import random

import pytest

from tests.lua.harness import F32_TOL, comparable, to_records, tshark_json, ur_items_by_stream, write_sessions
from tests.tools import capture, valid
from tests.vectors import mismatches

import urwire


@pytest.mark.parametrize("max_len", [7, 400])
def test_sessions_of_every_generation_agree_with_python(tmp_path, max_len):
    rng = random.Random(max_len)
    data = []
    for version in valid.versions():
        for _ in range(3):
            session = valid.session(rng, version, 10)
            data += [session, session[int.from_bytes(session[:4], "big"):]]   # and one cut mid-stream
    sessions = [capture.random_cuts([d], seed=i, max_len=max_len) for i, d in enumerate(data)]
    # -Y ur: only the frames that complete a message are printed (the others show nothing of it)
    by_stream = ur_items_by_stream(tshark_json(write_sessions(tmp_path / "generations.pcap", sessions), "-Y", "ur"))
    failures = []
    for i, d in enumerate(data):
        expected = comparable([urwire.to_dict(r) for r in urwire.decode_stream(d)])
        actual = [r for u in by_stream.get(i, []) for r in to_records(u)]
        problems = mismatches(expected, actual, partial=False, tolerance=F32_TOL)
        if problems:
            failures.append(f"stream {i} ({d.hex()[:80]}...): " + "; ".join(problems[:5]))
    assert not failures, f"{len(failures)} of {len(data)} sessions differ:\n" + "\n".join(failures[:10])
