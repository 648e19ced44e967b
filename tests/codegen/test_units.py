"""Every value that plainly has a physical or time unit says it. The check reads the Python
bindings' metadata (`field(metadata={"label", "unit"})` of every generated class, and the RTDE
variable table): what each spec gives every target, the same model the C comments, the Lua and the
native trees render (`make check-generated` keeps them equal to the spec). A field whose name or
label says a quantity with a unit (time, voltage, current, temperature, speed, force, pose, ...)
has a unit, or is listed below with the reason it has none."""
from __future__ import annotations

import dataclasses
import importlib
import pkgutil
import re
from typing import Iterator, NamedTuple, Optional

import urwire.generated
from urwire import rtde

# Words that name a quantity with a unit.
QUANTITIES = {
    "time", "timestamp", "timer", "duration", "timeout", "frequency", "voltage", "voltages", "current", "currents",
    "temperature", "temperatures", "speed", "velocity", "velocities", "acceleration", "accelerations",
    "accelerometer", "force", "torque", "torques", "moment", "moments", "wrench", "pose", "position", "positions",
    "offset", "radius", "mass", "payload", "inertia", "cog", "energy", "gravity", "momentum",
}
# Words that make it a code or a ratio instead, which has no unit ("Speed scaling", "Tool output mode").
DIMENSIONLESS = {"fraction", "ratio", "scaling", "slider", "mask", "bits", "mode", "modes", "state", "status",
                 "type", "range", "domain", "source"}

# (interface, field) -> why it has no unit. Each spec says the same in its field_note or doc.
NO_UNIT = {
    # No source gives the primary timestamps' unit (robot_mode_data's field_note).
    ("messages", "timestamp"): "not documented",
    # "Deprecated - ignore", says the document, and nothing more.
    ("messages", "t_micro"): "deprecated",
    # The RTDE guide gives its twins (io_current, euromap67_24V_current) in mA; what the primary
    # interface sends, no source says (masterboard_data's field_note).
    ("messages", "master_io_current"): "not documented",
    ("messages", "euromap_current"): "not documented",
    # CB2's shorts, whose scale no source gives.
    ("messages", "euromap_voltage_cb2"): "not documented",
    ("messages", "euromap_current_cb2"): "not documented",
    # An input from the three-position enabling device: "position" names the switch, not a place.
    ("messages", "three_position_enabling_device_input"): "a code",
    # A group: its members (joint_min_limit, joint_max_limit) carry rad.
    ("messages", "joint_position_limits"): "a group",
    # No source gives eq_radius a unit (configuration_data's field_note).
    ("messages", "eq_radius"): "not documented",
    # The RealTime tables and the RTDE guide give none.
    ("ur_realtime", "controller_timer"): "not documented",
    ("ur_realtime", "linear_momentum_norm"): "not documented",
    ("rtde", "actual_momentum"): "not documented",
    # Joint values (rad) or a pose (m and rad), as the motion type says (the field's doc).
    ("ur_trajectory", "positions"): "set by the motion type",
    ("ur_trajectory", "velocities"): "set by the motion type",
    ("ur_trajectory", "accelerations"): "set by the motion type",
}


class Value(NamedTuple):
    interface: str        # the generated module (`messages` for the primary interface), or `rtde`
    name: str
    label: str
    unit: Optional[str]


def values() -> Iterator[Value]:
    """Every labelled field of every generated class, and every RTDE variable."""
    for info in pkgutil.iter_modules(urwire.generated.__path__):
        module = importlib.import_module(f"urwire.generated.{info.name}")
        for cls in vars(module).values():
            if isinstance(cls, type) and dataclasses.is_dataclass(cls) and cls.__module__ == module.__name__:
                for f in dataclasses.fields(cls):
                    if "label" in f.metadata:
                        yield Value(info.name, f.name, f.metadata["label"], f.metadata.get("unit"))
    for v in rtde.VARIABLES.rows:
        yield Value("rtde", v.name, v.label, v.unit)


def words(value: Value) -> set[str]:
    return set(re.split(r"[^a-z0-9]+", f"{value.name.replace('_', ' ')} {value.label}".lower()))


def plainly_has_a_unit(value: Value) -> bool:
    said = words(value)
    return bool(said & QUANTITIES) and not said & DIMENSIONLESS


def test_every_value_that_plainly_has_a_unit_has_one():
    lacking = sorted({(v.interface, v.name, v.label) for v in values()
                      if plainly_has_a_unit(v) and not v.unit and (v.interface, v.name) not in NO_UNIT})
    assert not lacking, f"give these a unit: in the spec, or in NO_UNIT with the reason: {lacking}"


def test_every_value_listed_without_a_unit_still_lacks_one():
    """An entry goes when its field gets a unit or leaves the spec."""
    listed = {(v.interface, v.name): v.unit for v in values() if (v.interface, v.name) in NO_UNIT}
    assert set(listed) == set(NO_UNIT), sorted(set(NO_UNIT) - set(listed))
    assert not {key: unit for key, unit in listed.items() if unit}


def test_the_timestamps_and_durations_of_every_interface_are_known():
    """The values that say when or how long: each with its unit, or listed."""
    timed = {(v.interface, v.name): v.unit for v in values()
             if plainly_has_a_unit(v) and words(v) & {"time", "timestamp", "timer", "duration", "timeout"}}
    assert timed[("rtde", "timestamp")] == "s"
    assert timed[("ur_realtime", "time")] == "s"
    assert timed[("ur_trajectory", "duration")] == "s"
    assert timed[("ur_reverse", "read_timeout")] == "ms"
    assert timed[("rtde", "actual_execution_time")] == "ms"
    assert timed[("messages", "timestamp")] is None and ("messages", "timestamp") in NO_UNIT
    assert all(unit or key in NO_UNIT for key, unit in timed.items()), timed


def test_the_words_find_what_they_should():
    assert plainly_has_a_unit(Value("x", "tool_voltage_48v", "Tool voltage", None))
    assert plainly_has_a_unit(Value("x", "output_frequency", "Output frequency", None))
    assert not plainly_has_a_unit(Value("x", "speed_scaling", "Speed scaling", None))
    assert not plainly_has_a_unit(Value("x", "robot_mode", "Robot mode", None))
