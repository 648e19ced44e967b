"""`urwire serve`'s RTDE follows the variable table of spec/rtde.yaml: every output variable the
served software version has is offered, with the table's type, and streamed with a value of that
type (zero where the simulated robot has no value for it); one the version lacks is NOT_FOUND. A
variable added to a copy of the spec is offered and streamed by a serve built from that copy."""
from __future__ import annotations

import pytest

from tests.python.cell_server import CellServer, RtdeClient, generated_from_edited_spec
from urwire import rtde
from urwire.generated import rtde as g
from urwire.live.serve_rtde import _OUTPUTS

PYTHON_TYPE = {"float": float, "int": int, "bool": bool}


def version_of(software: str) -> tuple:
    return tuple(int(p) for p in software.split(".")) + (0,) * (3 - software.count(".") - 1)


def streamed(server: CellServer, names: list) -> tuple:
    """The types a protocol 2 setup of `names` gets, and (when taken) the first data package's values."""
    client = RtdeClient(server)
    try:
        assert client.ask(rtde.request_protocol_version(2), g.RequestProtocolVersionReply).accepted
        reply = client.ask(rtde.setup_outputs(names, 125.0), g.SetupOutputsReply)
        if not reply.recipe_id:
            return list(reply.types), None
        assert client.ask(rtde.start(), g.StartReply).accepted
        return list(reply.types), client.packages(1)[0].values
    finally:
        client.close()


def assert_of_its_type(name: str, type_name: str, value) -> None:
    value_type = g.VALUE_TYPES[type_name]
    items = value if value_type.count > 1 else [value]
    assert len(items) == value_type.count, name
    assert all(type(item) is PYTHON_TYPE[value_type.kind] for item in items), (name, value)


@pytest.mark.parametrize("software", ["3.15", "5.11", "10.7"])
def test_every_output_variable_of_the_version_is_offered_and_streamed(tmp_path, software):
    version = version_of(software)
    outputs = [v for v in rtde.VARIABLES.rows if v.direction == "output"]
    offered = [v for v in outputs if v.available_in(version) is not False]
    lacking = [v.name for v in outputs if v.available_in(version) is False]
    assert any(v.name not in _OUTPUTS for v in offered)
    assert bool(lacking) == (version < (10, 0, 0))       # 10.x has every output of the table
    with CellServer(tmp_path, "--software", software) as server:
        types, values = streamed(server, [v.name for v in offered])
        assert types == [v.type for v in offered]
        assert set(values) == {v.name for v in offered}
        for v in offered:
            assert_of_its_type(v.name, v.type, values[v.name])
        if lacking:
            assert streamed(server, ["timestamp"] + lacking) == (["DOUBLE"] + ["NOT_FOUND"] * len(lacking), None)
        assert server.stop() == 0


NEW_VARIABLES = """  - {name: tcp_speed_scaling, type: DOUBLE, direction: output, label: TCP speed scaling,
     since: {cb3: none, eseries: "5.11"}}
  - {name: joint_brake_counts, type: VECTOR6INT32, direction: output, label: Joint brake counts,
     since: {cb3: "3.15", eseries: "5.11"}}
"""


def test_a_variable_added_to_the_spec_is_offered_and_streamed_without_code(tmp_path):
    env = generated_from_edited_spec(tmp_path, "rtde.yaml", lambda text: text + NEW_VARIABLES)
    names = ["timestamp", "tcp_speed_scaling", "joint_brake_counts"]
    assert not set(names[1:]) & set(_OUTPUTS)
    with CellServer(tmp_path, "--software", "5.11", env=env) as server:
        types, values = streamed(server, names)
        assert server.stop() == 0
    assert types == ["DOUBLE", "DOUBLE", "VECTOR6INT32"]
    assert values["tcp_speed_scaling"] == 0.0 and values["joint_brake_counts"] == [0] * 6
    with CellServer(tmp_path, "--software", "3.15", env=env) as server:
        assert streamed(server, names)[0] == ["DOUBLE", "NOT_FOUND", "VECTOR6INT32"]
        assert server.stop() == 0
