"""One message shows at most MAX_TREE_ITEMS items in Wireshark's tree; an expert note says how
many more it holds. Past the cap the values are still read: an error after them still shows."""
from __future__ import annotations

import re
import struct
import xml.etree.ElementTree as ET

from tests.lua.harness import run_tshark
from tests.tools import capture

from codegen.kinds.packages.dissector import MAX_TREE_ITEMS

LIST, INT = 17, 15   # value type codes from software 5.9 (the default with no Version message)
HEADER_FIELDS = {"ur.length", "ur.type"}   # the message's header, outside the cap


def update(values: bytes) -> bytes:
    """A global variables update: timestamp, subtype 1, start index 0, then the values."""
    body = struct.pack(">QBH", 7, 1, 0) + values
    return struct.pack(">iB", 5 + len(body), 25) + body


def int_list(n: int) -> bytes:
    """One value: a LIST of n INTs (0, 1, ...), then the terminator."""
    items = b"".join(struct.pack(">Bi", INT, i) for i in range(n))
    return struct.pack(">Bh", LIST, n) + items + b"\x0a"


def tree(tmp_path, name: str, message: bytes) -> tuple[int, list[str]]:
    """The items under the message's `ur` item (header and expert items aside), and its
    expert texts."""
    pcap = capture.write(tmp_path / f"{name}.pcap", capture.robot_session([message]))
    pdml = ET.fromstring(run_tshark(pcap, "-T", "pdml", "-Y", "ur"))
    (ur,) = [p for p in pdml.iter("proto") if p.get("name") == "ur"]
    items, experts = 0, []

    def walk(node):
        nonlocal items
        for f in node.findall("field"):
            name = f.get("name")
            if name == "_ws.expert":
                experts.append(f.find("field[@name='_ws.expert.message']").get("show"))
                continue
            if name not in HEADER_FIELDS:
                items += 1
            walk(f)

    walk(ur)
    return items, experts


def test_a_message_shows_at_most_the_cap_and_says_how_many_more(tmp_path):
    # Items per INT of the list, and the rest, from two small messages the cap leaves whole.
    two, _ = tree(tmp_path, "two", update(int_list(2)))
    three, _ = tree(tmp_path, "three", update(int_list(3)))
    per_int, rest = three - two, two - 2 * (three - two)
    n = 3000
    total = rest + n * per_int
    assert total > MAX_TREE_ITEMS
    shown, experts = tree(tmp_path, "big", update(int_list(n)))
    assert shown == MAX_TREE_ITEMS
    assert f"{total - MAX_TREE_ITEMS} more items not shown (a message shows at most {MAX_TREE_ITEMS})" in experts


def test_an_error_past_the_cap_still_shows(tmp_path):
    n = 3000
    values = int_list(n) + bytes([99])   # then a value of an unknown type
    offset = 5 + 11 + len(int_list(n))
    _, experts = tree(tmp_path, "bad", update(values))
    assert f"global_variables_update: variables[1].type at offset {offset}: unknown value type 99" in experts
    assert any(re.fullmatch(r"\d+ more items not shown .*", e) for e in experts)
