"""Subset C builds (`make subset-c SELECT=...`, codegen --select): the parser of joint data and
tool data alone, on every version and pinned to 5.11. It compiles clean with gcc and clang under
the strict flags (and `make subset-c` at -Os); the CLI built on it reads every golden vector's
robot states to exactly the full decoder's joint data and tool data, every other sub-package kept
raw with its type and bytes and every other message as unknown; every message and sub-package
encodes back to its bytes."""
from __future__ import annotations

import functools
import subprocess
import sys

import pytest

from tests.c.harness_c import CLI_SOURCES, OUT, ROOT, compile_c, parse_lines, python_records
from tests.vectors import all_cases

SELECT = "ur:robot_state.joint_data,robot_state.tool_data"
PICKED = {"joint_data", "tool_data"}
# The vectors each build reads: every one on every version; the 5.11 generation's when pinned.
PINS = {"all": None, "5.11": "5.11"}
CASES = {c.name: c for c in all_cases()}
PINNED_CASES = ["generation_eseries_5_11_robot_state", "generation_eseries_5_11_robot_state~no_version_message"]


@functools.cache
def subset_source(name: str):
    folder = OUT / "subset" / name
    pin = ["--pin", PINS[name]] if PINS[name] else []
    subprocess.run([sys.executable, "-m", "codegen", "--select", SELECT, *pin, "--target", "c", "--out", str(folder)],
                   cwd=ROOT, check=True)
    return folder / "c"


@pytest.fixture(scope="module", params=list(PINS))
def subset(request):
    return request.param, subset_source(request.param)


def cases_of(name: str):
    return list(CASES.values()) if PINS[name] is None else [CASES[n] for n in PINNED_CASES]


def test_subset_has_only_the_picked_layouts(subset):
    _, src = subset
    header = (src / "urwire.h").read_text()
    for kept in ("urwire_joint_data", "urwire_tool_data", "urwire_version_message"):   # the framer reads it
        assert f"}} {kept};" in header, kept
    for dropped in ("urwire_robot_mode_data", "urwire_masterboard_data", "urwire_text_message", "urwire_key_message"):
        assert f"}} {dropped};" not in header, dropped
    assert "URWIRE_PACKAGE_TYPE_MASTERBOARD_DATA" in header     # its code is still named
    assert "Only these parts (python -m codegen --select): robot_state.joint_data robot_state.tool_data" in header


def on_the_wire(package: dict) -> bytes:
    """A sub-package kept raw as the stream sends it: its declared length, its type, its bytes."""
    body = bytes.fromhex(package["raw"])
    return (5 + len(body)).to_bytes(4, "big") + bytes([package["package_type"]]) + body


# The pinned build's CLI (two vectors, a whole CLI build) is a long run for make test-deep.
@pytest.mark.parametrize("name", ["all", pytest.param("5.11", marks=pytest.mark.deep)])
def test_subset_reads_the_picked_parts_as_the_full_decoder(name, cc="gcc"):
    """(One compiler: the CLI is most of the build; the driver below builds the subset with both.)"""
    src = subset_source(name)
    exe = OUT / "subset" / f"urwire-decode-{name}-{cc}"
    compile_c(cc, ["-O2", f"-I{src}"], [*CLI_SOURCES, src / "urwire.c"], exe, ["-lm"])
    states = picked = raw = 0
    for case in cases_of(name):
        args = ["--version-hint", case.version] if case.version else []
        result = subprocess.run([str(exe), *args, "-"], input=case.data, capture_output=True)
        mine = parse_lines(result.stdout)
        full, code = python_records(case.data, case.version)
        assert result.returncode <= code, case.name   # what is kept raw is no error, whatever it holds
        assert len(mine) == len(full), case.name
        for record, reference in zip(mine, full):
            if reference["type"] == "version" or record == reference:
                assert record == reference, case.name
                continue
            if reference["type"] != "robot_state":   # a message type or subtype with no layout here
                assert record["type"] == "unknown" and "raw" in record, (case.name, record)
                continue
            states += 1
            assert {k: v for k, v in record.items() if k != "packages"} == \
                {k: v for k, v in reference.items() if k != "packages"}, case.name
            assert len(record["packages"]) == len(reference["packages"]), case.name
            for mine_pkg, full_pkg in zip(record["packages"], reference["packages"]):
                if full_pkg["type"] in PICKED or full_pkg["type"] == "unknown":
                    assert mine_pkg == full_pkg, case.name
                    picked += full_pkg["type"] in PICKED
                    continue
                raw += 1
                assert set(mine_pkg) == {"type", "package_type", "raw"} and mine_pkg["type"] == "unknown", case.name
                assert on_the_wire(mine_pkg) in case.data, case.name
    assert states >= (50 if PINS[name] is None else 2) and picked >= states and raw >= states


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_subset_encodes_every_message_back_to_its_bytes(subset, cc):
    """Built under the strict flags (compile_c) at -O2, the subset and the driver alike."""
    name, src = subset
    exe = OUT / "subset" / f"subset-driver-{name}-{cc}"
    compile_c(cc, ["-O2", f"-I{src}"], [ROOT / "tests" / "c" / "subset_driver.c", src / "urwire.c"], exe)
    totals = [0, 0, 0]
    for case in cases_of(name):
        result = subprocess.run([str(exe), *([case.version] if case.version else [])], input=case.data,
                                capture_output=True, text=False)
        assert result.returncode == 0, (case.name, result.stdout)
        words = result.stdout.split()
        totals = [t + int(words[1 + 2 * i]) for i, t in enumerate(totals)]
    messages_, packages, raw = totals
    assert messages_ > 0 and packages > raw > 0


def test_make_subset_c_writes_the_files_and_an_object():
    result = subprocess.run(["make", "--no-print-directory", "-C", str(ROOT), "subset-c", f"SELECT={SELECT}",
                             "PIN=3.2"], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "--select ur:robot_state.joint_data,robot_state.tool_data --pin 3.2" in result.stdout
    for rel in ("c/urwire.h", "c/urwire.c", "urwire.o"):
        assert (ROOT / "build" / "subset" / rel).is_file(), rel
    assert "Documented versions: 3.2." in (ROOT / "build" / "subset" / "c" / "urwire.h").read_text()
