"""The C parser's compile-time options (docs/c.md, "Options for a firmware"): built with
URWIRE_NO_NAMES and URWIRE_NO_FAST_PATHS (at -Os, as a firmware is), the library decodes every
vector to the records the default build gives, an error's field path aside: its status, offset
and numbers are the same. Without its fast paths, the one-pass robot-state decoder still agrees
with the iterator member by member (the driver's roundtrip)."""
from __future__ import annotations

import json

import pytest

from tests.c.harness_c import GEN, OPTION_VARIANTS, OUT, CommandPeer, compile_c, get_build, parse_lines, run_cli
from tests.c.seeds import messages
from tests.vectors import all_cases

CASES = all_cases()
AT = " at offset "


@pytest.fixture(scope="module")
def small():
    return get_build("small-gcc")


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_the_options_compile_clean(cc):
    """Under the strict flags, as the default build does (compile_c fails on any warning)."""
    _, flags = OPTION_VARIANTS["small-gcc"]
    compile_c(cc, [*flags, "-c"], [GEN / "urwire.c"], OUT / "options" / f"urwire-{cc}.o")


def without_paths(value):
    """A record with each error text cut to what follows its path ("... at offset 17: ...")."""
    if isinstance(value, dict):
        return {k: (v.partition(AT)[2] if k == "error" and isinstance(v, str) and AT in v else without_paths(v))
                for k, v in value.items()}
    if isinstance(value, list):
        return [without_paths(v) for v in value]
    return value


@pytest.mark.parametrize("hint", sorted({c.version for c in CASES if c.version}) + [None])
def test_the_options_change_no_record_but_the_error_paths(small, fast, hint):
    data = b"".join(c.data for c in CASES if c.version == hint)
    args = ["--version-hint", hint] if hint else []
    mine, default = run_cli(small, data, *args), run_cli(fast, data, *args)
    assert mine.returncode == default.returncode and mine.stderr == b""
    records, expected = parse_lines(mine.stdout), parse_lines(default.stdout)
    assert [without_paths(r) for r in records] == [without_paths(r) for r in expected]


def test_the_option_build_names_no_field(small, fast):
    """The vectors hold errors inside fields; the default build names them, this one does not
    (a sub-package's framing is "package" in the text alone, as in every build)."""
    data = b"".join(c.data for c in CASES if c.version is None)
    texts = [line for line in run_cli(fast, data).stdout.decode().splitlines() if AT in line]
    assert any(json.loads(line).get("error", "").startswith("variables[") for line in texts)
    for line in run_cli(small, data).stdout.decode().splitlines():
        error = json.loads(line).get("error")
        assert not isinstance(error, str) or AT not in error or error.startswith(("[", AT, "package" + AT)), error


def test_without_fast_paths_the_robot_state_decoder_agrees_with_the_iterator(small):
    every = [m for case in CASES for m in messages(case.data)]
    with CommandPeer(small.driver, "roundtrip") as peer:
        (out,), code = peer.decode(b"".join(every))
    assert code == 0, out
    assert int(out.split()[1]) == len(every) and int(out.split()[3]) > 40


def test_an_element_keeps_its_index_without_its_name(small):
    """joints[2].qd_actual cut short: the path keeps the element's index, "[2]"."""
    [case] = [c for c in CASES if c.name == "robot_state_package_short"]
    errors = [p["error"] for r in parse_lines(run_cli(small, case.data).stdout) for p in r.get("packages", [])
              if isinstance(p.get("error"), str)]
    assert errors == ["[2] at offset 108: needs 8 bytes, 4 left"]
