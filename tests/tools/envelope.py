"""What a record decoded from a capture carries beyond the same record of a raw stream: the
envelope that names its interface, direction and conversation (docs/canonical-json.md#records-of-a-capture)."""
from __future__ import annotations

ENVELOPE = ("interface", "direction", "conversation")


def bare(record: dict) -> dict:
    """A capture's record as a raw stream of its interface prints it: its envelope taken off."""
    return {key: value for key, value in record.items() if key not in ENVELOPE}


def where(record: dict) -> tuple:
    """(interface, direction, conversation) of a capture's record."""
    return tuple(record[key] for key in ENVELOPE)
