"""`urwire decode` of a capture under the C backend, whose primary conversations C writes
(urwire/capture_json.py), against the path that writes every record in Python: the same lines,
exit code and stderr, for every capture the tests have and for lossy primary conversations (a
framer restart after each gap), and the same announced version."""
from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.tools import capture as pcap
from urwire import capture, cli
from urwire.extension import CCORE
from urwire.interfaces import PrimaryConversation

ROOT = Path(__file__).resolve().parents[2]
CAPTURES = sorted(p for folder in ("tests", "examples", "dissector") for pattern in ("*.pcap", "*.pcapng")
                  for p in (ROOT / folder).rglob(pattern))
SAMPLE = ROOT / "dissector" / "samples" / "cell_session.pcapng"

pytestmark = pytest.mark.skipif(CCORE is None, reason="the C extension is not built")


def decoded(argv: list[str], in_c: bool, monkeypatch, capsys) -> tuple[int, str, str]:
    """Exit code, stdout and stderr of `urwire decode`, its capture lines written in C or not."""
    monkeypatch.setattr(cli, "backend", lambda: "c" if in_c else "python")
    out = io.StringIO()
    monkeypatch.setattr(sys, "stdout", out)
    code = cli.main(["decode", "--no-progress", *argv])
    return code, out.getvalue(), capsys.readouterr().err


def assert_same(argv: list[str], monkeypatch, capsys) -> str:
    in_c = decoded(argv, True, monkeypatch, capsys)
    assert in_c == decoded(argv, False, monkeypatch, capsys), argv
    return in_c[1]


def primary_stream() -> bytes:
    with open(SAMPLE, "rb") as fh:
        return b"".join(data for _, data, _ in capture.robot_streams(fh, {30001, 30002}))


def lossy(path: Path) -> Path:
    """Two robots' primary conversations cut into segments, some of them lost: a gap each, after
    which the framer starts afresh; the conversations interleave."""
    stream = primary_stream() * 8
    pieces = [stream[at:at + 300] for at in range(0, len(stream), 300)]
    one = pcap.robot_session(pieces, port=30001)
    two = pcap.robot_session(pieces[::-1], port=30002, robot="192.168.56.102", client_port=50200)
    del one[3 + 2 * 3], two[3 + 2 * 5]             # a robot segment each, after the handshake
    frames = [frame for pair in zip(one, two) for frame in pair]
    return pcap.write(path, frames, pcapng=True)


def test_there_are_captures_to_compare():
    assert len(CAPTURES) >= 10


@pytest.mark.parametrize("path", CAPTURES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_capture_of_the_tests_prints_the_same(path, monkeypatch, capsys):
    assert_same([str(path)], monkeypatch, capsys)


def test_lost_segments_of_two_robots_print_the_same(tmp_path, monkeypatch, capsys):
    out = assert_same([str(lossy(tmp_path / "lossy.pcapng"))], monkeypatch, capsys)
    assert out.count("bytes missing from the capture") == 2
    assert '"conversation": "192.168.56.102:30002-' in out


def test_runs_of_segments_fed_in_slices_print_the_same(tmp_path, monkeypatch, capsys):
    """One primary conversation of many segments in a row: the C reader joins them into runs, fed
    to C in slices (FEED_BYTES) that cut its messages; the first slices come before the conversation's
    lines have their envelope from C."""
    from urwire import capture_json

    stream = primary_stream() * 8
    frames = pcap.robot_session([stream[at:at + 300] for at in range(0, len(stream), 300)], port=30001)
    path = str(pcap.write(tmp_path / "long.pcapng", frames, pcapng=True))
    monkeypatch.setattr(capture_json, "FEED_BYTES", 1000)
    fed = []
    feed = capture_json.PrimaryJsonConversation.feed
    monkeypatch.setattr(capture_json.PrimaryJsonConversation, "feed",
                        lambda self, data, from_robot: fed.append(data) or feed(self, data, from_robot))
    out = assert_same([path], monkeypatch, capsys)
    assert any(isinstance(data, capture.Segments) and len(data.data) > 3000 for data in fed)
    assert out.count('"conversation": "192.168.56.101:30001-') == out.count("\n") >= 16


def test_a_hint_and_one_protocol_print_the_same(tmp_path, monkeypatch, capsys):
    path = str(lossy(tmp_path / "lossy.pcapng"))
    assert_same([path, "--version-hint", "3.2"], monkeypatch, capsys)
    assert_same([path, "--protocol", "ur", "--port", "30002"], monkeypatch, capsys)


def test_the_command_prints_the_same_under_either_backend(tmp_path):
    path = str(lossy(tmp_path / "lossy.pcapng"))
    runs = [subprocess.run([sys.executable, "-m", "urwire", "decode", "--no-progress", path], capture_output=True,
                           env=dict(os.environ, URWIRE_BACKEND=name)) for name in ("c", "python")]
    assert runs[0].stdout == runs[1].stdout and runs[0].returncode == runs[1].returncode == 1


def test_the_announced_version_and_a_restart_are_the_framers():
    from urwire.capture_json import PrimaryJsonConversation
    stream = primary_stream()
    in_c, in_python = PrimaryJsonConversation(), PrimaryConversation()
    in_c.feed(stream[:5000], True)
    in_python.feed(stream[:5000], True)
    assert in_c.software_version == in_python.software_version is not None
    lines = b"".join(w.text for w in in_c.lost(True, 9000) + in_c.feed(stream[9000:], True) + in_c.close(True))
    records = in_python.lost(True, 9000) + in_python.feed(stream[9000:], True) + in_python.close(True)
    assert lines.decode() == "".join(cli.to_json_line(r) + "\n" for r in records)


def assert_heads_replace_braces(ccore) -> None:
    """PrimaryJsonLines with a head, fed in pieces and restarted: each line as without one, its
    "{" replaced by the head. Also run under ASan and UBSan (ccore_asan_peer.py)."""
    stream = primary_stream() * 4
    head = b'{"interface": "ur", "direction": "from_robot", "conversation": "\xc3\xa9", '
    plain, headed = ccore.PrimaryJsonLines(), ccore.PrimaryJsonLines()
    headed.set_head(head)
    want, got = b"", b""
    for n, at in enumerate(range(0, len(stream), 700)):
        for lines in (plain, headed):
            text = lines.restart(at + 333) if n % 3 == 2 else lines.feed(stream[at:at + 700])
            if lines is plain:
                want += text
            else:
                got += text
    want, got = want + plain.close(), got + headed.close()
    lines = want.split(b"\n")[:-1]
    assert len(lines) > 10 and got == b"".join(head + line[1:] + b"\n" for line in lines)
    assert plain.errors and headed.errors         # the restarts cut messages
    with pytest.raises(TypeError):
        headed.set_head("{")


def test_a_head_replaces_each_lines_brace():
    assert_heads_replace_braces(CCORE)
