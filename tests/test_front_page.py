"""The README stays a front page a newcomer reads in five minutes: at most 250 lines, no line
wider than 160 characters (nor in docs/benchmarks.md, where the speed tables went), the two
commands of a fresh machine exactly as the Makefile and CI run them, and every link and `make`
target it names real."""
import re
from pathlib import Path

from tests.codegen.test_knowledge import anchors

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
MAX_LINES = 250
MAX_WIDTH = 160
TWO_COMMANDS = "make demo   #", "make test   #"


def readme() -> str:
    return README.read_text(encoding="utf-8")


def make_targets() -> set[str]:
    rules = [ROOT / "Makefile", *sorted((ROOT / "mk").glob("*.mk"))]
    return {name for path in rules
            for name in re.findall(r"^([A-Za-z0-9_.-]+)\s*:(?!=)", path.read_text(encoding="utf-8"), re.M)}


def test_the_readme_is_short():
    assert len(readme().splitlines()) <= MAX_LINES


def test_no_line_of_the_readme_or_the_benchmarks_is_too_wide():
    wide = [f"{path.relative_to(ROOT)}:{n}: {len(line)}"
            for path in (README, ROOT / "docs" / "benchmarks.md")
            for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
            if len(line) > MAX_WIDTH]
    assert wide == []


def test_the_two_commands_are_shown_and_run_by_make_and_ci():
    section = readme().split("## Two commands", 1)[1].split("\n## ", 1)[0]
    block = section.split("```sh\n", 1)[1].split("```", 1)[0].splitlines()
    assert [line[:len(TWO_COMMANDS[0])] for line in block] == list(TWO_COMMANDS)
    assert {"demo", "test", "setup"} <= make_targets()
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    assert "bash scripts/setup.sh" in ci and "make test" in ci


def test_every_make_target_the_readme_names_exists():
    named = set(re.findall(r"`?make ([a-z][a-z0-9-]*)", readme())) - {"it"}
    assert named, "the README names no make target"
    assert sorted(named - make_targets()) == []


def test_every_link_of_the_readme_lands():
    broken = []
    for target, anchor in re.findall(r"\]\(([^)#\s]+)(?:#([A-Za-z0-9_-]+))?\)", readme()):
        path = ROOT / target
        if not path.exists() or (anchor and anchor not in anchors(path)):
            broken.append(f"{target}#{anchor}" if anchor else target)
    assert broken == []
