"""The primary interface's naming rules, in one place: how its spec names become identifiers in
each target (C enum constants, Python classes, Wireshark filter names) and labels."""
from __future__ import annotations

from ... import ir
from ...lang.python import class_name
from ...naming import words
from . import model


def layout_label(layout: model.Layout) -> str:
    """What people read for a layout in every output: its label, else its name in words, then its
    marks ("Payload info (undocumented, inferred)")."""
    text = layout.label or words(layout.name)
    return f"{text} ({', '.join(layout.marks)})" if layout.marks else text


def py_enum_class(enum: ir.Enum) -> str:
    return class_name(enum.name)


def _table_bounds(table: ir.EnumTable) -> tuple[str, str]:
    """The bounds of an enum table's versions as identifier parts: ("3_3", "5_8"), ("", "3_2")."""
    r = table.versions
    low = ir.version_text(r.low).replace(".", "_") if r.low else ""
    high = ir.version_text(r.high).replace(".", "_") if r.high else ""
    return low, high


def table_suffix(table: ir.EnumTable) -> str:
    """The versions of an enum table as an identifier part: UpTo3_2, 3_3To5_8, 5_25_1On."""
    low, high = _table_bounds(table)
    if low and high:
        return f"{low}To{high}"
    return f"{low}On" if low else f"UpTo{high}"


def c_table_suffix(table: ir.EnumTable) -> str:
    """table_suffix in C's spelling: UP_TO_3_2, 3_3_TO_5_8, 5_25_1_ON."""
    low, high = _table_bounds(table)
    if low and high:
        return f"{low}_TO_{high}"
    return f"{low}_ON" if low else f"UP_TO_{high}"


def c_enum_tag(enum: ir.Enum, table: ir.EnumTable) -> str:
    """The C enum of one table. As in Python, the newest table keeps the plain name
    (urwire_robot_mode) and older ones say their versions (urwire_robot_mode_up_to_1_8)."""
    if table is enum.tables[-1]:
        return f"urwire_{enum.name}"
    return f"urwire_{enum.name}_{c_table_suffix(table).lower()}"


def c_enum_prefix(enum: ir.Enum, table: ir.EnumTable) -> str:
    """The prefix of a table's constants: URWIRE_ROBOT_MODE, URWIRE_ROBOT_MODE_UP_TO_1_8."""
    return c_enum_tag(enum, table).upper()


def c_enum_const(enum: ir.Enum, value: int) -> str:
    """The constant naming a wire value: in the newest table that holds it."""
    for table in reversed(enum.tables):
        for v in table.values:
            if v.value == value:
                return f"{c_enum_prefix(enum, table)}_{v.name}"
    raise KeyError(f"{enum.name} has no value {value}")


def c_member_const(enum: ir.Enum, member: ir.EnumValue) -> str:
    """The constant of one member (a layout's code): in the newest table that has it."""
    for table in reversed(enum.tables):
        for v in table.values:
            if v.name == member.name and v.value == member.value:
                return f"{c_enum_prefix(enum, table)}_{v.name}"
    raise KeyError(f"{enum.name} has no member {member.name}")


def py_table_class(enum: ir.Enum, table: ir.EnumTable) -> str:
    """One IntEnum per version table. The newest keeps the plain name (RobotMode), so code
    written for today's controllers reads the same; older ones say their versions
    (RobotModeUpTo1_8, ValueType3_3To5_8)."""
    if table is enum.tables[-1]:
        return class_name(enum.name)
    return class_name(enum.name) + table_suffix(table)


def py_lookup(enum: ir.Enum) -> str:
    """Module constant mapping wire values to enum members."""
    return f"{enum.name.upper()}_BY_VALUE"


def py_layout_class(layout: model.Layout, in_dispatch: bool) -> str:
    """Sub-packages keep their name; whole messages end in Message (VersionMessage)."""
    base = class_name(layout.name)
    return base + "Message" if in_dispatch and not base.endswith("Message") else base


def py_message_class(message: model.Message) -> str:
    return class_name(message.name) + "Message"


def py_item_class(group: ir.GroupField) -> str:
    return class_name(group.item.name)


def wireshark_field(owner: str, name: str) -> str:
    return f"ur.{owner}.{name}"
