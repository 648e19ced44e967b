"""The epan target of the typed-messages kind (codegen/kinds/typed_messages/epan.py): what the
runtime relies on in the tables of generated/epan/packet-rtde.c. (The filter names it would refuse
are refused by the kind's resolver: tests/codegen/test_rtde_filter_names.py.)"""
from __future__ import annotations

import re

from codegen.compile import SPEC_DIR, compile_text
from codegen.emit import banner_lines
from codegen.kinds.typed_messages import epan
from codegen.kinds.typed_messages.plan import plan

SPEC = SPEC_DIR / "rtde.yaml"
TEXT = SPEC.read_text(encoding="utf-8")


def rendered(text: str = TEXT) -> str:
    files = epan.render(plan(compile_text(text, str(SPEC))), banner_lines("spec/rtde.yaml", text))
    assert list(files) == ["epan/packet-rtde.c"]
    return files["epan/packet-rtde.c"]


def _table(source: str, name: str) -> str:
    return source.split(f"{name}[] = {{", 1)[1].split("\n};", 1)[0]


def test_the_variable_table_is_sorted_as_the_binary_search_compares():
    """runtime/epan/typed_messages/rtde_state.c finds a recipe's names by a binary search over memcmp: the table
    must be in byte order, hold every variable once, and each row name its own field."""
    source = rendered()
    rows = re.findall(r'\{ "([^"]+)", RTDE_HF_([A-Z0-9_]+), ', _table(source, "rtde_variables"))
    names = [name for name, _ in rows]
    assert len(names) > 400 and len(set(names)) == len(names)
    assert names == sorted(names, key=lambda n: n.encode())
    # A vector whose items the spec names points at its first item's field, the others after it.
    assert all(field in (name.upper(), f"{name.upper()}_0") for name, field in rows)
    assert ("actual_q", "ACTUAL_Q_0") in rows and ("timestamp", "TIMESTAMP") in rows
    assert {"actual_q", "input_int_register_24", "timestamp"} <= set(names)


def test_every_layout_is_reachable_by_code_direction_and_protocol():
    """rtde_layout_of holds 1 + each layout's index exactly once."""
    source = rendered()
    layouts = _table(source, "rtde_layouts").count('{ "')
    entries = [int(n) for n in re.findall(r"\d+", " ".join(
        line.split("=", 1)[1].split("/*")[0] for line in source.split("rtde_layout_of[256]", 1)[1]
        .split("\n};", 1)[0].splitlines()[1:]))]
    assert sorted(n for n in entries if n) == list(range(1, layouts + 1))
