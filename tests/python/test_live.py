"""The live tools over real TCP on loopback: `serve` for three controller generations, `listen`
recording it, a dumpcap capture of the session dissected by the Wireshark plugin, `export`
read back with pyarrow and DuckDB, and `plot`. Every process is bounded by --count/--duration
and a timeout."""
from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import urwire

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
PLUGIN = ROOT / "generated" / "lua" / "urwire.lua"
GENERATIONS = {"1.8": (1, 8, 0), "3.15": (3, 15, 0), "5.11": (5, 11, 0)}
STATES = 25


def start_server(software: str, duration: float = 30) -> tuple[subprocess.Popen, int]:
    proc = subprocess.Popen([sys.executable, "-m", "urwire", "serve", "--port", "0", "--software", software,
                             "--rate", "50", "--duration", str(duration)],
                            stderr=subprocess.PIPE, text=True, env=ENV)
    line = proc.stderr.readline()
    match = re.search(r":(\d+)$", line.strip())
    assert match, f"serve said: {line!r}"
    return proc, int(match.group(1))


def stop(proc: subprocess.Popen) -> int:
    proc.send_signal(signal.SIGTERM)
    return proc.wait(timeout=10)


def listen(port: int, tmp: Path, count: int) -> tuple[subprocess.CompletedProcess, Path, Path]:
    out, raw = tmp / "records.jsonl", tmp / "session.raw"
    res = subprocess.run([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{port}", "--out", str(out),
                          "--raw", str(raw), "--count", str(count), "--duration", "20"],
                         capture_output=True, text=True, env=ENV, timeout=60)
    return res, out, raw


@pytest.mark.parametrize("software", sorted(GENERATIONS))
def test_serve_listen(software, tmp_path):
    server, port = start_server(software)
    try:
        res, out, raw = listen(port, tmp_path, STATES)
    finally:
        assert stop(server) == 0  # SIGTERM is a clean stop
    assert res.returncode == 0, res.stderr
    lines = [json.loads(line) for line in out.read_text().splitlines()]
    assert len(lines) == STATES
    first = lines[0]
    assert first["type"] == "version"
    assert (first["major_version"], first["minor_version"]) == GENERATIONS[software][:2]

    # The raw bytes read back through decode: no error, no unknown part, no extra bytes.
    records = list(urwire.decode_file(raw))
    assert records and all(not urwire.canonical.has_error(r) for r in records)
    states = [r for r in records if isinstance(r, urwire.RobotStateMessage)]
    for r in records:
        assert not getattr(r, "extra", b"")
        for p in getattr(r, "packages", []):
            assert type(p).__name__ not in ("UnknownPackage", "MalformedPackage") and not p.extra
    # Kinematics and configuration come once, in the first state.
    assert states[0].package(urwire.KinematicsInfo) and states[0].package(urwire.ConfigurationData)
    assert not any(s.package(urwire.ConfigurationData) for s in states[1:])
    # A real arm's kinematics and identity arrived (ur5 on 1.8 and 3.15, ur5e on 5.11).
    kinematics, configuration = states[0].package(urwire.KinematicsInfo), states[0].package(urwire.ConfigurationData)
    assert kinematics.dh_a[1] == -0.425 and all(kinematics.checksum) and configuration.robot_type == 1
    assert configuration.dh_d == kinematics.dh_d and configuration.masterboard_version > 0
    # The joints move, within their limits.
    q = [[j.q_actual for j in s.package(urwire.JointData).joints] for s in states]
    assert all(q[0][j] != q[-1][j] for j in range(6))
    assert all(-6.3 < x < 6.3 for row in q for x in row)


def test_program_loop_in_every_generation():
    """A run of the simulated program says everything the protocol can: the version's value
    types, key and text messages, a protective stop and its safety mode."""
    from urwire.live.simulated import Controller

    for version in GENERATIONS.values():
        sim = Controller(version, 10)
        data = sim.version_message() + b"".join(b for _ in range(300) for b in sim.step())
        records = list(urwire.decode_stream(data))
        kinds = [getattr(r, "TYPE", None) for r in records]
        assert not any(urwire.canonical.has_error(r) for r in records)
        for kind in ("key", "text", "global_variables_setup", "global_variables_update", "safety_mode"):
            assert kind in kinds, (version, kind)
        titles = {r.title for r in records if getattr(r, "TYPE", None) == "key"}
        assert titles == {"PROGRAM_XXX_STARTED", "PROGRAM_XXX_STOPPED"}
        stopped = [s for s in records if isinstance(s, urwire.RobotStateMessage)
                   and s.package(urwire.RobotModeData).is_protective_stopped]
        assert stopped


def test_several_clients(tmp_path):
    server, port = start_server("5.11")
    try:
        clients = [subprocess.Popen([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{port}", "--count", "10",
                                     "--duration", "20"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=ENV)
                   for _ in range(3)]
        outputs = [c.communicate(timeout=60)[0].decode().splitlines() for c in clients]
    finally:
        stop(server)
    assert [len(o) for o in outputs] == [10, 10, 10]
    assert all(json.loads(o[0])["type"] == "version" for o in outputs)


def test_listen_reconnects(tmp_path):
    """Nothing listens yet: listen says it retries, then records once the server is up."""
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    client = subprocess.Popen([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{port}", "--count", "3",
                               "--duration", "20"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV)
    first = client.stderr.readline().decode()
    assert "retrying" in first
    # Only the primary port is the one picked: the others take free ones, not --port's neighbours,
    # which another test running beside this one may hold (serve would then not start).
    server = subprocess.Popen([sys.executable, "-m", "urwire", "serve", "--port", str(port), "--rtde-port", "0",
                               "--realtime-port", "0", "--dashboard-port", "0", "--duration", "20"],
                              stderr=subprocess.DEVNULL, env=ENV)
    try:
        out, _ = client.communicate(timeout=40)
    finally:
        stop(server)
    assert client.returncode == 0
    assert len(out.decode().splitlines()) == 3


@pytest.mark.skipif(shutil.which("dumpcap") is None or shutil.which("tshark") is None,
                    reason="needs dumpcap and tshark (scripts/setup.sh installs them)")
@pytest.mark.parametrize("software", ["5.11", "10.14"])  # 10.14: the hardware info message too
def test_capture_on_loopback_dissects_cleanly(software, tmp_path):
    server, port = start_server(software)
    pcap = tmp_path / "live.pcapng"
    cap = subprocess.Popen(["dumpcap", "-q", "-i", "lo", "-f", f"tcp port {port}", "-w", str(pcap)],
                           stderr=subprocess.PIPE, text=True)
    try:
        # dumpcap says "Capturing on" once its filter is in place.
        assert "Capturing on" in cap.stderr.readline() + cap.stderr.readline()
        res, _, _ = listen(port, tmp_path, 60)
        assert res.returncode == 0, res.stderr
    finally:
        stop(server)
        time.sleep(1)  # dumpcap writes what the kernel still holds for it
        cap.send_signal(signal.SIGINT)
        cap.wait(timeout=10)
    tshark = ["tshark", "-r", str(pcap), "-X", f"lua_script:{PLUGIN}", "-d", f"tcp.port=={port},ur"]
    ur = subprocess.run([*tshark, "-Y", "ur"], capture_output=True, text=True, timeout=120)
    assert "Lua: Error" not in ur.stderr
    assert len(ur.stdout.splitlines()) > 10
    errors = subprocess.run([*tshark, "-Y", "_ws.expert.severity == 0x800000 || _ws.malformed"],
                            capture_output=True, text=True, timeout=120)
    assert errors.returncode == 0 and errors.stdout == ""
    # The Python decoder reads the same capture, with the same port, without error.
    records = list(urwire.decode_file(pcap, ports=[port]))
    assert len(records) >= 60 and records[0].TYPE == "version"
    assert not any(urwire.canonical.has_error(r) for r in records)


def test_export_row_counts(tmp_path):
    import pyarrow  # noqa: F401  (the parquet extra; requirements-dev.txt installs it)
    import pyarrow.parquet as pq
    from urwire.live.simulated import Controller

    sim = Controller((3, 15, 0), 10)
    raw = tmp_path / "session.raw"
    raw.write_bytes(sim.version_message() + b"".join(b for _ in range(120) for b in sim.step()))
    res = subprocess.run([sys.executable, "-m", "urwire", "export", str(raw), "--out", str(tmp_path / "t")],
                         capture_output=True, text=True, env=ENV, timeout=120)
    assert res.returncode == 0, res.stderr
    expected: dict[str, int] = {}
    for r in urwire.decode_file(raw):
        expected[r.TYPE] = expected.get(r.TYPE, 0) + 1
        for p in getattr(r, "packages", []):
            expected[p.TYPE] = expected.get(p.TYPE, 0) + 1
    found = {p.stem: pq.read_metadata(p).num_rows for p in (tmp_path / "t").glob("*.parquet")}
    assert found == expected
    joints = pq.read_table(tmp_path / "t" / "joint_data.parquet")
    assert joints.schema.field("q_actual_5").type == "double" and joints.schema.field("t_motor_0").type == "float"
    import duckdb  # a dev dependency (requirements-dev.txt): the query the docs show

    n = duckdb.sql(f"select count(*) from '{tmp_path}/t/joint_data.parquet'").fetchall()[0][0]
    assert n == expected["joint_data"]


def test_export_dates_capture_rows_by_the_frame_that_completed_them(tmp_path):
    import pyarrow.parquet as pq

    capture = ROOT / "dissector" / "samples" / "primary_session.pcapng"
    res = subprocess.run([sys.executable, "-m", "urwire", "export", str(capture), "--out", str(tmp_path / "t")],
                         capture_output=True, text=True, env=ENV, timeout=120)
    assert res.returncode == 0, res.stderr
    times = pq.read_table(tmp_path / "t" / "robot_state.parquet").column("capture_time").to_pylist()
    # tshark's own times of the robot's frames that carry bytes: every message ends in one of them
    frames = subprocess.run(["tshark", "-r", str(capture), "-Y", "tcp.srcport == 30001 && tcp.len > 0",
                             "-T", "fields", "-e", "frame.time_epoch"], capture_output=True, text=True,
                            timeout=120, check=True).stdout.split()
    frame_times = {round(float(t), 6) for t in frames}
    assert len(times) == sum(r.TYPE == "robot_state" for r in urwire.decode_file(capture))
    assert all(round(t, 6) in frame_times for t in times)
    assert times == sorted(times) and times[-1] - times[0] > 15  # the capture's 20 s of motion


def test_export_csv_needs_nothing(tmp_path):
    from urwire.live.simulated import Controller

    sim = Controller((1, 8, 0), 10)
    raw = tmp_path / "session.raw"
    raw.write_bytes(sim.version_message() + b"".join(b for _ in range(30) for b in sim.step()))
    res = subprocess.run([sys.executable, "-m", "urwire", "export", str(raw), "--format", "csv", "--out",
                          str(tmp_path / "t")], capture_output=True, text=True, env=ENV, timeout=120)
    assert res.returncode == 0, res.stderr
    rows = (tmp_path / "t" / "joint_data.csv").read_text().splitlines()
    assert rows[0].startswith("position,q_actual_0,") and len(rows) == 31


def test_plot_writes_an_image(tmp_path):
    import matplotlib  # noqa: F401  (the plot extra; requirements-dev.txt installs it)
    from urwire.live.simulated import Controller

    sim = Controller((5, 11, 0), 10)
    raw = tmp_path / "session.raw"
    raw.write_bytes(sim.version_message() + b"".join(b for _ in range(50) for b in sim.step()))
    out = tmp_path / "q.png"
    res = subprocess.run([sys.executable, "-m", "urwire", "plot", str(raw), "--field", "joint_data.q_actual",
                          "--out", str(out)], capture_output=True, text=True, env=ENV, timeout=120)
    assert res.returncode == 0, res.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "50 points, 6 lines" in res.stderr


def test_plot_axis_names_the_field_as_the_spec_labels_it():
    from urwire.data import plot
    from urwire.generated import messages

    assert plot.axis_title(messages.Joint, "q_actual") == "Actual joint position (rad)"
    assert plot.axis_title(messages.Joint, "no_such_field") == "no_such_field"
