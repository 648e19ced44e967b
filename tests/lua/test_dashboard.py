"""The dashboard dissector (generated/lua/ur_dashboard.lua) in real tshark, loaded on its own: the
golden vectors in whole and one-byte segments against their expected records, expert infos,
filters, Decode As, state per conversation, and its runtime alone under Lua 5.2-5.4."""
from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from tests.interface_vectors import Segment, bytewise, conversation_cases
from tests.lua.harness import TsharkError, run_tshark
from tests.tools import capture

ROOT = Path(__file__).resolve().parents[2]
PLUGIN = ROOT / "generated" / "lua" / "ur_dashboard.lua"
CASES = conversation_cases("ur_dashboard")
P = "ur_dashboard."


def _lists(pairs: list) -> dict:
    """A JSON object whose repeated keys (several lines in one frame) become lists."""
    out: dict = {}
    for key, value in pairs:
        out.setdefault(key, []).append(value)
    return {k: v[0] if len(v) == 1 else v for k, v in out.items()}


def _items(layer) -> list[dict]:
    return layer if isinstance(layer, list) else [layer]


def _bool(text: str) -> bool:
    return text in ("1", "True", "true")


def tcp_segments(segments) -> list[capture.Segment]:
    return [capture.Segment(s.from_robot, s.data) for s in segments]


def tshark_text(pcap: Path, *args: str, plugin: Path = PLUGIN) -> str:
    """tshark's output with the dissector, its bytes read as UTF-8 with U+FFFD for the invalid
    ones (a line's text is shown as it came); fails on any Lua error."""
    result = subprocess.run(["tshark", "-r", str(pcap), "-X", f"lua_script:{plugin}", *args],
                            capture_output=True, timeout=600)
    out, err = result.stdout.decode("utf-8", "replace"), result.stderr.decode("utf-8", "replace")
    if result.returncode != 0 or "Lua: Error" in err + out or "_ws.lua.error" in out or "internal_error" in out:
        raise TsharkError(f"tshark failed: {err[:2000]} {out[:2000]}")
    return out


def to_record(item: dict, P: str = P) -> dict:
    """A tree item of one line -> its canonical record (errors: their type only)."""
    if P + "command" in item:
        rec = {"type": "command", "command": item[P + "command"]}
        for key in ("command_name", "argument"):
            if P + key in item:
                rec[key] = item[P + key]
        if P + "available" in item:
            rec["available"] = _bool(item[P + "available"])
        return rec
    if P + "reply" in item:
        rec = {"type": "reply", "reply": item[P + "reply"]}
        for key in ("command_name", "reply_name"):
            if P + key in item:
                rec[key] = item[P + key]
        rec["error"] = _bool(item[P + "error"])
        return rec
    return {"type": "error"}


def dissect(tmp_path: Path, segments, *args: str, port: int = 29999, sessions=None) -> list[dict]:
    frames = []
    for i, session in enumerate(sessions or [segments]):
        frames += capture.session_frames(tcp_segments(session), port=port, client_port=50123 + i)
    pcap = capture.write(tmp_path / "dashboard.pcap", frames)
    text = tshark_text(pcap, "-2", "-T", "json", *args)
    records = []
    for frame in json.loads(text or "[]", object_pairs_hook=_lists):
        layer = frame["_source"]["layers"].get("ur_dashboard")
        if layer is not None:
            records += [to_record(item) for item in _items(layer)]
    return records


def lua_expectation(expect: list[dict]) -> list[dict]:
    """What tshark can show: a line cut by the end of the capture waits for its newline, and a
    fault shows as an expert, without the offset of the JSON record."""
    return [{"type": "error"} if r["type"] == "error" else r for r in expect
            if not (r["type"] == "error" and "without a newline" in r["error"])]


def preference(version) -> tuple[str, ...]:
    return ("-o", f"ur_dashboard.version:{version}") if version else ()


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_golden_vectors(tmp_path, case):
    assert dissect(tmp_path, case.segments, *preference(case.version)) == lua_expectation(case.expect)


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_golden_vectors_in_one_byte_segments(tmp_path, case):
    assert dissect(tmp_path, bytewise(case.segments), *preference(case.version)) == lua_expectation(case.expect)


def conversation(*lines: tuple[bool, bytes]) -> list:
    return [Segment(from_robot, data) for from_robot, data in lines]


def test_expert_infos_flag_error_replies_unknown_and_unavailable_commands_and_long_lines(tmp_path):
    segments = conversation((True, b"Connected: Universal Robots Dashboard Server\n"),
                            (False, b"hello\nplay\nsafetystatus\n"),
                            (True, b"could not understand: 'hello'\nFailed to execute: play\n"),
                            (False, b"x" * 5000 + b"\nstop\n"))
    pcap = capture.write(tmp_path / "experts.pcap", capture.session_frames(tcp_segments(segments), port=29999))
    text = run_tshark(pcap, "-2", "-o", "ur_dashboard.version:3.15", "-T", "fields", "-e", "_ws.expert.message",
                      "-Y", "_ws.expert", plugin=PLUGIN)
    messages = ",".join(text.split())
    for expected in ("Unknown command", "The software version lacks this command", "The reply says an error",
                     "Line longer than 4096 bytes"):
        assert expected.replace(" ", ",") in messages, (expected, text)


def test_past_the_kept_commands_a_reply_pairs_with_nothing_and_an_expert_says_why(tmp_path):
    segments = conversation((False, b"robotmode\n" * 256 + b"play\nrobotmode\n"),
                            (True, b"Robotmode: IDLE\n" * 256 + b"Starting program\nRobotmode: IDLE\n"),
                            (False, b"stop\n"), (True, b"Stopped\n"))
    records = dissect(tmp_path, segments)
    replies = [r for r in records if r["type"] == "reply"]
    assert all(r.get("command_name") == "robotmode" for r in replies[:256])
    assert [r.get("command_name") for r in replies[256:]] == [None, None, "stop"]
    pcap = capture.write(tmp_path / "kept.pcap", capture.session_frames(tcp_segments(segments), port=29999))
    text = run_tshark(pcap, "-2", "-T", "fields", "-e", "_ws.expert.message", "-Y", "_ws.expert", plugin=PLUGIN)
    messages = text.replace(",", "\n").split("\n")
    assert messages.count("Command not kept: more than 256 commands awaited replies") == 2
    assert messages.count("Reply to a command that was not kept: more than 256 commands awaited replies") == 2


def test_a_line_too_long_still_takes_its_place_in_the_pairing(tmp_path):
    segments = conversation((True, b"Connected: Universal Robots Dashboard Server\n"),
                            (False, b"popup " + b"x" * 5000 + b"\nplay\n"),
                            (True, b"could not understand: 'line longer than 4096 bytes'\nStarting program\n"),
                            (False, b"robotmode\nstop\n"), (True, b"Robotmode: " + b"y" * 5000 + b"\nStopped\n"))
    replies = [r for r in dissect(tmp_path, segments) if r["type"] == "reply"]
    assert [r.get("command_name") for r in replies] == [None, None, "play", "stop"]


def test_filters_name_the_banner_a_reply_and_error_replies(tmp_path):
    segments = conversation((True, b"Connected: Universal Robots Dashboard Server\n"), (False, b"play\n"),
                            (True, b"Failed to execute: play\n"))
    pcap = capture.write(tmp_path / "filters.pcap", capture.session_frames(tcp_segments(segments), port=29999))
    replies = run_tshark(pcap, "-2", "-Y", "ur_dashboard.reply", "-T", "fields", "-e", "ur_dashboard.reply",
                         plugin=PLUGIN).splitlines()
    assert replies == ["Connected: Universal Robots Dashboard Server", "Failed to execute: play"]
    errors = run_tshark(pcap, "-2", "-Y", "ur_dashboard.error == 1 && ur_dashboard.command_name == \"play\"",
                        "-T", "fields", "-e", "ur_dashboard.reply_name", plugin=PLUGIN).splitlines()
    assert errors == ["failed"]


def test_decode_as_on_another_port(tmp_path):
    segments = conversation((False, b"play\n"), (True, b"Starting program\n"))
    records = dissect(tmp_path, segments, "-d", "tcp.port==40000,ur_dashboard", port=40000)
    assert records == [{"type": "command", "command": "play", "command_name": "play"},
                       {"type": "reply", "reply": "Starting program", "command_name": "play",
                        "reply_name": "starting_program", "error": False}]


def test_two_clients_in_one_capture_keep_their_own_version_and_pending_commands(tmp_path):
    first = conversation((False, b"PolyscopeVersion\n"), (True, b"URSoftware 3.15.7.1 (x)\n"),
                         (False, b"safetystatus\n"))
    second = conversation((False, b"play\n"), (True, b"Starting program\n"), (False, b"safetystatus\n"))
    records = dissect(tmp_path, None, sessions=[first, second])
    commands = [r for r in records if r.get("command") == "safetystatus"]
    assert commands == [{"type": "command", "command": "safetystatus", "command_name": "safetystatus",
                         "available": False},
                        {"type": "command", "command": "safetystatus", "command_name": "safetystatus"}]
    assert {"type": "reply", "reply": "Starting program", "command_name": "play", "reply_name": "starting_program",
            "error": False} in records


def test_binary_junk_and_long_lines_never_raise_a_lua_error(tmp_path):
    junk = bytes(range(256)) * 40
    segments = conversation((True, junk), (False, junk), (True, b"\n" * 3), (False, b"\r\n" + b"p" * 9000))
    dissect(tmp_path, segments)            # run_tshark fails on any Lua error
    # One byte per segment: a few lines' worth is enough to cross every state of the line reassembly.
    dissect(tmp_path, bytewise(tuple(conversation((True, junk[:1024]), (False, junk[:1024])))))


def test_no_global_is_assigned():
    listing = subprocess.run(["luac5.2", "-l", "-p", str(PLUGIN)], capture_output=True, text=True, check=True).stdout
    assert [line for line in listing.splitlines() if "SETTABUP" in line and "_ENV" in line] == []


MATCH_TEST = r"""
local spec = {lookup = {2, 1}, version_prefix = "URSoftware ", e_series_from = 5000000, polyscope_x_from = 10000000,
    common = {{name = "no", pieces = {"could not understand: '", "'"}, error = true}},
    commands = {{name = "load", text = "load", argument = true, since_cb = 1004000, since_e_series = 5000000,
                 replies = {{name = "loading", pieces = {"Loading program: ", ""}, error = false}}},
                {name = "load_installation", text = "load installation", argument = true, since_cb = 3002000,
                 replies = {}}}}
local rt = {}
assert(loadfile(arg[1]))(spec, rt)
assert(rt.find_command("load installation x") == 2 and select(2, rt.find_command("load a b")) == "a b")
assert(rt.find_command("loadx") == nil and rt.find_command("load") == 1)
assert(rt.classify(1, "Loading program: p").name == "loading" and rt.classify(nil, "could not understand: 'x'").error)
assert(rt.classify(nil, "Loading program: p") == nil)
assert(rt.matches({"a", "b", "c"}, "a-b-c") and not rt.matches({"ab", "b"}, "ab"))
assert(rt.version_in("URSoftware 5.11.1.108318 (Nov 26 2021)") == 5011001)
assert(rt.version_in("URSoftware 5.11") == 5011000 and rt.version_in("URSoftware 5.11.") == nil)
assert(rt.version_in("URSoftware 5.1x") == nil and rt.version_in("URSoftware 1234.1") == nil)
assert(rt.available(2, 3002000) and not rt.available(2, 5011000) and not rt.available(1, 1003000))
-- as Python's decode("utf-8", "replace"): one U+FFFD per maximal ill-formed part; a NUL ends the text
local R = "\239\191\189"
assert(rt.shown("caf\233 \255") == "caf" .. R .. " " .. R and rt.shown("a\226\130b") == "a" .. R .. "b")
assert(rt.shown("\240\159\152\128") == "\240\159\152\128" and rt.shown("\237\160\128") == R .. R .. R)
assert(rt.shown("\192\175") == R .. R and rt.shown("x\0y") == "x" and rt.shown("plain") == "plain")
print("ok")
"""


@pytest.mark.parametrize("lua", ["lua5.2", "lua5.3", "lua5.4"])
def test_the_match_runtime_alone(tmp_path, lua):
    if shutil.which(lua) is None:
        pytest.fail(f"{lua} is not installed (scripts/setup.sh installs it)")
    script = tmp_path / "match_test.lua"
    script.write_text(MATCH_TEST)
    result = subprocess.run([lua, str(script), str(ROOT / "runtime" / "lua" / "lines" / "match.lua")],
                            capture_output=True, text=True)
    assert result.stdout == "ok\n", result.stderr


SENDER = ROOT / "generated" / "lua" / "ur_script_sender.lua"


@pytest.mark.parametrize("case", conversation_cases("ur_script_sender"), ids=lambda c: c.name)
def test_the_script_sender_golden_vectors_whole_and_in_one_byte_segments(tmp_path, case):
    for segments in (case.segments, bytewise(case.segments)):
        # The control PC listens on 50002 and the robot connects: in the capture writer's terms
        # (the side on the port sends "from_robot") the directions are swapped.
        frames = capture.session_frames([capture.Segment(not s.from_robot, s.data) for s in segments], port=50002)
        pcap = capture.write(tmp_path / "sender.pcap", frames)
        shown = []
        for frame in json.loads(tshark_text(pcap, "-2", "-T", "json", plugin=SENDER) or "[]", object_pairs_hook=_lists):
            layer = frame["_source"]["layers"].get("ur_script_sender")
            if layer is not None:
                shown += [to_record(item, "ur_script_sender.") for item in _items(layer)]
        assert shown == lua_expectation(case.expect)
