"""The differential fuzzer of the cell's other interfaces (tests/fuzz/fuzz_diff.py, `make fuzz-diff`)
replayed: every golden session of each interface and its kept corpus
(tests/fuzz/corpus/diff_<interface>/) through `urwire decode` and urwire-decode (its main run in
one process, ASan and UBSan on): the same lines, byte for byte, and the same exit status. And the
fuzzer itself: it stops on a difference and keeps the session, which reads back as it was."""
from __future__ import annotations

import random

import pytest

from tests.c.harness_c import build_decode_driver
from tests.fuzz import fuzz_diff
from tests.fuzz.diff_sessions import INTERFACES, Mutator, dump, kept, load, seeds


@pytest.fixture(scope="module")
def peer():
    with_peer = fuzz_diff.CPeer(build_decode_driver())
    yield with_peer
    with_peer.close()


@pytest.fixture(scope="module")
def space():
    workspace = fuzz_diff.Workspace()
    yield workspace
    workspace.dir.cleanup()


@pytest.mark.parametrize("interface", INTERFACES)
def test_every_interface_has_a_small_kept_corpus(interface):
    sessions = kept(interface)
    assert len(sessions) >= 20 and all(len(raw) <= 8192 for raw in sessions)


@pytest.mark.parametrize("interface", INTERFACES)
def test_the_golden_and_kept_sessions_agree(interface, peer, space):
    sessions = seeds(interface)
    assert any(s.to_robot for s in sessions) == (interface != "ur_realtime")
    for session in sessions:
        why, output = fuzz_diff.check(interface, session, peer, space)
        assert why is None, f"{interface} session {dump(session)[:80].hex()}: {why}"
        assert output or not session.size()


@pytest.mark.parametrize("interface", INTERFACES)
def test_a_session_reads_back_from_its_file(interface):
    rng = random.Random(interface)
    pool = seeds(interface)
    mutate = Mutator(interface, rng)
    for _ in range(200):
        session = mutate(rng.choice(pool), pool)
        again = load(interface, dump(session))
        assert (again.hint, again.to_robot, again.stream(True)) == (session.hint, session.to_robot,
                                                                     session.stream(True))
        assert again.stream(False) == (session.stream(False) if session.to_robot else b"")


def test_a_difference_stops_the_run_and_keeps_the_session(peer, space, tmp_path, monkeypatch):
    """Python made to print one line more than C: the first session fails, and is kept."""
    answer = fuzz_diff.python_answer
    monkeypatch.setattr(fuzz_diff, "python_answer", lambda args: (answer(args)[0] + b"{}\n", answer(args)[1]))
    done, failures, _ = fuzz_diff.fuzz("rtde", 0, 5, random.Random(1), peer, space, tmp_path, False, None)
    assert (done, failures) == (1, 1)
    (kept_file,) = (tmp_path / "diff_rtde").glob("*[0-9a-f]")
    again, first = load("rtde", kept_file.read_bytes()), seeds("rtde")[0]
    assert (again.stream(True), again.stream(False)) == (first.stream(True), first.stream(False))
    assert "lines from python" in kept_file.with_suffix(".txt").read_text()


def test_a_robot_file_read_as_a_capture_is_not_compared(peer, space):
    """urwire-decode reads raw streams only: a lone robot stream opening with a whole pcap header
    (a big-endian magic, then major version 2) is a capture to `urwire decode` alone, which must
    still raise nothing; a magic without the version stays raw to both and is compared."""
    session = load("rtde", bytes.fromhex("000000000000" "a1b2c3d4" "0002"))
    assert fuzz_diff.read_as_capture(session)
    why, output = fuzz_diff.check("rtde", session, peer, space)
    assert why is None and b"capture header unreadable" in output
    raw = load("rtde", bytes.fromhex("000000000000" "a1b2c3d4" "0003"))
    assert not fuzz_diff.read_as_capture(raw)
    assert fuzz_diff.check("rtde", raw, peer, space)[0] is None
