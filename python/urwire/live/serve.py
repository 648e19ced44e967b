"""`urwire serve`: a simulated robot on every interface of a UR cell, one session per client.

One process serves one robot (robot_cell.RobotCell) on six ports: the primary interface (--port,
default 30001), RTDE (30004, from 3.3), the real-time interface (30003), the dashboard server
(29999), interpreter mode (30020, from e-Series 5.10) and the Robotiq gripper URCap's socket
(63352). Each other port defaults to its offset from --port (so `--port 0` gives every interface a
free port) or takes its own option; the gripper's is the URCap's own, 63352, with the default
--port, and a free one with any other. Every interface samples the same motion on the server's clock,
and what a client changes (a dashboard `stop`, an RTDE input) every interface reports.

Primary clients each get their own simulated.Controller: the Version message first (and the
hardware info message, from 5.26 and 10.13), then robot states at the given rate. The arm is
--model's (default: the generation's usual one). Loopback by default. SIGINT and SIGTERM abort
every connection and stop within a second or two, whatever the clients do (exit status 0). A
client that stops reading is dropped once its unsent data passes --max-unsent, so it costs bounded
memory and never holds the others back. What a primary or real-time client sends is read and
thrown away.
"""
from __future__ import annotations

import argparse
import asyncio
import os
import signal
import sys
from dataclasses import dataclass, field
from typing import Callable, Optional

from ..arguments import HIGHEST_PORT, finite_number, port_number, software_version
from .robot_cell import RobotCell
from .robot_models import MODELS, RobotModel, model_for
from .serve_dashboard import DashboardSession
from .serve_gripper import Gripper, GripperSession, has_gripper
from .serve_interpreter import Interpreter, InterpreterSession, has_interpreter
from .serve_realtime import RealtimePackets, RealtimeSession
from .serve_rtde import RtdeSession, has_rtde
from .simulated import Controller

# Connections the kernel queues before `accept`: asyncio's default of 100 turns away a crowd.
BACKLOG = 4096
DEFAULT_MAX_UNSENT_KB = 256
# How long a stop waits for the aborted sessions to finish before giving up on them.
STOP_GRACE_SECONDS = 1.0
PRIMARY_PORT = 30001
# Each other interface's port is its offset from the primary's: 30004, 30003, 29999 and 30020 by
# default. The gripper's is the URCap's own with the default primary port, and a free one with any
# other (two servers on other ports then never meet on it).
OFFSETS = {"rtde": 3, "realtime": 2, "dashboard": -2, "interpreter": 19}
FIXED = {"gripper": 63352}
# The fastest a UR controller sends on any interface: an e-Series' real-time and RTDE data, at
# 500 Hz (the primary interface's states come at 10 Hz). A faster --rate is no robot's, and only
# burns the server's processor.
HIGHEST_RATE = 500.0


def add_parser(sub) -> None:
    p = sub.add_parser("serve", help="simulate a robot of any software version on every interface of a UR cell",
                       description="Serve a simulated robot: the primary interface (its Version message, then "
                                   "robot states and program messages), RTDE, the real-time interface, the "
                                   "dashboard server, interpreter mode and a Robotiq gripper's socket, each on "
                                   "its port, all reporting one motion.")
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default: 127.0.0.1)")
    p.add_argument("--port", type=port_number, default=PRIMARY_PORT,
                   help="the primary interface's TCP port; 0 picks a free one for it and, unless given, for every "
                        "other interface (default: 30001)")
    for name, offset, title in (("rtde", 3, "RTDE (from software 3.3)"), ("realtime", 2, "the real-time interface"),
                                ("dashboard", -2, "the dashboard server"),
                                ("interpreter", 19, "interpreter mode (from e-Series 5.10)")):
        p.add_argument(f"--{name}-port", type=port_number, metavar="PORT",
                       help=f"{title}'s TCP port; 0 picks a free one (default: --port {offset:+d}, "
                            f"{PRIMARY_PORT + offset} for 30001)")
    p.add_argument("--gripper-port", type=port_number, metavar="PORT",
                   help=f"the Robotiq gripper URCap's TCP port; 0 picks a free one (default: {FIXED['gripper']} "
                        f"with --port {PRIMARY_PORT}, a free one with any other)")
    p.add_argument("--software", type=software_version, default=(5, 11, 0), metavar="X.Y[.Z]",
                   help="software version to simulate, e.g. 1.8, 3.15 or 5.11 (default: 5.11)")
    p.add_argument("--model", type=str.lower, choices=list(MODELS), metavar="MODEL",
                   help="the arm: ur3 (CB3), ur5, ur10 (CB2, CB3), ur3e, ur5e, ur10e, ur16e, ur20, ur30 (e-Series, "
                        "PolyScope X) (default: ur5 on CB2 and CB3, ur5e on e-Series and PolyScope X)")
    p.add_argument("--rate", type=finite_number, default=10.0,
                   help=f"primary robot states per second, above 0 and at most {HIGHEST_RATE:g}, the fastest a "
                        f"controller sends on any interface (default: 10, as a controller sends them)")
    p.add_argument("--duration", type=finite_number, metavar="S",
                   help="stop after S seconds (default: run until stopped)")
    p.add_argument("--max-unsent", type=int, default=DEFAULT_MAX_UNSENT_KB, metavar="KB",
                   help="drop a client once this much data waits unsent for it "
                        f"(default: {DEFAULT_MAX_UNSENT_KB})")
    p.set_defaults(run=serve_command)


def raise_open_file_limit() -> None:
    """Every client is a file descriptor: take the hard limit so a crowd of clients fits."""
    try:
        import resource  # Unix only
    except ImportError:  # not on this platform
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft != hard:
        try:
            resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))
        except (ValueError, OSError):
            pass  # keep the soft limit we were given


def log(text: str) -> None:
    print(f"urwire serve: {text}", file=sys.stderr, flush=True)


@dataclass
class Robot:
    """What every session of one served robot shares: its state, the server's clock (seconds since
    it started), the real-time packets, the primary's rate and the send limit."""
    cell: RobotCell
    clock: Callable[[], float]
    realtime: RealtimePackets
    rate: float
    max_unsent: int
    sessions: set
    interpreter: Interpreter = field(default_factory=Interpreter)   # one per robot, whichever client sends
    gripper: Gripper = field(default_factory=Gripper)


class Session(asyncio.Protocol):
    """One client of any interface: writes without ever waiting on the client, so no session can
    block a stop. Subclasses say what to send (`run`) and what to do with what arrives."""

    def __init__(self, robot: Robot):
        self.robot = robot
        self.transport: Optional[asyncio.Transport] = None
        self.task: Optional[asyncio.Task] = None

    def connection_made(self, transport) -> None:
        self.transport = transport
        self.robot.sessions.add(self)
        self.task = asyncio.get_running_loop().create_task(self.run())

    def data_received(self, data: bytes) -> None:
        pass  # the primary and real-time interfaces ignore what the client sends

    def eof_received(self) -> bool:
        return True  # a half-closed client still reads: keep sending

    def connection_lost(self, exc) -> None:
        self.robot.sessions.discard(self)
        if self.task is not None:
            self.task.cancel()

    def closing(self) -> bool:
        return self.transport.is_closing()

    def send(self, data: bytes) -> bool:
        """Write, or drop the client and return False when it has stopped reading."""
        if self.transport.is_closing():
            return False
        self.transport.write(data)
        unsent = self.transport.get_write_buffer_size()
        if unsent <= self.robot.max_unsent:
            return True
        peer = self.transport.get_extra_info("peername") or ("?", 0)
        log(f"dropped {peer[0]}:{peer[1]}: not reading ({unsent // 1024} KB unsent)")
        self.transport.abort()
        return False

    async def run(self) -> None:
        pass

    def abort(self) -> None:
        self.transport.abort()


class PrimarySession(Session):
    def __init__(self, robot: Robot):
        super().__init__(robot)
        self.controller = Controller(robot.cell.version, robot.rate, robot.cell.model, start=robot.clock(),
                                     cell=robot.cell)

    async def run(self) -> None:
        loop = asyncio.get_running_loop()
        start = loop.time()
        if not self.send(self.controller.opening()):
            return
        while not self.closing():
            if not self.send(b"".join(self.controller.step())):
                return
            due = start + self.controller.tick / self.robot.rate
            await asyncio.sleep(max(0.0, due - loop.time()))


class RealtimeClient(Session):
    async def run(self) -> None:
        await RealtimeSession(self.robot.realtime, self.robot.clock, self.send).run(self.closing)


class RtdeClient(Session):
    def __init__(self, robot: Robot):
        super().__init__(robot)
        self.rtde = RtdeSession(robot.cell, robot.clock, self.send)

    def data_received(self, data: bytes) -> None:
        self.rtde.received(data)

    def eof_received(self) -> bool:
        self.rtde.inputs_ended()             # it can write no more inputs: another client may take them
        # A half-closed client still reads what streams; with nothing streaming, the session is over.
        return bool(self.rtde.streams)

    def connection_lost(self, exc) -> None:
        self.rtde.closed()
        super().connection_lost(exc)

    async def run(self) -> None:
        await self.rtde.run(self.closing)


class DashboardClient(Session):
    def __init__(self, robot: Robot):
        super().__init__(robot)
        self.dashboard = DashboardSession(robot.cell, robot.clock)

    def connection_made(self, transport) -> None:
        super().connection_made(transport)
        self.send(self.dashboard.banner())

    def data_received(self, data: bytes) -> None:
        replies = self.dashboard.received(data)
        if replies and self.send(replies) and self.dashboard.closing:
            self.transport.close()                 # after `quit`: its reply goes out, then the connection ends


class LineClient(Session):
    """A client of a text-line interface that answers each line (interpreter mode, the gripper)."""

    def __init__(self, robot: Robot, lines):
        super().__init__(robot)
        self.lines = lines

    def data_received(self, data: bytes) -> None:
        replies = self.lines.received(data)
        if replies:
            self.send(replies)


def interpreter_client(robot: Robot) -> LineClient:
    return LineClient(robot, InterpreterSession(robot.interpreter, robot.clock))


def gripper_client(robot: Robot) -> LineClient:
    return LineClient(robot, GripperSession(robot.gripper, robot.clock))


def interface_ports(port: int, given: dict) -> dict:
    """Each interface's port: given, else its offset from the primary's (0 stays 0: a free one), or
    its fixed one with the default primary port and a free one with any other."""
    out = {"primary": port}
    for name, offset in OFFSETS.items():
        out[name] = given.get(name) if given.get(name) is not None else (port + offset if port else 0)
    for name, fixed in FIXED.items():
        out[name] = given.get(name) if given.get(name) is not None else (fixed if port == PRIMARY_PORT else 0)
    return out


# The interfaces a software version may lack.
HAS = {"rtde": has_rtde, "interpreter": has_interpreter, "gripper": has_gripper}
SESSIONS = {"primary": PrimarySession, "rtde": RtdeClient, "realtime": RealtimeClient, "dashboard": DashboardClient,
            "interpreter": interpreter_client, "gripper": gripper_client}
TITLES = {"primary": "", "rtde": "RTDE", "realtime": "real-time", "dashboard": "dashboard",
          "interpreter": "interpreter mode", "gripper": "Robotiq gripper"}


class ListenError(OSError):
    """An interface's port cannot be listened on."""

    def __init__(self, name: str, port: int, error: OSError):
        # asyncio words its bind errors itself: the errno's own text is the short one.
        why = os.strerror(error.errno) if error.errno else str(error)
        super().__init__(f"{TITLES[name] or 'primary'} port {port}: {why}")


async def serve(host: str, port: int, version: tuple, rate: float, duration: Optional[float],
                max_unsent_kb: int = DEFAULT_MAX_UNSENT_KB, model: Optional[RobotModel] = None,
                ports: Optional[dict] = None) -> None:
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    model = model or model_for(version)
    clock_start = loop.time()
    cell = RobotCell(version, model)
    robot = Robot(cell, lambda: loop.time() - clock_start, RealtimePackets(cell), rate, max_unsent_kb * 1024, set())
    for signum in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(signum, stop.set)
    servers = []
    try:
        for name, number in interface_ports(port, ports or {}).items():
            if not HAS.get(name, lambda _: True)(version):
                continue
            try:
                server = await loop.create_server(lambda cls=SESSIONS[name]: cls(robot), host, number, backlog=BACKLOG)
            except OSError as exc:
                raise ListenError(name, number, exc) from None
            servers.append(server)
            bound = server.sockets[0].getsockname()
            what = f"{model.name}, software {'.'.join(map(str, version))}" if name == "primary" else TITLES[name]
            log(f"{what} on {bound[0]}:{bound[1]}")
        try:
            await asyncio.wait_for(stop.wait(), duration)
        except asyncio.TimeoutError:
            pass
    finally:
        await stop_all(servers, robot.sessions)


async def stop_all(servers: list, sessions: set) -> None:
    for server in servers:
        server.close()
    # Abort rather than close: a closing transport waits for its unsent data, which a client
    # that never reads never takes (and Server.wait_closed waits for every connection from 3.12).
    tasks = [s.task for s in sessions if s.task is not None]
    for session in list(sessions):
        session.abort()
    if tasks:
        await asyncio.wait(tasks, timeout=STOP_GRACE_SECONDS)
    for server in servers:
        try:
            await asyncio.wait_for(server.wait_closed(), STOP_GRACE_SECONDS)
        except asyncio.TimeoutError:
            pass


def serve_command(args: argparse.Namespace) -> int:
    if not 0 < args.rate <= HIGHEST_RATE:
        print(f"urwire serve: --rate must be above 0 and at most {HIGHEST_RATE:g}, the fastest a controller "
              f"sends on any interface", file=sys.stderr)
        return 2
    ports = {"rtde": args.rtde_port, "realtime": args.realtime_port, "dashboard": args.dashboard_port,
             "interpreter": args.interpreter_port, "gripper": args.gripper_port}
    for name, number in interface_ports(args.port, ports).items():
        if not 0 <= number <= HIGHEST_PORT:
            print(f"urwire serve: --port {args.port} puts the {TITLES[name]} port at {number}, outside 0 to "
                  f"{HIGHEST_PORT}: give --{name}-port", file=sys.stderr)
            return 2
    if args.duration is not None and args.duration < 0:
        print("urwire serve: --duration must be 0 or more", file=sys.stderr)
        return 2
    if args.max_unsent <= 0:
        print("urwire serve: --max-unsent must be above 0", file=sys.stderr)
        return 2
    try:
        model = model_for(args.software, args.model)
    except ValueError as exc:
        print(f"urwire serve: --model: {exc}", file=sys.stderr)
        return 2
    raise_open_file_limit()
    try:
        asyncio.run(serve(args.host, args.port, args.software, args.rate, args.duration, args.max_unsent, model,
                          ports))
    except ListenError as exc:
        print(f"urwire serve: cannot listen on {args.host}: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"urwire serve: cannot listen on {args.host}:{args.port}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0
