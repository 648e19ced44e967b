"""The units the specs give reach the Wireshark tree of both dissectors, the native plugin and the Lua
ones, on the cell sample (every interface of a cell in one capture): a double's unit after its value,
an array's in its subtree's title, an int32 record field's after its label; and so do the names the
specs give codes, bits and the items of vectors, and a setup reply's variables."""
from __future__ import annotations

import re

import pytest

from tests.native import harness

CELL = harness.ROOT / "dissector" / "samples" / "cell_session.pcapng"
LUA = sorted(harness.LUA.glob("*.lua"))

# One line of the tree for each way a unit is shown, as a regular expression.
SHOWN = [
    r"Output frequency: 125 Hz",                    # RTDE: a message's double
    r"Time since the controller started: \S+ s",    # RTDE: a variable of a data package
    r"Read timeout \(ms\): 20",                     # ROS driver reverse socket: an int32 field
    r"Segment duration \(s\): 2.5 \(raw 2500000, scaled by MULT_TIME = 1000000\)",   # a scaled field
    r"Actual tool pose \(m, rad\)",                 # real-time: an array's title
    r"Z: \S+ m",                                    # and its items, each with its part of the unit
    r"RX: \S+ rad",
    r"Fz: \S+ N",
    r"Tx: \S+ Nm",
    r"Wrist 3: \S+ rad",                            # joints named
    r"Ixx: \S+ kg·m²",                              # real-time
    r"Payload inertia: \S+ kg·m²",                  # primary
    r"Actual joint position: \S+ rad",              # primary
]


@pytest.fixture(scope="module")
def trees() -> dict[str, str]:
    return {"native": harness.checked(harness.run_native(CELL, "-V")),
            "lua": harness.checked(harness.run_lua(CELL, "-V", lua=LUA))}


@pytest.mark.parametrize("dissector", ["native", "lua"])
@pytest.mark.parametrize("line", SHOWN)
def test_the_unit_shows_in_the_tree(trees, dissector, line):
    assert re.search(rf"^\s+{line}$", trees[dissector], re.M), (dissector, line)


# One line of the tree for each kind of name, as a regular expression.
NAMED = [
    r"Wrist 3: \S+ rad",                            # real-time and RTDE: joints
    r"RX: \S+ rad",                                 # an axis of a pose
    r"Robot mode: 7 \(RUNNING\)",                   # real-time: a double's code
    r"Robot mode: RUNNING \(7\)",                   # RTDE: an integer's code
    r"[.01 ]*\.1\.\. = Standard 2: True",           # real-time: a double's bits as flags
    r"\[actual_q: VECTOR6D\]",                      # RTDE: a setup reply's type by its variable
]


@pytest.mark.parametrize("dissector", ["native", "lua"])
@pytest.mark.parametrize("line", NAMED)
def test_the_name_shows_in_the_tree(trees, dissector, line):
    assert re.search(rf"^\s+{line}$", trees[dissector], re.M), (dissector, line)
