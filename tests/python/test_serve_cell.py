"""`urwire serve` on every interface of the cell, over real TCP on loopback: RTDE (protocol 1 and
2, the controller version, setups answered with types, NOT_FOUND by software version and IN_USE
for a held input, start and pause, data packages at the asked frequency with the motion's values,
inputs that change what the robot reports), the real-time interface (the served version's layout
at the generation's rate, the motion's joints) and the dashboard server (the banner, the replies'
texts by version, play, stop and pause changing the program state every interface reports).

Each client here is urwire's own decoder for the interface; the values are checked against
urwire.live.motion.Motion, the one motion every interface samples, worked out apart from the server."""
from __future__ import annotations

import math
import socket
import subprocess
import sys
import time

import pytest

from tests.python.cell_server import ENV, CellServer, RtdeClient, read_until
from urwire import rtde
from urwire.generated import rtde as g
from urwire.generated import ur_dashboard
from urwire.live.motion import Motion
from urwire.realtime import RealtimeFramer
from urwire.live.robot_models import model_for
from urwire.framer import Framer
import urwire

BUILD = 108318


@pytest.fixture
def server(tmp_path, request):
    software = getattr(request, "param", "5.11")
    with CellServer(tmp_path, "--software", software) as running:
        yield running
        assert running.stop() == 0


def test_every_interface_listens_on_its_offset_from_the_primary_port(tmp_path):
    # A base whose offsets are free now (another process may take one before serve does: try again).
    for _ in range(3):
        base = free_port_with_offsets()
        try:
            server = CellServer(tmp_path, "--software", "5.11", port=base)
        except AssertionError:
            continue
        with server:
            gripper = server.ports.pop("gripper")          # the URCap's 63352 only with the default --port
            assert server.ports == {"primary": base, "rtde": base + 3, "realtime": base + 2, "dashboard": base - 2,
                                    "interpreter": base + 19}
            assert gripper not in (0, 63352)
            assert server.stop() == 0
        return
    pytest.fail("no base port whose offsets serve could take")


def free_port_with_offsets() -> int:
    while True:
        with socket.create_server(("127.0.0.1", 0)) as probe:
            base = probe.getsockname()[1]
        if base < 1024 or base > 65516:
            continue
        try:
            for port in (base - 2, base + 2, base + 3, base + 19):
                with socket.create_server(("127.0.0.1", port)):
                    pass
        except OSError:
            continue
        return base


def test_a_port_taken_is_said_and_serve_exits_2(tmp_path):
    with socket.create_server(("127.0.0.1", 0)) as taken:
        port = taken.getsockname()[1]
        res = subprocess.run([sys.executable, "-m", "urwire", "serve", "--port", "0", "--rtde-port", str(port),
                              "--duration", "5"], capture_output=True, text=True, env=ENV, timeout=30)
    assert res.returncode == 2
    assert f"cannot listen on 127.0.0.1: RTDE port {port}: Address already in use" in res.stderr


def test_rtde_protocol_2_setup_start_stream_pause(server):
    client = RtdeClient(server)
    assert client.ask(rtde.request_protocol_version(2), g.RequestProtocolVersionReply).accepted
    version = client.ask(rtde.get_controller_version(), g.GetUrcontrolVersionReply)
    assert (version.major, version.minor, version.bugfix, version.build) == (5, 11, 0, BUILD)
    refused = client.ask(rtde.setup_outputs(["timestamp", "no_such_variable"], 125.0), g.SetupOutputsReply)
    assert refused.recipe_id == 0 and refused.types == ["DOUBLE", "NOT_FOUND"]
    names = ["timestamp", "actual_q", "actual_qd", "actual_TCP_pose", "robot_mode", "runtime_state", "safety_mode"]
    reply = client.ask(rtde.setup_outputs(names, 125.0), g.SetupOutputsReply)
    assert reply.recipe_id >= 1
    assert reply.types == ["DOUBLE", "VECTOR6D", "VECTOR6D", "VECTOR6D", "INT32", "UINT32", "INT32"]
    assert client.ask(rtde.start(), g.StartReply).accepted
    packages = client.packages(60)
    motion = Motion(model_for((5, 11, 0)))
    stamps = [p.values["timestamp"] for p in packages]
    # 125 Hz on the server's clock: each package 8 ms after the one before.
    assert all(abs(b - a - 1 / 125) < 1e-9 for a, b in zip(stamps, stamps[1:])), stamps[:5]
    for p in packages:
        assert p.recipe_id == reply.recipe_id
        sample = motion.joints(p.values["timestamp"])
        assert p.values["actual_q"] == list(sample.q)
        assert p.values["actual_qd"] == list(sample.qd)
        assert p.values["actual_TCP_pose"] == pytest.approx(list(motion.tcp_pose(sample.q)), abs=1e-12)
        assert (p.values["robot_mode"], p.values["runtime_state"], p.values["safety_mode"]) == (7, 2, 1)
    assert client.ask(rtde.pause(), g.PauseReply).accepted
    client.sock.settimeout(0.3)
    late = []
    try:
        while True:
            late += [r for r in client.conversation.feed(client.sock.recv(65536), True)
                     if type(r).__name__ == "DataPackage"]
    except TimeoutError:
        pass
    assert not late, "data packages after the pause reply"
    client.close()


@pytest.mark.parametrize("server", ["3.15"], indirect=True)
def test_rtde_protocol_1_on_cb3_at_most_125_hz(server):
    client = RtdeClient(server)
    version = client.ask(rtde.get_controller_version(), g.GetUrcontrolVersionReply)
    assert (version.major, version.minor) == (3, 15)
    reply = client.ask(rtde.setup_outputs(["timestamp", "actual_q"], protocol=1), g.SetupOutputsReplyV1)
    assert reply.types == ["DOUBLE", "VECTOR6D"]
    assert client.ask(rtde.start(), g.StartReply).accepted
    packages = client.packages(20)
    assert all(type(p) is g.DataPackageV1 for p in packages)
    motion = Motion(model_for((3, 15, 0)))
    assert all(p.values["actual_q"] == list(motion.joints(p.values["timestamp"]).q) for p in packages)
    client.close()
    # Protocol 2 at 125 Hz, a CB3's most; 500 Hz it refuses (recipe id 0: no recipe to start).
    client = RtdeClient(server)
    client.ask(rtde.request_protocol_version(2), g.RequestProtocolVersionReply)
    assert client.ask(rtde.setup_outputs(["timestamp"], 500.0), g.SetupOutputsReply).recipe_id == 0
    assert client.ask(rtde.setup_outputs(["timestamp"], 125.0), g.SetupOutputsReply).recipe_id == 1
    client.ask(rtde.start(), g.StartReply)
    stamps = [p.values["timestamp"] for p in client.packages(10)]
    assert all(abs(b - a - 1 / 125) < 1e-9 for a, b in zip(stamps, stamps[1:]))
    client.close()


@pytest.mark.parametrize("server", ["5.3"], indirect=True)
def test_rtde_not_found_for_a_variable_the_version_lacks(server):
    # safety_status came with 5.4 (RTDE guide); output_bit_register_64 with 5.3.
    client = RtdeClient(server)
    client.ask(rtde.request_protocol_version(2), g.RequestProtocolVersionReply)
    reply = client.ask(rtde.setup_outputs(["safety_status", "output_bit_register_64"], 125.0), g.SetupOutputsReply)
    assert reply.recipe_id == 0 and reply.types == ["NOT_FOUND", "BOOL"]
    client.close()


def test_rtde_inputs_in_use_and_what_they_change(server):
    first, second = RtdeClient(server), RtdeClient(server)
    for client in (first, second):
        client.ask(rtde.request_protocol_version(2), g.RequestProtocolVersionReply)
    names = ["speed_slider_mask", "speed_slider_fraction", "standard_digital_output_mask", "standard_digital_output"]
    held = first.ask(rtde.setup_inputs(names), g.SetupInputsReply)
    assert held.recipe_id >= 1 and held.types == ["UINT32", "DOUBLE", "UINT8", "UINT8"]
    refused = second.ask(rtde.setup_inputs(["standard_digital_output_mask", "standard_digital_output"]),
                         g.SetupInputsReply)
    assert refused.recipe_id == 0 and refused.types == ["IN_USE", "IN_USE"]
    recipe = first.conversation.recipes["inputs"][held.recipe_id]
    first.send(rtde.input_data(recipe, {"speed_slider_mask": 1, "speed_slider_fraction": 0.4,
                                        "standard_digital_output_mask": 0b101, "standard_digital_output": 0b111}))
    first.ask(rtde.get_controller_version(), g.GetUrcontrolVersionReply)        # the input is taken by now
    second.ask(rtde.setup_outputs(["target_speed_fraction", "actual_digital_output_bits", "speed_scaling"], 125.0),
               g.SetupOutputsReply)
    second.ask(rtde.start(), g.StartReply)
    values = second.packages(3)[-1].values
    assert values == {"target_speed_fraction": 0.4, "actual_digital_output_bits": 0b101, "speed_scaling": 0.4}
    first.close()
    time.sleep(0.3)
    # The holder gone, its inputs are free again.
    third = RtdeClient(server)
    third.ask(rtde.request_protocol_version(2), g.RequestProtocolVersionReply)
    assert third.ask(rtde.setup_inputs(["standard_digital_output"]), g.SetupInputsReply).recipe_id >= 1
    second.close()
    third.close()


def test_rtde_a_speed_slider_fraction_off_the_slider_is_not_taken(server):
    client = RtdeClient(server)
    client.ask(rtde.request_protocol_version(2), g.RequestProtocolVersionReply)
    held = client.ask(rtde.setup_inputs(["speed_slider_mask", "speed_slider_fraction"]), g.SetupInputsReply)
    recipe = client.conversation.recipes["inputs"][held.recipe_id]
    for fraction in (0.25, math.nan, math.inf, -0.5, 1.5):
        client.send(rtde.input_data(recipe, {"speed_slider_mask": 1, "speed_slider_fraction": fraction}))
    client.ask(rtde.setup_outputs(["target_speed_fraction"], 125.0), g.SetupOutputsReply)
    client.ask(rtde.start(), g.StartReply)
    assert client.packages(2)[-1].values == {"target_speed_fraction": 0.25}
    client.close()


@pytest.mark.parametrize("server,size,rate", [("5.11", 1220, 500), ("3.15", 1116, 125), ("1.8", 812, 125)],
                         indirect=["server"])
def test_realtime_layout_and_rate_of_the_version(server, size, rate):
    version = tuple(int(p) for p in server.proc.args[server.proc.args.index("--software") + 1].split(".")) + (0,)
    framer = RealtimeFramer(version)
    with server.connect("realtime") as sock:
        packets = read_until(sock, framer.feed, lambda r: len(r) >= 50)
    assert len(packets) >= 50 and all(p.message_size == size for p in packets)
    times = [p.time for p in packets]
    assert all(abs(b - a - 1 / rate) < 1e-9 for a, b in zip(times, times[1:]))
    motion = Motion(model_for(version))
    for p in packets:
        assert list(p.q_actual) == list(motion.joints(p.time).q)
        assert list(p.tool_vector_actual) == pytest.approx(list(motion.tcp_pose(p.q_actual)), abs=1e-12)


def dashboard_exchange(server: CellServer, lines: list) -> list:
    """The banner and a reply for each line, decoded by urwire's dashboard conversation."""
    conversation = ur_dashboard.conversation()
    with server.connect("dashboard") as sock:
        sock.sendall("".join(line + "\n" for line in lines).encode())
        conversation.feed("".join(line + "\n" for line in lines).encode(), False)
        replies = read_until(sock, lambda chunk: conversation.feed(chunk, True), lambda r: len(r) > len(lines))
    assert len(replies) == len(lines) + 1, replies
    return replies


@pytest.mark.parametrize("server", ["5.11"], indirect=True)
def test_dashboard_replies_and_the_program_state_every_interface_reports(server):
    model = model_for((5, 11, 0))
    replies = dashboard_exchange(server, ["PolyscopeVersion", "programState", "robotmode", "get serial number",
                                          "get robot model", "no such command", "stop", "programState",
                                          "running", "play", "programState", "pause", "programState"])
    texts = [r.reply for r in replies]
    assert texts[0] == "Connected: Universal Robots Dashboard Server"
    assert texts[1] == f"URSoftware 5.11.0.{BUILD} (Nov 26 2021)"
    assert texts[2:6] == ["PLAYING demo.urp", "Robotmode: RUNNING", texts[4], "UR5"]
    assert texts[4].isdigit() and len(texts[4]) == 11
    assert texts[6] == "could not understand: 'no such command'"
    assert texts[7:] == ["Stopped", "STOPPED demo.urp", "Program running: false", "Starting program",
                         "PLAYING demo.urp", "Pausing program", "PAUSED demo.urp"]
    assert [r.reply_name for r in replies[7:]] == ["stopped", "stopped", "program_running", "starting_program",
                                                   "playing", "pausing_program", "paused"]
    assert not any(r.error for r in replies if r.reply_name != "not_understood")
    assert model.name == "ur5e"
    # Paused: the arm holds still, and every interface says so with the same joints.
    time.sleep(0.2)
    framer = RealtimeFramer((5, 11, 0))
    with server.connect("realtime") as sock:
        packets = read_until(sock, framer.feed, lambda r: len(r) >= 5)
    assert {p.program_state for p in packets} == {4.0} and {p.speed_scaling for p in packets} == {0.0}
    assert len({p.q_actual for p in packets}) == 1 and set(packets[0].qd_actual) == {0.0}
    primary = Framer()
    with server.connect("primary") as sock:
        states = read_until(sock, primary.feed,
                            lambda r: sum(isinstance(x, urwire.RobotStateMessage) for x in r) >= 2)
    state = [r for r in states if isinstance(r, urwire.RobotStateMessage)][-1]
    mode = state.package(urwire.RobotModeData)
    assert (mode.is_program_running, mode.is_program_paused) == (False, True)
    assert [j.q_actual for j in state.package(urwire.JointData).joints] == list(packets[0].q_actual)
    client = RtdeClient(server)
    client.ask(rtde.request_protocol_version(2), g.RequestProtocolVersionReply)
    client.ask(rtde.setup_outputs(["actual_q", "runtime_state"], 125.0), g.SetupOutputsReply)
    client.ask(rtde.start(), g.StartReply)
    values = client.packages(2)[-1].values
    assert values == {"actual_q": list(packets[0].q_actual), "runtime_state": 4}
    client.close()


def test_the_primary_stream_says_when_the_dashboard_stops_and_plays_the_program(server):
    primary = Framer()
    keys = lambda records: [r.title for r in records if isinstance(r, urwire.KeyMessage)]   # noqa: E731
    with server.connect("primary") as sock:
        read_until(sock, primary.feed, lambda r: any(isinstance(x, urwire.RobotStateMessage) for x in r))
        replies = dashboard_exchange(server, ["stop"])
        assert replies[1].reply == "Stopped"
        stopped = read_until(sock, primary.feed, lambda r: "PROGRAM_XXX_STOPPED" in keys(r))
        assert "PROGRAM_XXX_STOPPED" in keys(stopped)
        key = [r for r in stopped if isinstance(r, urwire.KeyMessage)][-1]
        assert key.text == "demo"
        states = read_until(sock, primary.feed,
                            lambda r: sum(isinstance(x, urwire.RobotStateMessage) for x in r) >= 2)
        state = [r for r in states if isinstance(r, urwire.RobotStateMessage)][-1]
        assert state.package(urwire.RobotModeData).is_program_running is False
        assert not keys(states)              # a stopped program says nothing more
        dashboard_exchange(server, ["play"])
        started = read_until(sock, primary.feed, lambda r: "PROGRAM_XXX_STARTED" in keys(r))
        assert "PROGRAM_XXX_STARTED" in keys(started)


@pytest.mark.parametrize("server", ["3.15"], indirect=True)
def test_dashboard_commands_of_the_version_only(server):
    # safetystatus is e-Series only (5.4); get serial number came with 3.12 on CB3.
    replies = dashboard_exchange(server, ["safetystatus", "get serial number", "PolyscopeVersion", "power off",
                                          "robotmode", "play", "power on", "brake release", "robotmode", "quit"])
    texts = [r.reply for r in replies[1:]]
    assert texts[0] == "could not understand: 'safetystatus'"
    assert texts[1].isdigit()
    assert texts[2].startswith("URSoftware 3.15.0.")
    assert texts[3:] == ["Powering off", "Robotmode: POWER_OFF", "Failed to execute: play", "Powering on",
                         "Brake releasing", "Robotmode: RUNNING", "Disconnected"]
    assert replies[6].error


def test_serve_without_rtde_before_3_3(tmp_path):
    with CellServer(tmp_path, "--software", "1.8") as running:
        assert set(running.ports) == {"primary", "realtime", "dashboard"}
        assert running.stop() == 0


