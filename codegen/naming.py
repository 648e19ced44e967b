"""Naming rules, in one place: how spec names become identifiers in each target."""
from __future__ import annotations

from . import ir


def camel(name: str) -> str:
    """robot_mode_data -> RobotModeData"""
    return "".join(part[:1].upper() + part[1:] for part in name.split("_"))


def words(name: str) -> str:
    """robot_mode_data -> Robot mode data (labels for humans and Wireshark)."""
    text = name.replace("_", " ")
    return text[:1].upper() + text[1:]


def py_enum_class(enum: ir.Enum) -> str:
    return camel(enum.name)


def table_suffix(table: ir.EnumTable) -> str:
    """The versions of an enum table as an identifier part: UpTo3_2, 3_3To5_8, 5_25_1On."""
    r = table.versions
    low = ir.version_text(r.low).replace(".", "_") if r.low else ""
    high = ir.version_text(r.high).replace(".", "_") if r.high else ""
    if low and high:
        return f"{low}To{high}"
    return f"{low}On" if low else f"UpTo{high}"


def py_table_class(enum: ir.Enum, table: ir.EnumTable) -> str:
    """One IntEnum per version table. The newest keeps the plain name (RobotMode), so code
    written for today's controllers reads the same; older ones say their versions
    (RobotModeUpTo1_8, ValueType3_3To5_8)."""
    if table is enum.tables[-1]:
        return camel(enum.name)
    return camel(enum.name) + table_suffix(table)


def py_lookup(enum: ir.Enum) -> str:
    """Module constant mapping wire values to enum members."""
    return f"{enum.name.upper()}_BY_VALUE"


def py_layout_class(layout: ir.Layout, in_dispatch: bool) -> str:
    """Sub-packages keep their name; whole messages end in Message (VersionMessage)."""
    base = camel(layout.name)
    return base + "Message" if in_dispatch and not base.endswith("Message") else base


def py_message_class(message: ir.Message) -> str:
    return camel(message.name) + "Message"


def py_item_class(group: ir.GroupField) -> str:
    return camel(group.item.name)


def wireshark_field(owner: str, name: str) -> str:
    return f"ur.{owner}.{name}"
