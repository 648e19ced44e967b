"""Versions read as versions wherever a generated file or the reference names them: "1.5 to 1.8",
"5.25.1 and later", "up to 3.1", never a bugfix sentinel (999, 1000) or a tuple."""
import re
from pathlib import Path

import pytest

from codegen import ir

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("low, high, first, text", [
    ((1, 5, 0), (1, 8, ir.BUGFIX_ANY), None, "1.5 to 1.8"),
    ((5, 0, 0), (5, 0, ir.BUGFIX_ANY), None, "5.0"),
    ((5, 25, 1), None, None, "5.25.1 and later"),
    (None, (3, 1, ir.BUGFIX_ANY), None, "up to 3.1"),
    ((0, 0, 0), (3, 1, ir.BUGFIX_ANY), (0, 0, 0), "up to 3.1"),
    ((3, 0, 0), (5, 25, 0), None, "3.0 to 5.25.0"),
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
