"""Fields with a version range are read only for streams of those versions, in generated code.

The real spec's layouts agree for 5.9 and 5.10, so this renders a variant of it with one
gated field into a scratch package and decodes the same bytes under two versions.
"""
from __future__ import annotations

import importlib
import struct
import sys

import yaml

from codegen.kinds.packages.plan import plan
from codegen.compile import DEFAULT_SPEC, compile_file, compile_text, kind_of, spec_files
from codegen.load import load_file
from codegen.kinds.packages import python as python_target


def render_variant(tmp_path, edit):
    data = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))
    edit(data)
    protocol = compile_text(yaml.safe_dump(data, sort_keys=False))
    outputs = python_target.render(plan(protocol), ["test build"])
    # The other interfaces' modules as the specs make them: the package imports them (interfaces.py).
    for spec in spec_files():
        if spec != DEFAULT_SPEC:
            outputs.update(kind_of(load_file(spec)).render(compile_file(spec), ["test build"], ["python"]))
    for rel, text in outputs.items():
        path = tmp_path / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return tmp_path / "python"


def add_gated_field(data):
    fields = data["messages"]["robot_state"]["packages"]["tool_mode_info"]["fields"]
    fields.append({"name": "gated_flag", "label": "Gated flag", "type": "uint16", "versions": {"from": "5.12", "through": "PolyScope X"}})


def robot_state(body: bytes) -> bytes:
    pkg = struct.pack(">iB", 5 + len(body), 12) + body
    return struct.pack(">iB", 5 + len(pkg), 16) + pkg


def test_a_gated_field_follows_the_version_and_else_the_length(tmp_path):
    """docs/contract.md#choosing-a-layout: the version's layout when it fits the declared length; else the one layout
    whose size equals it; else the version's layout with its short or extra bytes."""
    root = render_variant(tmp_path, add_gated_field)
    saved = {k: v for k, v in sys.modules.items() if k == "urwire" or k.startswith("urwire.")}
    for k in saved:
        del sys.modules[k]
    sys.path.insert(0, str(root))
    try:
        variant = importlib.import_module("urwire")
        long = robot_state(bytes([1, 0, 1]) + struct.pack(">H", 0xBEEF))
        short = robot_state(bytes([1, 0, 1]))
        neither = robot_state(bytes([1, 0, 1, 7]))

        (new,) = variant.decode_stream(long, "5.12")
        assert new.packages[0].gated_flag == 0xBEEF and new.packages[0].extra == b""
        (by_length,) = variant.decode_stream(long, "5.9")        # 5.9's 3 bytes do not fit: 5.12's do
        assert by_length.packages[0].gated_flag == 0xBEEF and by_length.packages[0].decoded_version == (5, 12, 0)
        (old,) = variant.decode_stream(short, "5.9")
        assert old.packages[0].gated_flag is None and "gated_flag" not in variant.to_dict(old)["packages"][0]
        (old_by_length,) = variant.decode_stream(short, "5.12")
        assert old_by_length.packages[0].gated_flag is None and old_by_length.packages[0].extra == b""
        (extra,) = variant.decode_stream(neither, "5.9")         # fits no layout: 5.9's, one extra byte
        assert extra.packages[0].gated_flag is None and extra.packages[0].extra == b"\x07"
        for msg, record in ((long, new), (long, by_length), (short, old), (short, old_by_length), (neither, extra)):
            assert record.encode() == msg
    finally:
        sys.path.remove(str(root))
        for k in [k for k in sys.modules if k == "urwire" or k.startswith("urwire.")]:
            del sys.modules[k]
        sys.modules.update(saved)


def test_enum_members_carry_their_version_range():
    protocol = compile_text(DEFAULT_SPEC.read_text(encoding="utf-8"))
    laser, kinematics = (protocol.enums["package_type"].member(n) for n in ("LASER_POINTER", "KINEMATICS_INFO"))
    assert laser.value == kinematics.value == 5
    assert laser.versions.describe() == "up to 1.7" and kinematics.versions.describe() == "1.8 and later"
    by_table = [{v.name for v in t.values} for t in protocol.enums["package_type"].tables]
    assert [t.versions.describe() for t in protocol.enums["package_type"].tables] == ["up to 1.7", "1.8 and later"]
    assert "LASER_POINTER" in by_table[0] and "KINEMATICS_INFO" in by_table[1]
    modes = protocol.enums["robot_mode"]
    assert modes.table_for((1, 8, 3)).values[0].name != modes.table_for((3, 0, 0)).values[0].name
    tables = protocol.enums["value_type"].tables
    assert [t.versions.describe() for t in tables] == ["up to 3.2", "3.3 to 5.8", "5.9 and later"]
    assert protocol.enums["value_type"].table_for((5, 10, 0)) is tables[2]
    assert protocol.enums["value_type"].table_for((5, 4, 2)) is tables[1]
    assert protocol.enums["value_type"].table_for((5, 8, 7)) is tables[1]   # "until 5.8" takes every 5.8.x
