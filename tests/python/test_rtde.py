"""urwire.rtde: a connection's state (protocol version, recipes) kept per Conversation, bytes in any
chunks, hostile bytes never raise, the client's messages, the variable table."""
from __future__ import annotations

import random
import struct

import pytest

import urwire
from tests.rtde_vectors import python_records, rtde_cases
from urwire import rtde
from urwire.generated import rtde as generated
from urwire.interfaces import INTERFACES, interface_of_port

SESSION = {c.name: c for c in rtde_cases()}["protocol2_session"]


def test_registered_on_its_port():
    assert interface_of_port(30004) is INTERFACES["rtde"]
    assert INTERFACES["rtde"].conversation is rtde.Conversation


@pytest.mark.parametrize("case", rtde_cases(), ids=lambda c: c.name)
def test_chunks_of_any_size_give_the_same_records(case):
    """Every message fed in pieces of 1, 2 and 7 bytes: the same records as whole messages, stream
    faults included (one fault per scan, however the bytes were cut)."""
    whole = [urwire.to_json_line(r) for r in python_records(case)]
    for size in (1, 2, 7):
        conversation = rtde.Conversation(protocol=case.protocol)
        got = []
        for from_robot, data in case.messages:
            for at in range(0, len(data), size):
                got += conversation.feed(data[at:at + size], from_robot)
        got += conversation.close()
        assert [urwire.to_json_line(r) for r in got] == whole, size


def test_a_direction_fed_whole_gives_the_same_records():
    """The robot's whole stream in one piece after the client's: the same records from the robot
    (replies find the requests already seen)."""
    whole = [urwire.to_json_line(r) for r in python_records(SESSION)]
    conversation = rtde.Conversation()
    conversation.feed(SESSION.client_bytes, False)
    robot = [urwire.to_json_line(r) for r in conversation.feed(SESSION.robot_bytes, True)]
    from_robot = [line for line, (fr, _) in zip(whole, SESSION.messages) if fr]
    assert robot == from_robot


def test_two_connections_never_share_recipes():
    first, second = rtde.Conversation(), rtde.Conversation()
    for from_robot, data in SESSION.messages:
        first.feed(data, from_robot)
    data_package = [d for fr, d in SESSION.messages if fr and d[2] == ord("U")][0]
    (alone,) = second.feed(data_package, True)
    assert urwire.to_dict(alone)["error"].startswith("data package of a recipe")
    assert first.recipes["outputs"][2].names == ("timestamp", "actual_q", "robot_mode")
    assert second.recipes == {"outputs": {}, "inputs": {}}


def test_a_recipe_remembers_where_it_was_set_up():
    conversation = rtde.Conversation()
    records = []
    for from_robot, data in SESSION.messages:
        records += conversation.feed(data, from_robot)
    recipe = conversation.recipes["outputs"][2]
    assert records[recipe.defined_at].NAME == "setup_outputs_reply" and records[recipe.defined_at].recipe_id == 2


def test_the_client_side_builds_what_the_vectors_hold():
    sent = [d for from_robot, d in SESSION.messages if not from_robot]
    assert rtde.request_protocol_version(2) == sent[0]
    assert rtde.get_controller_version() == sent[1]
    assert rtde.setup_outputs(["timestamp", "actual_q", "not_a_variable"], 125.0) == sent[2]
    assert rtde.setup_inputs(["input_int_register_24"]) == sent[4]
    assert rtde.start() == sent[6] and rtde.pause() == sent[8]
    recipe = rtde.Recipe(1, "inputs", ["input_double_register_0"], ["DOUBLE"], generated.VALUE_TYPES)
    assert rtde.input_data(recipe, {"input_double_register_0": 0.5}) == sent[7]
    assert rtde.setup_outputs(["timestamp"], protocol=1) == bytes.fromhex("000c4f") + b"timestamp"


def test_every_value_type_reads_and_writes_back():
    names = list(generated.VALUE_TYPES)
    recipe = rtde.Recipe(3, "outputs", [n.lower() for n in names], names, generated.VALUE_TYPES)
    body = bytes([3]) + bytes(range(1, recipe.size + 1))
    message = struct.pack(">HB", 3 + len(body), ord("U")) + body
    conversation = rtde.Conversation()
    conversation.recipes["outputs"][3] = recipe
    (record,) = conversation.feed(message, True)
    assert record.encode() == message
    assert record.values["vector6int32"] == list(struct.unpack_from(">6i", body, 1 + recipe.size - 48))


@pytest.mark.parametrize("seed", range(6))
def test_hostile_bytes_never_raise(seed):
    rng = random.Random(seed)
    conversation = rtde.Conversation()
    for from_robot, data in SESSION.messages:
        conversation.feed(data, from_robot)
    for _ in range(200):
        size = rng.choice([0, 1, 3, 5, 40, 300])
        noise = bytes(rng.getrandbits(8) for _ in range(size))
        if rng.random() < 0.5:   # a plausible header with a random size and a real code
            noise = struct.pack(">HB", rng.choice([0, 2, 3, 4, 65535]), rng.choice(b"VvMOISPUR")) + noise
        for record in conversation.feed(noise, rng.random() < 0.5):
            urwire.to_json_line(record)
    for record in conversation.close():
        urwire.to_json_line(record)


def test_a_huge_size_waits_for_its_bytes_then_is_a_truncated_tail():
    conversation = rtde.Conversation()
    assert conversation.feed(struct.pack(">HB", 65535, ord("U")) + b"\0" * 100, True) == []
    (tail,) = conversation.close()
    assert urwire.to_dict(tail) == {"type": "error", "offset": 0,
                                    "error": "truncated message: 103 bytes at the end of the stream"}


def test_the_variable_table_has_labels_units_and_versions():
    q = rtde.variable("actual_q")
    assert (q.type, q.unit, q.label, q.since) == ("VECTOR6D", "rad", "Actual joint positions",
                                                  {"cb3": "3.3", "eseries": "5.0", "polyscope_x": "10.0"})
    assert rtde.variable("speed_slider_fraction", "input").type == "DOUBLE"
    assert all(v.type in generated.VALUE_TYPES for v in rtde.VARIABLES.rows)
    assert rtde.variable("no_such_thing") is None


def test_a_vector_variable_names_its_items_and_their_units():
    table = rtde.VARIABLES
    assert table["actual_q"].items == ("Base", "Shoulder", "Elbow", "Wrist 1", "Wrist 2", "Wrist 3")
    assert table["actual_q"].item_units == () and table["actual_q"].unit == "rad"
    assert table["actual_TCP_force"].items == ("Fx", "Fy", "Fz", "Tx", "Ty", "Tz")
    assert table["actual_TCP_force"].item_units == ("N", "N", "N", "Nm", "Nm", "Nm")
    assert table["timestamp"].items == () and table["robot_mode"].items == ()


def test_the_variable_table_is_a_mapping_by_name():
    """VARIABLES["actual_q"] is its row; a name in both directions (the input registers, which the
    robot sends back) is the row the robot sends, its input row being variable(name, "input"); every
    row stays in `rows`."""
    from collections.abc import Mapping

    table = rtde.VARIABLES
    assert isinstance(table, Mapping) and table["actual_q"] is rtde.variable("actual_q")
    assert "actual_q" in table and "no_such_thing" not in table and table.get("no_such_thing") is None
    both = table["input_int_register_24"]
    assert both.direction == "output" and rtde.variable("input_int_register_24", "input").direction == "input"
    assert table["speed_slider_fraction"].direction == "input"          # written by the client only
    assert list(table) == [name for name in dict.fromkeys(v.name for v in table.rows)]
    assert len(table.rows) == len({(v.name, v.direction) for v in table.rows}) > len(table)
    assert {(v.name, v.direction) for v in table.values()} | {(v.name, "input") for v in table.rows
                                                              if v.direction == "input"} == \
        {(v.name, v.direction) for v in table.rows}


def test_which_controllers_have_a_variable():
    """The first CB3 and e-Series versions decide; a variable whose first version no source gives
    is neither there nor missing."""
    upper = rtde.variable("output_int_register_24")
    assert (upper.available_in((3, 8)), upper.available_in((3, 9, 0)), upper.available_in((5, 2)),
            upper.available_in((5, 3))) == (False, True, False, True)
    assert rtde.variable("tool_output_mode").available_in((3, 15)) is False
    assert rtde.variable("tool_output_mode").available_in((5, 2)) is True
    assert rtde.variable("actual_q").available_in((3, 3)) is True
    assert rtde.variable("ft_raw_wrench").available_in((3, 15)) is False
    assert rtde.variable("ft_raw_wrench").available_in((5, 9)) is True
    assert rtde.variable("actual_current_window").available_in((5, 11)) is None


def test_a_capture_decodes_every_rtde_conversation_in_time_order(tmp_path):
    """`urwire decode CAPTURE`: each RTDE conversation of a capture (two clients here) is read in
    the order its segments crossed the wire, and gives the records of its vector, enveloped."""
    import json
    import subprocess
    import sys
    from pathlib import Path

    from tests.tools import capture
    from tests.tools.capture import Segment

    cases = {c.name: c for c in rtde_cases()}
    first, second = cases["protocol2_session"], cases["data_during_setup"]
    one = capture.session_frames([Segment(fr, d) for fr, d in first.messages], port=30004, client_port=51001)
    two = capture.session_frames([Segment(fr, d) for fr, d in second.messages], port=30004, client_port=51002)
    pcap = tmp_path / "two.pcap"
    capture.write(pcap, one + two)
    root = Path(__file__).resolve().parents[2]
    res = subprocess.run([sys.executable, "-m", "urwire", "decode", str(pcap)], capture_output=True, text=True,
                         env={"PYTHONPATH": f"{root / 'python'}:{root / 'generated' / 'python'}"}, timeout=60)
    assert res.returncode == 0, res.stderr
    by_conversation: dict = {}
    for line in res.stdout.splitlines():
        record = json.loads(line)
        assert record.pop("interface") == "rtde"
        direction = record.pop("direction")
        by_conversation.setdefault(record.pop("conversation"), []).append((direction, record))
    streams = list(by_conversation.values())
    assert [r for _, r in streams[0]] == first.expect
    assert [r for _, r in streams[1]] == second.expect
    assert [d for d, _ in streams[0]] == ["from_robot" if fr else "to_robot" for fr, _ in first.messages]


def test_any_recipe_reads_back_what_it_wrote():
    """Hypothesis: a recipe of any value types, any values of them: encode, then decode through a
    connection that set the recipe up, gives the same values and the same bytes."""
    from hypothesis import given, settings
    from hypothesis import strategies as st

    def value_of(type_name):
        vt = generated.VALUE_TYPES[type_name]
        bounds = {"B": (0, 255), "I": (0, 2**32 - 1), "Q": (0, 2**64 - 1), "i": (-2**31, 2**31 - 1)}
        one = (st.floats(width=64, allow_nan=False) if vt.kind == "float" else st.booleans() if vt.kind == "bool"
               else st.integers(*bounds[vt.code]))
        return st.lists(one, min_size=vt.count, max_size=vt.count) if vt.count > 1 else one

    recipes = st.lists(st.sampled_from(sorted(generated.VALUE_TYPES)), min_size=1, max_size=12).flatmap(
        lambda types: st.tuples(st.just(types), st.tuples(*[value_of(t) for t in types])))

    @settings(max_examples=150, deadline=None)
    @given(recipes, st.integers(1, 255))
    def check(recipe_values, recipe_id):
        types, values = recipe_values
        names = [f"v{i}" for i in range(len(types))]
        recipe = rtde.Recipe(recipe_id, "outputs", names, list(types), generated.VALUE_TYPES)
        message = generated.DataPackage(recipe_id, dict(zip(names, values))).encode(recipe)
        conversation = rtde.Conversation()
        conversation.recipes["outputs"][recipe_id] = recipe
        (record,) = conversation.feed(message, True)
        assert record.values == dict(zip(names, values))
        assert record.encode() == message

    check()


def _repeated_session():
    case = [c for c in rtde_cases() if c.name == "repeated_variable"][0]
    return case, python_records(case)


def test_a_name_given_twice_keeps_each_value():
    """Values of a recipe that names timestamp twice: by name the first (as C's rtde_data_find),
    each with all(), every one in order, and the record encodes back to its bytes."""
    case, records = _repeated_session()
    values = records[2].values
    assert values["timestamp"] == 1.5 and values.all("timestamp") == [1.5, 2.5]
    assert values.in_order() == [1.5, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0], 2.5]
    assert values.pairs()[2] == ("timestamp", 2.5) and list(values) == ["timestamp", "actual_q"]
    assert values != {"timestamp": 1.5, "actual_q": [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]}   # a dict holds one of them
    assert records[2].encode() == case.messages[2][1]
    assert records[5].encode() == case.messages[5][1]
    assert records[5].values.all("input_double_register_0") == [0.5, 0.75]


def test_values_without_a_repeat_are_a_mapping_by_name():
    case = [c for c in rtde_cases() if c.name == "protocol2_session"][0]
    package = [r for r in python_records(case) if r.NAME == "data_package"][0]
    assert dict(package.values) == {n: package.values[n] for n in package.values.names}
    assert package.values == dict(package.values) and len(package.values) == len(package.values.names)


def test_a_recipes_reader_is_a_loop_over_its_shapes():
    """Random recipes over random bytes: the reader a recipe compiles once gives what a loop over its
    types gives (a vector a list of its items, a bool byte 0 or 1 as False or True and 2 to 255 as
    the number); every package of the recipe finds a name by the recipe's one index."""
    from urwire._runtime import BOOL

    rng = random.Random(39)
    types = sorted(generated.VALUE_TYPES)
    for _ in range(200):
        chosen = [rng.choice(types) for _ in range(rng.randrange(1, 14))]
        names = [rng.choice(("a", "b", "c", "d", "e", "f", "g")) for _ in chosen]
        recipe = rtde.Recipe(1, "outputs", names, chosen, generated.VALUE_TYPES)
        body = bytes(rng.getrandbits(8) for _ in range(recipe.size + 2))
        values, end = recipe.decode(body, 1, len(body))
        expected, at = [], 1
        for t in chosen:
            shape = generated.VALUE_TYPES[t]
            items = list(struct.unpack_from(">" + shape.code * shape.count, body, at))
            at += shape.size
            expected.append(items if shape.count > 1 else BOOL[items[0]] if shape.kind == "bool" else items[0])
        assert values.in_order() == expected and end == at
        assert [type(v) for v in values.in_order()] == [type(v) for v in expected]
        assert {n: values[n] for n in names} == {n: expected[names.index(n)] for n in names}
        assert recipe.decode(body, 1, len(body))[0]._index is values._index is recipe.index
        with pytest.raises(urwire.DecodeError, match="values"):
            recipe.decode(body, 3, len(body))


def test_input_data_takes_a_dict_or_values_in_order():
    """input_data by name (a dict) or, for a recipe naming a variable twice, a Values in order."""
    recipe = rtde.Recipe(1, "inputs", ["input_double_register_0", "input_double_register_0"], ["DOUBLE", "DOUBLE"],
                         generated.VALUE_TYPES)
    two = rtde.input_data(recipe, rtde.Values(recipe.names, [0.5, 0.75]))
    assert two == bytes.fromhex("001455" "01" "3fe0000000000000" "3fe8000000000000")
    assert rtde.input_data(recipe, {"input_double_register_0": 0.5})[4:] == struct.pack(">dd", 0.5, 0.5)


def test_a_reply_paired_with_nothing_leaves_its_id_without_a_recipe():
    """Recipe 9 is set up (timestamp), then nine more setups: the ninth is not kept, and its reply,
    which gives id 9 again, makes none: recipe 9's data come out raw, never as timestamp."""
    c = rtde.Conversation(protocol=2)
    c.feed(rtde.setup_outputs(["timestamp"], 125.0), False)
    c.feed(struct.pack(">HBB", 10, ord("O"), 9) + b"DOUBLE", True)
    for k in range(9):
        c.feed(rtde.setup_outputs(["actual_q"], 125.0), False)
    replies = []
    for recipe_id in range(1, 10):
        replies += c.feed(struct.pack(">HBB", 12, ord("O"), recipe_id) + b"VECTOR6D", True)
    assert "error" in replies[-1].notes and 9 not in c.recipes["outputs"]
    package = c.feed(struct.pack(">HBBd", 12, ord("U"), 9, 1.0), True)[0]
    assert urwire.to_dict(package)["error"] == "data package of a recipe this connection did not set up"
