"""Start a new software version's golden robot-state vectors from the newest ones of its series.

    python3 scripts/new_vector.py 5.27                 (make new-vector VERSION=5.27)
    python3 scripts/new_vector.py 5.27 --from tests/golden/generation_eseries_5_25_1_robot_state.yaml

The series is the one of `protocol.generations` in spec/ur_primary.yaml that holds the new version.
Its newest vectors older than the new version (generation_<series>_<version>_robot_state*.yaml,
the euromap67 variant too) are copied under the new version's name, and in each copy the Version
message's major, minor and bugfix numbers are set to the new version: the bytes, their comments and
the expected record. Nothing else changes, so each copy still describes the older layout. It opens
with a `TODO: check` line, and its description carries one too: tests/vectors.py refuses a file
that holds one, so a copy cannot pass as a vector until someone has laid out the new version's
bytes and values by hand (tests/golden/README.md) and deleted both. urwire's own code never writes
a byte of it.
"""
from __future__ import annotations

import argparse
import re
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from codegen import ir  # noqa: E402
from codegen.compile import DEFAULT_SPEC, compile_file  # noqa: E402
from tests.vectors import GOLDEN_DIR, UNCHECKED  # noqa: E402

NAME = re.compile(r"generation_(?P<series>[a-z][a-z0-9_]*?)_(?P<version>\d+(?:_\d+)+)_robot_state(?P<variant>.*)\.yaml")
# The Version message's numbers, as the vectors annotate them: `05   # major_version = 5`.
NUMBERS = ("major_version", "minor_version", "bugfix_version")


class ScaffoldError(Exception):
    """Why no scaffold was written."""


@dataclass(frozen=True)
class Vector:
    path: Path
    series: str            # the file name's series, e.g. "eseries"
    version: ir.Version    # the file name's version
    variant: str           # "" or e.g. "_euromap67"

    @classmethod
    def of(cls, path: Path) -> "Vector | None":
        m = NAME.fullmatch(path.name)
        if not m:
            return None
        return cls(path, m["series"], ir.parse_version(m["version"].replace("_", ".")), m["variant"])


def series_of(version: ir.Version, generations) -> str:
    for name, versions in generations:
        if versions.contains(version):
            return name
    raise ScaffoldError(f"{ir.version_text(version)} is in no series of protocol.generations in the primary spec")


def sources(version: ir.Version, golden: Path, generations) -> list[Vector]:
    """The newest robot-state vectors of the new version's series that are older than it."""
    series = series_of(version, generations)
    vectors = [v for v in map(Vector.of, sorted(golden.glob("generation_*.yaml")))
               if v and v.version < version and series_of(v.version, generations) == series]
    if not vectors:
        raise ScaffoldError(f"no generation_*_robot_state vector of {series} older than "
                            f"{ir.version_text(version)}: name one with --from")
    newest = max(v.version for v in vectors)
    return [v for v in vectors if v.version == newest]


def target_path(source: Vector, version: ir.Version) -> Path:
    name = ir.version_text(version).replace(".", "_")
    return source.path.with_name(f"generation_{source.series}_{name}_robot_state{source.variant}.yaml")


def retarget(text: str, version: ir.Version, source_name: str) -> str:
    """The source's text with the new version's numbers in its Version message, and the marks."""
    numbers = dict(zip(NUMBERS, version))
    hex_part, sep, expect_part = text.partition("\nexpect:")
    if not sep:
        raise ScaffoldError(f"{source_name}: no 'expect:'")
    for name, value in numbers.items():
        hex_part = _set_hex_line(hex_part, name, value, source_name)
        expect_part = _set_expected(expect_part, name, value, source_name)
    return _marked(hex_part + sep + expect_part, version, source_name)


def _set_hex_line(text: str, name: str, value: int, source_name: str) -> str:
    line = re.compile(rf"^(?P<indent>\s*)(?P<hex>[0-9a-fA-F]{{2}}(?: [0-9a-fA-F]{{2}})*)(?P<pad>\s+)"
                      rf"# {name} = \d+$", re.M)
    found = list(line.finditer(text))
    if not found:
        if name == "bugfix_version" and value == 0:
            return text     # the svn-form Version message (up to 3.2) has no bugfix number
        raise ScaffoldError(f"{source_name}: no '# {name} = ' line in its Version message to set to {value}")
    m = found[0]   # the first message of the stream is its Version message
    width = len(m["hex"].split())
    if value >= 1 << (8 * width):
        raise ScaffoldError(f"{source_name}: {name} {value} does not fit in {width} byte(s)")
    new_hex = " ".join(f"{b:02x}" for b in value.to_bytes(width, "big"))
    pad = " " * (len(m["hex"]) + len(m["pad"]) - len(new_hex))
    return text[:m.start()] + f"{m['indent']}{new_hex}{pad}# {name} = {value}" + text[m.end():]


def _set_expected(text: str, name: str, value: int, source_name: str) -> str:
    line = re.compile(rf"^(?P<indent>\s+){name}: \d+$", re.M)
    m = line.search(text)
    if not m:
        if name == "bugfix_version" and value == 0:
            return text
        raise ScaffoldError(f"{source_name}: no '{name}:' in the expected Version record")
    return text[:m.start()] + f"{m['indent']}{name}: {value}" + text[m.end():]


def _marked(text: str, version: ir.Version, source_name: str) -> str:
    new = ir.version_text(version)
    text = re.sub(r'^description: "(.*)"$',
                  lambda m: f'description: "{UNCHECKED}: say what {new} changed. Was: {m[1]}"',
                  text, count=1, flags=re.M)
    head = (f"# {UNCHECKED}: scaffolded by scripts/new_vector.py from {source_name}.\n"
            f"# Only the Version message's numbers are {new}'s; the rest is the older layout. Lay out\n"
            f"# what {new} changed by hand (the new fields' bytes, each messageSize and packageSize, the\n"
            f"# byte count below, the expected records, description and source), then delete this comment.\n")
    return head + text


def scaffold(version_text: str, golden: Path = GOLDEN_DIR, spec: Path = DEFAULT_SPEC,
             source: Path | None = None) -> list[Path]:
    """Write the scaffolds; return their paths. Nothing is written if any target exists."""
    version = ir.parse_version(version_text)
    if source is None:
        chosen = sources(version, golden, compile_file(spec).generations)
    else:
        one = Vector.of(source)
        if one is None:
            raise ScaffoldError(f"{source}: not a generation_<series>_<version>_robot_state*.yaml vector")
        chosen = [one]
    plan = [(v, target_path(v, version)) for v in chosen]
    existing = [str(t) for _, t in plan if t.exists()]
    if existing:
        raise ScaffoldError(f"already there, not overwritten: {', '.join(existing)}")
    texts = [(t, retarget(v.path.read_text(encoding="utf-8"), version, v.path.name)) for v, t in plan]
    for target, text in texts:
        target.write_text(text, encoding="utf-8")
    return [t for t, _ in texts]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="scripts/new_vector.py", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("version", help='the new software version, e.g. 5.27 or 5.27.1')
    parser.add_argument("--from", dest="source", type=Path,
                        help="start from this vector instead of the newest of the series")
    parser.add_argument("--golden", type=Path, default=GOLDEN_DIR, help=argparse.SUPPRESS)
    parser.add_argument("--spec", type=Path, default=DEFAULT_SPEC, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if not re.fullmatch(r"\d+\.\d+(\.\d+)?", args.version):
        parser.error(f"{args.version!r}: give the version as major.minor or major.minor.bugfix")
    try:
        written = scaffold(args.version, args.golden, args.spec, args.source)
    except ScaffoldError as exc:
        print(f"new_vector: {exc}", file=sys.stderr)
        return 2
    for path in written:
        print(f"{path}: to check by hand (its '{UNCHECKED}' lines say what)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
