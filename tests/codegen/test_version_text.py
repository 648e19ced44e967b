"""Versions read as versions wherever a generated file or the reference names them: "1.5 to 1.8",
"5.25.1 and later", "up to 3.1", never a bugfix sentinel (999, 1000) or a tuple."""
import re
from pathlib import Path

import pytest

from codegen import ir
from codegen.compile import compile_text
from codegen.kinds import KINDS
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages.reference import protocol_markdown
from tests.codegen.test_series import with_field

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("low, high, first, text", [
    ((1, 5, 0), (1, 8, ir.BUGFIX_ANY), None, "1.5 to 1.8"),
    ((5, 0, 0), (5, 0, ir.BUGFIX_ANY), None, "5.0"),
    ((5, 25, 1), None, None, "5.25.1 and later"),
    (None, (3, 1, ir.BUGFIX_ANY), None, "up to 3.1"),
    ((0, 0, 0), (3, 1, ir.BUGFIX_ANY), (0, 0, 0), "up to 3.1"),
    ((3, 0, 0), (5, 25, 0), None, "3.0 to 5.25.0"),
    ((10, 100, 0), None, None, "after 10.99"),             # past "until: 10.99", no 10.100
    ((5, 100, 0), (9, 9, ir.BUGFIX_ANY), None, "after 5.99, up to 9.9"),
    (None, None, None, "all versions"),
])
def test_a_range_reads_as_versions(low, high, first, text):
    assert ir.VersionRange(low, high).describe(first) == text


SENTINEL = re.compile(r"\b\d+\.\d+\.(999|1000)\b|\(\d+, \d+, \d+\) to \(|\b(\d+\.\d+) to \2\b")


def test_no_generated_text_names_a_sentinel_version():
    # Only comments and texts are searched: the code compares versions as numbers or tuples.
    for path in [*sorted((ROOT / "generated").rglob("*.*")), ROOT / "docs/protocol.md"]:
        if path.suffix not in (".py", ".c", ".h", ".lua", ".md"):
            continue
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            prose = re.split(r"/\*|\*|--|#|\"", line, maxsplit=1)[1:]
            assert not (prose and SENTINEL.search(prose[0])), f"{path.relative_to(ROOT)}:{n}: {line.strip()}"


def test_a_range_ending_at_a_last_minor_is_followed_by_no_made_up_version():
    # A PolyScope X field "until: 10.99": what follows is every later version, not a "10.100".
    protocol = compile_text(with_field({"from": "10.0", "until": "10.99"}))
    planned = plan(protocol)
    assert [s.describe() for s in planned.segments][-2:] == ["10.0 to 10.99", "after 10.99"]
    texts = [protocol_markdown(planned, "made-up.yaml"),
             *KINDS["packages"].render(protocol, ["made-up"]).values()]
    prose = [line for text in texts for line in text.splitlines() if "10.99" in line]
    assert any("after 10.99" in line for line in prose)
    # Only the Lua table of segment starts may hold it, as the key "10.100" the runtime compares.
    assert not [line for text in texts for line in text.splitlines()
                if re.search(r"\b10\.100\b", line) and '"10.100"' not in line]
