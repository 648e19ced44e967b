"""Every golden vector and conformance case, written into pcaps in several segmentations and
decoded by real tshark with the generated dissector: the values must equal the expected ones.

One pcap per (segmentation, version hint) holds every case as its own TCP session, so each
segmentation costs one tshark run.
"""
from __future__ import annotations

import pytest

from tests.lua.harness import F32_TOL, comparable, to_records, tshark_json, ur_items_by_stream, write_sessions
from tests.tools import capture
from tests.vectors import all_cases, mismatches

import urwire

CASES = all_cases()
HINTS = sorted({c.version for c in CASES}, key=lambda v: v or "")
# The tail of a real message: a capture that starts in the middle of the stream.
MID_STREAM = bytes.fromhex("3ff000000000000000000001")

SEGMENTATIONS = {
    "whole": capture.whole,
    "bytewise": capture.bytewise,
    "random_cuts": lambda msgs: capture.random_cuts(msgs, seed=7, max_len=40),
    "packed": lambda msgs: capture.packed(msgs, per_segment=3),
    "mid_stream": lambda msgs: capture.random_cuts([MID_STREAM] + list(msgs), seed=3, max_len=300),
    "retransmitted": lambda msgs: capture.random_cuts(msgs, seed=5, max_len=200),
}


def split_messages(data: bytes) -> list[bytes]:
    """Cut a case's stream at its declared lengths where they are plausible (else keep it whole),
    so that 'whole' and 'packed' mean one or several messages per segment."""
    out, pos = [], 0
    while len(data) - pos >= 5:
        n = int.from_bytes(data[pos:pos + 4], "big", signed=True)
        if n < 5 or pos + n > len(data):
            break
        out.append(data[pos:pos + n])
        pos += n
    if pos < len(data):
        out.append(data[pos:])
    return out


def expected(case, segmentation: str) -> list:
    if segmentation == "mid_stream":
        # The reference decoder tells what the extra leading bytes turn into.
        recs = [urwire.to_dict(r) for r in urwire.decode_stream(MID_STREAM + case.data, version_hint=case.version)]
        return comparable(recs)
    return comparable(case.expect)


@pytest.fixture(scope="module", params=sorted(SEGMENTATIONS))
def decoded(request, tmp_path_factory):
    seg = request.param
    out = {}
    for hint in HINTS:
        cases = [c for c in CASES if c.version == hint]
        streams = [SEGMENTATIONS[seg](split_messages(c.data)) for c in cases]
        pcap = write_sessions(tmp_path_factory.mktemp(seg) / f"{seg}_{hint}.pcap", streams,
                              handshake=seg != "mid_stream", retransmit_every=3 if seg == "retransmitted" else 0)
        opts = ("-o", f"ur.version:{hint}") if hint else ()
        # -Y ur: only the frames that complete a message are printed (the others show nothing of it)
        by_stream = ur_items_by_stream(tshark_json(pcap, *opts, "-Y", "ur"))
        for i, c in enumerate(cases):
            out[c.name] = [r for u in by_stream.get(i, []) for r in to_records(u)]
    return seg, out


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_case(decoded, case):
    seg, out = decoded
    exp = expected(case, seg)
    partial = case.partial and seg != "mid_stream"
    problems = mismatches(exp, out[case.name], partial=partial, tolerance=max(case.tolerance, F32_TOL))
    assert not problems, f"{case.name} ({seg}):\n" + "\n".join(problems[:20])
