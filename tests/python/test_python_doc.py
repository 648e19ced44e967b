"""docs/python.md#reading-a-capture-of-a-cell shows what Python users do with a capture of a cell:
each of its Python blocks runs on the bundled capture and prints what the text block after it says.
Every class a record of an interface is made of says what it is in a docstring."""
from __future__ import annotations

import inspect
import re
import subprocess
import sys
from pathlib import Path

import pytest
import urwire

ROOT = Path(__file__).resolve().parents[2]
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
SECTION = "## Reading a capture of a cell"


def examples() -> list[tuple[str, str]]:
    """(Python block, the text block after it) of the section, in order."""
    text = (ROOT / "docs" / "python.md").read_text(encoding="utf-8")
    section = text.split(SECTION + "\n", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```(python|text)\n(.*?)```", section, re.S)
    assert [kind for kind, _ in blocks] == ["python", "text"] * (len(blocks) // 2)
    return [(blocks[i][1], blocks[i + 1][1]) for i in range(0, len(blocks), 2)]


EXAMPLES = examples()


def test_the_section_shows_the_three_things_users_do():
    assert len(EXAMPLES) == 3
    assert [("decode_capture" in code, "DataPackage" in code, "RobotStateMessage" in code)
            for code, _ in EXAMPLES] == [(True, False, False), (True, True, False), (True, False, True)]


@pytest.mark.parametrize("code, printed", EXAMPLES, ids=["iterate", "rtde_series", "one_robots_states"])
def test_each_example_prints_what_the_doc_says(code, printed):
    res = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=ENV, capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert res.stdout == printed


def _record_classes() -> list[type]:
    from urwire import realtime, typed_records
    from urwire.generated import (rtde, ur_dashboard, ur_realtime, ur_reverse, ur_script_command, ur_script_sender,
                                  ur_trajectory, messages)

    modules = (messages, ur_realtime, rtde, ur_dashboard, ur_reverse, ur_script_sender, ur_trajectory,
               ur_script_command, realtime, typed_records)
    found = [c for m in modules for c in vars(m).values()
             if inspect.isclass(c) and c.__module__ == m.__name__ and hasattr(c, "JSON")]
    return found + [urwire.Enveloped, urwire.Endpoints, urwire.CaptureRecords, urwire.StreamError]


def test_every_record_class_says_what_it_is():
    classes = _record_classes()
    assert len(classes) > 40
    # A dataclass without a docstring gets its signature as one: "Reply(reply: str, ...)".
    undocumented = [c.__qualname__ for c in classes if not c.__doc__ or c.__doc__.startswith(c.__name__ + "(")]
    assert undocumented == []


def test_the_package_says_it_is_typed():
    assert (Path(urwire.__file__).parent / "py.typed").is_file()
