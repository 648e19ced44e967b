"""RTDE (30004) as `urwire serve` serves it: a controller's side of the protocol, one session per
client, built from the RTDE spec's generated classes and encoder.

A session starts in protocol 1, as a controller does, and takes protocol 1 or 2 when asked; it
answers the controller version; answers a setup with each variable's type, or NOT_FOUND for a name
the served software version's variable table lacks, or IN_USE for an input another connection
holds; refuses (recipe id 0) a frequency the robot would not run: not a number, infinite, zero or
below, or above the generation's maximum (125 Hz on CB3, 500 Hz on e-Series); starts and pauses;
streams an output data package per recipe at its frequency, with the values of the robot's one
motion at the package's time; and writes the inputs it receives into the robot's state.
"""
from __future__ import annotations

import asyncio
from typing import Callable, Optional

from .. import rtde
from ..generated import rtde as _g
from .robot_cell import BUILD_NUMBER, RobotCell, Snapshot
from .robot_models import CB3, E_SERIES, POLYSCOPE_X, generation

# The highest output frequency of each generation (RTDE guide: "125 Hz on CB3, 500 Hz on e-Series").
MAX_FREQUENCY = {CB3: 125.0, E_SERIES: 500.0, POLYSCOPE_X: 500.0}


def has_rtde(version: tuple) -> bool:
    """RTDE came with 3.3 (the RTDE guide); CB2 has none."""
    return version >= (3, 3, 0)


def max_frequency(version: tuple) -> float:
    return MAX_FREQUENCY.get(generation(version), 125.0)


def frequency_refused(frequency: float, version: tuple) -> bool:
    """Whether a controller of `version` refuses an output frequency: NaN fails every comparison."""
    return not 0.0 < frequency <= max_frequency(version)


def offers(variable, version: tuple) -> bool:
    """Whether a controller of `version` has this row of the variable table, as the table's own
    rule says (Variable.available_in: its series' column); a row whose first version the sources
    do not give is taken as there from the start."""
    return variable.available_in(version) is not False


def output_value(name: str, value_type: _g._r.ValueType, state: Snapshot, cell: RobotCell):
    """One output variable's value at a snapshot: the motion for joints and pose, the robot's state
    for modes and outputs, the input registers as clients wrote them, zero for the rest."""
    value = _OUTPUTS[name](state) if name in _OUTPUTS else cell.inputs.values.get(name)
    if value is None:
        value = [0] * value_type.count if value_type.count > 1 else 0
    if value_type.kind == "float":
        return [float(v) for v in value] if value_type.count > 1 else float(value)
    if value_type.kind == "bool":
        return bool(value)
    return [int(v) for v in value] if value_type.count > 1 else int(value)


_OUTPUTS: dict[str, Callable[[Snapshot], object]] = {
    "timestamp": lambda s: s.t,
    "actual_q": lambda s: s.q, "target_q": lambda s: s.q,
    "actual_qd": lambda s: s.qd, "target_qd": lambda s: s.qd,
    "target_qdd": lambda s: s.qdd,
    "actual_current": lambda s: s.current, "target_current": lambda s: s.current,
    "actual_TCP_pose": lambda s: s.tcp_pose, "target_TCP_pose": lambda s: s.tcp_pose,
    "actual_TCP_speed": lambda s: s.tcp_speed, "target_TCP_speed": lambda s: s.tcp_speed,
    "robot_mode": lambda s: s.robot_mode,
    "joint_mode": lambda s: [s.joint_mode] * 6,
    "safety_mode": lambda s: s.safety_mode,
    "safety_status": lambda s: s.safety_mode,
    "runtime_state": lambda s: s.program_state,
    "speed_scaling": lambda s: s.speed_scaling,
    "target_speed_fraction": lambda s: s.target_speed_fraction,
    "actual_digital_output_bits": lambda s: s.digital_outputs,
    "actual_main_voltage": lambda s: s.main_voltage,
    "actual_robot_voltage": lambda s: s.robot_voltage,
    "actual_robot_current": lambda s: s.robot_current,
    "actual_joint_voltage": lambda s: [s.robot_voltage] * 6,
    "joint_temperatures": lambda s: s.joint_temperatures,
    "actual_execution_time": lambda s: 0.3,
    # Bit 0 power on, bit 1 program running (RTDE guide).
    "robot_status_bits": lambda s: (s.robot_mode != 3) | (s.program_state == 2) << 1,
    "safety_status_bits": lambda s: 0b1,                                       # normal mode
}


class Stream:
    """One output recipe being sent: its recipe, period and the time of its next package."""

    def __init__(self, recipe: rtde.Recipe, frequency: float, first: float):
        self.recipe = recipe
        self.period = 1.0 / frequency
        self.due = first


class RtdeSession:
    """One client's RTDE connection. `send(bytes) -> bool` writes (False: the client was dropped);
    `clock()` is the server time in seconds."""

    def __init__(self, cell: RobotCell, clock: Callable[[], float], send: Callable[[bytes], bool]):
        self.cell = cell
        self.clock = clock
        self.send = send
        self.conversation = rtde.Conversation(protocol=1)     # a controller starts in protocol 1
        self.next_id = 1
        self.outputs: dict[Optional[int], tuple] = {}         # recipe id -> (recipe, frequency)
        self.inputs: dict[int, rtde.Recipe] = {}
        self.streams: list[Stream] = []
        self.wake = asyncio.Event()
        self.buffer = bytearray()

    # ---- the client's messages ---------------------------------------------------------------
    def received(self, data: bytes) -> None:
        """Answers each whole message. Messages are fed to the connection's state one at a time, each
        after the reply to the one before, so that a client that sends its setup right behind its
        protocol request (without waiting) has it read in the protocol just agreed."""
        self.buffer += data
        while len(self.buffer) >= _g.HEADER.size:
            size = _g.HEADER.unpack_from(self.buffer)[0]
            take = size if size >= _g.HEADER.size else len(self.buffer)   # a bad size: the framer reports it
            if len(self.buffer) < take:
                return
            message, self.buffer = bytes(self.buffer[:take]), self.buffer[take:]
            for record in self.conversation.feed(message, False):
                reply = self.answer(record)
                if reply is not None:
                    self.conversation.feed(reply, True)       # the connection's state follows its replies
                    if not self.send(reply):
                        return

    def answer(self, message) -> Optional[bytes]:
        """The reply to one client message (None: the message gets none)."""
        if isinstance(message, _g.RequestProtocolVersion):
            return _g.RequestProtocolVersionReply(message.protocol_version in _g.PROTOCOL_VERSIONS).encode()
        if isinstance(message, _g.GetUrcontrolVersion):
            major, minor, bugfix = self.cell.version
            return _g.GetUrcontrolVersionReply(major, minor, bugfix, BUILD_NUMBER).encode()
        if isinstance(message, (_g.SetupOutputs, _g.SetupOutputsV1)):
            return self.setup_outputs(message)
        if isinstance(message, _g.SetupInputs):
            return self.setup_inputs(message)
        if isinstance(message, _g.Start):
            self.start()
            return _g.StartReply(bool(self.outputs)).encode()
        if isinstance(message, _g.Pause):
            self.streams = []
            return _g.PauseReply(True).encode()
        if isinstance(message, _g.InputDataPackage):
            if message.recipe_id in self.inputs:
                self.cell.write_inputs(message.values)
            return None
        return None                                            # text messages and raw bytes: nothing to say

    def types_of(self, names: list, direction: str) -> list:
        types = []
        for name in names:
            row = rtde.variable(name, direction)
            types.append(row.type if row is not None and offers(row, self.cell.version) else "NOT_FOUND")
        return types

    def setup_outputs(self, message) -> bytes:
        names = [n for n in message.variables if n]           # an empty name (a trailing comma) names nothing
        types = self.types_of(names, "output")
        refused = any(t in _g.REFUSALS for t in types)
        if isinstance(message, _g.SetupOutputsV1):        # no frequency: the controller's own
            if not refused:
                frequency = max_frequency(self.cell.version)
                self.outputs = {None: (rtde.Recipe(None, "outputs", names, types, _g.VALUE_TYPES), frequency)}
            return _g.SetupOutputsReplyV1(types).encode()
        frequency = float(message.output_frequency)
        recipe_id = 0 if refused or frequency_refused(frequency, self.cell.version) else self._new_id()
        if recipe_id:
            self.outputs[recipe_id] = (rtde.Recipe(recipe_id, "outputs", names, types, _g.VALUE_TYPES), frequency)
        return _g.SetupOutputsReply(recipe_id, types).encode()

    def setup_inputs(self, message) -> bytes:
        names = [n for n in message.variables if n]
        types = self.types_of(names, "input")
        if not any(t in _g.REFUSALS for t in types):
            taken = set(self.cell.claim_inputs(self, names))
            types = ["IN_USE" if n in taken else t for n, t in zip(names, types)]
        if any(t in _g.REFUSALS for t in types):
            return _g.SetupInputsReply(0, types).encode()
        recipe_id = self._new_id()
        self.inputs[recipe_id] = rtde.Recipe(recipe_id, "inputs", names, types, _g.VALUE_TYPES)
        return _g.SetupInputsReply(recipe_id, types).encode()

    def _new_id(self) -> int:
        recipe_id, self.next_id = self.next_id, self.next_id % 255 + 1
        return recipe_id

    def start(self) -> None:
        now = self.clock()
        self.streams = [Stream(recipe, frequency, now) for recipe, frequency in self.outputs.values()]
        self.wake.set()

    def inputs_ended(self) -> None:
        self.cell.release_inputs(self)
        self.inputs.clear()

    def closed(self) -> None:
        self.inputs_ended()
        self.streams = []

    # ---- the robot's data packages -----------------------------------------------------------
    def package(self, recipe: rtde.Recipe, t: float) -> bytes:
        state = self.cell.state_at(t)
        values = {name: output_value(name, _g.VALUE_TYPES[type_name], state, self.cell)
                  for name, type_name in zip(recipe.names, recipe.types)}
        if recipe.id is None:
            return _g.DataPackageV1(values).encode(recipe)
        return _g.DataPackage(recipe.id, values).encode(recipe)

    async def run(self, closing: Callable[[], bool]) -> None:
        """Sends each stream's packages when due, until the connection closes. A stream that fell
        behind (a slow client) skips to now rather than sending a burst."""
        while not closing():
            if not self.streams:
                self.wake.clear()
                await self.wake.wait()
                continue
            now = self.clock()
            for stream in list(self.streams):
                if stream.due <= now:
                    if not self.send(self.package(stream.recipe, stream.due)):
                        return
                    stream.due += stream.period
                    if stream.due < now - 0.1:
                        stream.due = now
            if self.streams:
                await asyncio.sleep(max(0.0, min(s.due for s in self.streams) - self.clock()))
