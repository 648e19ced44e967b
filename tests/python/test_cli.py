"""The urwire command, as docs/contract.md#what-every-target-keeps says: inputs, JSON Lines,
--version-hint, exit codes."""
from __future__ import annotations

import json
import os
import struct
import subprocess
import sys
from pathlib import Path

import pytest
import urwire as package

from tests.tools import capture
from tests.tools.envelope import bare, where
from tests.vectors import all_cases

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
GOOD = [c for c in all_cases() if c.name.startswith("Universal_Robots_Client_Library/")
        and "template" not in c.name and "runtime_exception" not in c.name]


def urwire(*args: str, stdin: bytes | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "urwire", *args], input=stdin, capture_output=True, env=ENV)


def records(result) -> list[dict]:
    return [json.loads(line) for line in result.stdout.decode().splitlines()]


def test_a_clean_stream_exits_0_and_prints_one_line_per_message(tmp_path):
    data = b"".join(c.data for c in GOOD)
    path = tmp_path / "stream.bin"
    path.write_bytes(data)
    result = urwire("decode", str(path))
    assert result.returncode == 0, result.stderr
    assert len(records(result)) == len(GOOD)


def test_standard_input_is_read_with_a_dash():
    result = urwire("decode", "-", stdin=GOOD[0].data)
    assert result.returncode == 0
    assert records(result)[0]["type"] == "key"


def test_error_records_exit_1():
    (case,) = [c for c in all_cases() if c.name == "Universal_Robots_Client_Library/runtime_exception_message"]
    result = urwire("decode", "-", stdin=case.data)
    assert result.returncode == 1
    assert records(result)[-1] == {"type": "error", "offset": 57, "error": "truncated header: 2 bytes left"}


def test_a_malformed_package_also_exits_1():
    (case,) = [c for c in all_cases() if c.name == "robot_state_package_short"]
    assert urwire("decode", "-", stdin=case.data).returncode == 1


@pytest.mark.parametrize("args", [["decode", "/no/such/file"], ["decode"], ["frobnicate", "x"],
                                  ["decode", "--version-hint", "five", "-"]])
def test_usage_and_io_errors_exit_2_with_one_line(args):
    result = urwire(*args, stdin=b"")
    assert result.returncode == 2
    assert len(result.stderr.decode().strip().splitlines()) == 1, result.stderr


def test_version_hint_chooses_the_value_table():
    (case,) = [c for c in all_cases() if c.name == "global_variables_update_doc_example_5_0"]
    under_hint = records(urwire("decode", "--version-hint", "5.0", "-", stdin=case.data))
    assert [v["type"] for v in under_hint[0]["variables"]] == ["BOOL", "CONST_STRING"]
    default = urwire("decode", "-", stdin=case.data)
    assert default.returncode == 1 and "error" in records(default)[0]


def test_version_hint_takes_a_bugfix_number():
    (case,) = [c for c in all_cases() if c.name == "robot_state_configuration_data_449"]
    hinted = urwire("decode", "--version-hint", "5.25.1", "-", stdin=case.data)
    assert hinted.returncode == 0 and records(hinted) == case.expect
    assert "reserved_1" in records(hinted)[0]["packages"][0]
    bad = urwire("decode", "--version-hint", "5.25.x", "-", stdin=case.data)
    assert bad.returncode == 2 and "5.25.1" in bad.stderr.decode()


@pytest.mark.parametrize("hint", ["５.９", "٥.٩", "5.²", "\xa05.9", "5.9\u2028", "5.9\x1c", "1234567.0"])
def test_version_hint_is_ascii_digits_between_ascii_blanks(hint):
    """As urwire-decode reads it (C's urwire_parse_version): no Unicode digits or blanks, and
    at most six digits a part."""
    with pytest.raises(ValueError, match="not a software version"):
        package.parse_version(hint)
    assert package.parse_version(" 5.25.1\t") == (5, 25, 1)
    assert package.parse_version("999999.0") == (999999, 0, 0)


def test_text_view_names_codes_as_the_stream_version_does():
    (case,) = [c for c in all_cases() if c.name == "generation_cb2_1_8_robot_state"]
    text = urwire("decode", "--format", "text", "-", stdin=case.data).stdout.decode()
    robot_mode = case.expect[1]["packages"][0]["robot_mode"]
    names_1x = {0: "RUNNING", 1: "FREEDRIVE", 2: "READY", 3: "INITIALIZING", 4: "SECURITY_STOPPED",
                5: "EMERGENCY_STOPPED", 6: "FATAL_ERROR", 7: "NO_POWER", 8: "NOT_CONNECTED", 9: "SHUTDOWN",
                10: "SAFEGUARD_STOP"}
    assert names_1x[robot_mode] in text.splitlines()[1]


def test_help_states_the_default_version():
    result = urwire("decode", "--help")
    assert "default: 5.9" in " ".join(result.stdout.decode().split())   # as argparse wraps it


@pytest.mark.parametrize("pcapng", [False, True])
def test_captures_are_reassembled(tmp_path, pcapng):
    messages = [c.data for c in GOOD]
    frames = capture.robot_session(capture.random_cuts(messages, seed=7, max_len=90), retransmit=[2, 5])
    path = capture.write(tmp_path / ("s.pcapng" if pcapng else "s.pcap"), frames, pcapng=pcapng)
    result = urwire("decode", str(path))
    assert result.returncode == 0, result.stderr
    raw = urwire("decode", "-", stdin=b"".join(messages))
    # Each record of the capture names its conversation; the rest of it is what the raw stream gives.
    assert {where(r) for r in records(result)} == {("ur", "from_robot", "192.168.56.101:30001-192.168.56.1:50123")}
    assert [bare(r) for r in records(result)] == records(raw)


def test_client_to_robot_script_is_not_decoded(tmp_path):
    segs = [capture.Segment(False, b"def prog():\n  textmsg(\"hi\")\nend\n"), capture.Segment(True, GOOD[0].data)]
    path = capture.write(tmp_path / "s.pcap", capture.session_frames(segs))
    assert [r["type"] for r in records(urwire("decode", str(path)))] == ["key"]


def test_a_capture_starting_mid_stream_resynchronises(tmp_path):
    data = b"".join(c.data for c in GOOD)
    frames = capture.robot_session(capture.packed([data[37:]], 1), handshake=False)
    path = capture.write(tmp_path / "mid.pcap", frames)
    out = records(urwire("decode", str(path)))
    assert out[0]["type"] == "error"
    assert [r["type"] for r in out[1:]] == [r["type"] for r in records(urwire("decode", "-", stdin=data))][1:]


def test_text_format_names_enums():
    (case,) = [c for c in all_cases() if c.name.endswith("robot_state_real_robot_5.11_pr137")]
    text = urwire("decode", "--format", "text", "-", stdin=case.data).stdout.decode()
    assert "Robot mode data (Robot mode: RUNNING)" in text and "Masterboard data (Safety mode: NORMAL)" in text
    assert len(text.splitlines()) == 1


def test_text_views_read_as_labels_with_units():
    """The text and tree views use the spec's labels and units, never its snake_case names."""
    (case,) = [c for c in all_cases() if c.name.endswith("robot_state_real_robot_5.11_pr137")]
    tree = urwire("decode", "--format", "tree", "-", stdin=case.data).stdout.decode()
    lines = tree.splitlines()
    assert lines[0] == "Robot state [14 packages]"
    joint = lines.index("    Joint 0")
    assert lines[joint + 1].startswith("      Actual joint position: ") and lines[joint + 1].endswith(" rad")
    assert "      Motor temperature: 29.625 °C" in lines
    assert "    Tool output voltage: 24 V" in lines
    labels = [ln.split(":")[0].strip() for ln in lines if ":" in ln]
    assert labels and not [label for label in labels if "_" in label]
    version = [c for c in all_cases() if c.name == "version_message"][0]
    text = urwire("decode", "--format", "text", "-", stdin=version.data).stdout.decode()
    assert text.startswith("Version ") and "Project name: " in text and "project_name" not in text


def test_output_to_a_closed_pipe_is_quiet(tmp_path):
    path = tmp_path / "big.bin"
    path.write_bytes(b"".join(c.data for c in GOOD) * 200)
    proc = subprocess.run(f"{sys.executable} -m urwire decode {path} | head -n 1", shell=True, env=ENV,
                          capture_output=True)
    assert b"Traceback" not in proc.stderr and len(proc.stdout.splitlines()) == 1


def test_a_large_file_shows_a_progress_bar_on_a_terminal(tmp_path):
    import fcntl
    import pty
    import termios

    path = tmp_path / "large.bin"
    path.write_bytes(b"".join(c.data for c in GOOD) * 3000)  # about 9.5 MB: above the 8 MiB threshold
    controller, terminal = pty.openpty()
    # A terminal of 24 x 100: a fresh pty has no size, and a bar needs a width.
    fcntl.ioctl(terminal, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))
    proc = subprocess.Popen([sys.executable, "-m", "urwire", "decode", str(path)], env=ENV,
                            stdout=subprocess.DEVNULL, stderr=terminal)
    os.close(terminal)
    shown = b""
    while True:
        try:
            chunk = os.read(controller, 4096)
        except OSError:
            break
        if not chunk:
            break
        shown += chunk
    assert proc.wait() == 0
    assert b"decoding" in shown and b"%" in shown


def test_no_progress_bar_when_stderr_is_not_a_terminal(tmp_path):
    path = tmp_path / "large.bin"
    path.write_bytes(b"".join(c.data for c in GOOD) * 3000)
    result = subprocess.run([sys.executable, "-m", "urwire", "decode", str(path)], env=ENV,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    assert result.returncode == 0 and result.stderr == b""


@pytest.mark.parametrize("port", ["-1", "65536", "99999", "30o01"])
def test_decode_refuses_a_port_no_tcp_conversation_has(port):
    """A capture's TCP ports are 0 to 65535: any other --port could only ever match nothing."""
    res = subprocess.run([sys.executable, "-m", "urwire", "decode", "--port", port, "-"], input=b"",
                         capture_output=True, env=ENV, timeout=60)
    assert res.returncode == 2
    assert b"--port" in res.stderr and b"Traceback" not in res.stderr
