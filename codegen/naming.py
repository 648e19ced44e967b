"""Naming rules every kind shares: spec names as words and as column names. Class names are
codegen/lang/python.py's; a kind's own names for its identifiers live in the kind
(kinds/packages/naming.py)."""
from __future__ import annotations


def words(name: str) -> str:
    """robot_mode_data -> Robot mode data (labels for humans and Wireshark)."""
    text = name.replace("_", " ")
    return text[:1].upper() + text[1:]


def column_name(protocol: str) -> str:
    """What Wireshark's Protocol column shows for an interface: its name in words, with UR and
    RTDE in capitals and Robotiq a name (ur_script_command -> "UR script command")."""
    return " ".join(w.upper() if w in ("ur", "rtde") else w.capitalize() if w == "robotiq" else w
                    for w in protocol.split("_"))
