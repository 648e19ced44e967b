"""`urwire serve`'s dashboard server follows the dashboard spec: every command of the spec gets,
over a real TCP connection, one of the replies its spec lists on each served software version
that has it, and the real robot's unknown-command reply on one that lacks it; a command added
to a copy of the spec, with the Python generated from that copy, is answered without code."""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

from codegen.kinds.lines import model
from tests.python.cell_server import CellServer, generated_from_edited_spec, read_until
from urwire.generated import ur_dashboard
from urwire.live import serve_dashboard, serve_gripper, serve_interpreter

# A CB3, an e-Series and a PolyScope X controller.
SERVED = ["3.15", "5.11", "10.7"]
ARGUMENT = "/programs/probe.urp"


def command_line(command) -> str:
    return f"{command.text} {ARGUMENT}" if command.takes_argument else command.text


def exchange(server: CellServer, tables, version: str, lines: list) -> list:
    """The replies to `lines` after the banner, decoded by the spec's own dashboard conversation."""
    conversation = tables.conversation(version)
    data = "".join(line + "\n" for line in lines).encode()
    conversation.feed(data, False)
    with server.connect("dashboard") as sock:
        sock.sendall(data)
        replies = read_until(sock, lambda chunk: conversation.feed(chunk, True), lambda r: len(r) > len(lines))
    assert len(replies) == len(lines) + 1, replies
    assert replies[0].reply_name == "connected"
    return replies[1:]


def in_order(commands) -> list:
    """Every command, `quit` (which closes the connection) last."""
    return sorted(commands, key=lambda c: c.effect == "close_connection")


@pytest.mark.parametrize("software", SERVED)
def test_every_command_of_the_spec_gets_one_of_its_replies_or_is_not_understood(tmp_path, software):
    version = tuple(int(p) for p in software.split(".")) + (0,)
    commands = in_order(ur_dashboard.COMMANDS)
    with CellServer(tmp_path, "--software", software) as server:
        replies = exchange(server, ur_dashboard, software, [command_line(c) for c in commands])
        assert server.stop() == 0
    lacking = []
    for command, reply in zip(commands, replies):
        assert reply.command_name == command.name and reply.error is not None
        if command.available(version):
            assert reply.reply_name in {r.name for r in command.replies}, (command.name, reply.reply)
        else:
            assert reply.reply == f"could not understand: '{command_line(command)}'" and reply.error is True
            lacking.append(command.name)
    # Each series lacks some: CB3 the e-Series' commands, the e-Series and PolyScope X the CB3 ones.
    assert ("safetystatus" in lacking) == (version[0] < 5) and ("get_user_role" in lacking) == (version[0] >= 5)


def test_the_vocabulary_the_spec_may_name_is_what_serve_does():
    served = (serve_dashboard, serve_interpreter, serve_gripper)
    assert set().union(*(m._EFFECTS for m in served)) == set(model.EFFECTS)
    assert set().union(*(getattr(m, "_STATES", {}) for m in served)) | {"argument"} == set(model.ROBOT_STATES)


MADE_UP = """
  - name: get_tcp_speed_scaling
    text: get tcp speed scaling
    since: {cb: "3.15", e_series: "5.11", polyscope_x: "10.7"}
    doc: A command no controller has, in the spec only; no key says what the simulated robot answers.
    replies:
      - {name: failed, pattern: "Failed: <reason>", error: true}
      - {name: scaling, pattern: "TCP speed scaling: <fraction>"}
  - name: halt_and_tell
    text: halt and tell
    argument: why
    effect: pause
    since: {e_series: "5.11", polyscope_x: none}
    doc: A made-up command that pauses the program and says the program's state.
    replies:
      - {name: halted, pattern: "Halted (<state>)", fill: "{program_state}, {argument}"}
      - {name: refused, pattern: "Cannot halt: <why>", error: true}
"""


@pytest.fixture(scope="module")
def made_up(tmp_path_factory):
    """serve's environment with the made-up commands in its dashboard spec, and the generated
    module of that spec, loaded as a module of urwire.generated so that the client decodes with it."""
    env = generated_from_edited_spec(tmp_path_factory.mktemp("made_up"), "ur_dashboard.yaml", lambda t: t + MADE_UP)
    found = importlib.util.spec_from_file_location("urwire.generated.made_up_dashboard",
                                                   Path(env["GENERATED"]) / "ur_dashboard.py")
    tables = importlib.util.module_from_spec(found)
    sys.modules[found.name] = tables            # its conversation() finds its tables there
    found.loader.exec_module(tables)
    yield env, tables
    del sys.modules[found.name]


def test_a_command_added_to_the_spec_is_answered_without_code(tmp_path, made_up):
    env, tables = made_up
    assert {"get_tcp_speed_scaling", "halt_and_tell"} <= {c.name for c in tables.COMMANDS}
    lines = ["get tcp speed scaling", "halt and tell a visitor", "programState", "halt and tell again", "robotmode"]
    replies = {}
    for software in ("5.11", "3.15"):
        with CellServer(tmp_path, "--software", software, env=env) as server:
            replies[software] = exchange(server, tables, software, lines)
            assert server.stop() == 0
    assert [r.reply for r in replies["5.11"]] == ["TCP speed scaling: ", "Halted (PAUSED, a visitor)",
                                                  "PAUSED demo.urp", "Cannot halt: again", "Robotmode: RUNNING"]
    assert [r.reply_name for r in replies["5.11"]] == ["scaling", "halted", "paused", "refused", "robotmode"]
    # 3.15 has the first only: the second is a command of a later e-Series version.
    assert [r.reply_name for r in replies["3.15"]] == ["scaling", "not_understood", "playing", "not_understood",
                                                       "robotmode"]
