"""`urwire serve`'s primary interface follows the spec's layouts: a robot state carries the
sub-packages the served version sends, each decoding cleanly in that version's layout, and a field
added to a copy of the spec is in the states of the versions that have it (a serve and a
`urwire listen` built from that copy), and only there."""
from __future__ import annotations

import json
import subprocess
import sys

import pytest

import urwire
from tests.python.cell_server import CellServer, generated_from_edited_spec, read_until
from urwire.canonical import fails
from urwire.framer import Framer
from urwire.live.simulated import state_classes


def version_of(software: str) -> tuple:
    return tuple(int(p) for p in software.split(".")) + (0,)


@pytest.mark.parametrize("software", ["3.15", "5.11", "10.7"])
def test_a_served_state_has_every_sub_package_of_the_version_in_its_layout(tmp_path, software):
    with CellServer(tmp_path, "--software", software) as server:
        with server.connect("primary") as sock:
            records = read_until(sock, Framer().feed,
                                 lambda r: sum(isinstance(x, urwire.RobotStateMessage) for x in r) >= 2)
        assert server.stop() == 0
    states = [r for r in records if isinstance(r, urwire.RobotStateMessage)]
    assert records[0].project_name == "URControl" and not any(fails(r) for r in records)
    for state in states[:2]:
        # KinematicsInfo and ConfigurationData come in the first state only, as a controller sends them.
        assert {type(p) for p in state.packages} <= set(state_classes(version_of(software)))
    assert {type(p) for p in states[0].packages} == set(state_classes(version_of(software)))


NEW_FIELD = """          - name: tcp_speed_scaling
            label: "TCP speed scaling"
            type: float64
            versions: {from: "5.11", until: "5.99"}
"""


def with_new_field(spec: str) -> str:
    """additional_info with one float64 appended from 5.11 in the e-Series (its last field is reserved)."""
    return spec.replace("\n\n      calibration_data:", "\n" + NEW_FIELD + "\n      calibration_data:", 1)


def additional_info(env: dict, port: int) -> list:
    """The additional_info packages of the first states `urwire listen` (of the same copy) decodes."""
    listened = subprocess.run([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{port}", "--count", "3"],
                              env=dict(env, URWIRE_BACKEND="python"), capture_output=True, text=True, timeout=30)
    assert listened.returncode == 0, listened.stderr
    records = [json.loads(line) for line in listened.stdout.splitlines()]
    return [p for r in records for p in r.get("packages", []) if p["type"] == "additional_info"]


def test_a_field_added_to_the_spec_is_served_in_the_versions_that_have_it(tmp_path):
    env = generated_from_edited_spec(tmp_path, "ur_primary.yaml", with_new_field)
    found = {}
    for software in ("5.10", "5.11", "10.7"):
        with CellServer(tmp_path, "--software", software, env=env) as server:
            found[software] = additional_info(env, server.ports["primary"])
            assert server.stop() == 0
    assert found["5.11"] and all(p["tcp_speed_scaling"] == 0.0 for p in found["5.11"])
    assert found["5.10"] and not any("tcp_speed_scaling" in p for p in found["5.10"])
    assert found["10.7"] and not any("tcp_speed_scaling" in p for p in found["10.7"])
