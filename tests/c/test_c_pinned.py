"""Pinned C builds (`make pinned-c PIN=5.11`, codegen --pin): the protocol as one software
version sends it, with no version branches. For a CB2, a CB3 and an e-Series version, the
pinned urwire.c compiles clean with gcc and clang under the strict flags, and the CLI built on
it decodes that generation's vectors (with and without their Version message) to exactly the
records the full decoder gives."""
from __future__ import annotations

import functools
import subprocess
import sys

import pytest

from tests.c.harness_c import CLI_SOURCES, INCLUDES, OUT, ROOT, STRICT, compile_c, get_build, parse_lines, python_lines
from tests.vectors import all_cases

# The vectors of each generation; each "~no_version_message" twin runs too where there is one.
PINS = {
    "1.8": ["generation_cb2_1_8_robot_state", "generation_cb2_1_8_robot_state_euromap67", "robot_messages_cb2_1_8"],
    "3.2": ["generation_cb3_3_2_robot_state", "global_variables_update_3_2_version_message",
            "global_variables_update_3_2_hint", "version_message_svn_3_2"],
    "5.11": ["generation_eseries_5_11_robot_state"],
}
CASES = {c.name: c for c in all_cases()}


def pinned_source(version: str):
    folder = OUT / "pinned" / version
    subprocess.run([sys.executable, "-m", "codegen", "--pin", version, "--target", "c", "--out", str(folder)],
                   cwd=ROOT, check=True)
    return folder / "c"


@pytest.fixture(scope="module", params=list(PINS))
def pinned(request):
    return request.param, pinned_source(request.param)


# -O2: test_pinned_cli_decodes_its_generation_as_the_full_decoder compiles the pinned urwire.c so, with
# both compilers under the same strict flags, and fails on any diagnostic.
@pytest.mark.parametrize("cc", ["gcc", "clang"])
@pytest.mark.parametrize("opt", ["-O0", "-Os"])
def test_pinned_library_compiles_clean(pinned, cc, opt):
    version, src = pinned
    obj = OUT / "pinned" / f"urwire-{version}-{cc}{opt}.o"
    compile_c(cc, [opt, "-c", f"-I{src}"], [src / "urwire.c"], obj)


def test_pinned_layouts_have_no_version_branches(pinned):
    _, src = pinned
    text = (src / "urwire.c").read_text()
    assert "ver->key" not in text                        # no layout compares the version
    full = (ROOT / "generated" / "c" / "urwire.c").read_text()
    assert "ver->key >= URWIRE__V(" in full                # where the full build does


@functools.cache
def sources_without_the_primary_header() -> tuple:
    """The CLI's sources that include no urwire.h, directly or not (gcc -MM): their objects are the
    same whatever version the primary parser is pinned to."""
    def includes_it(source):
        deps = subprocess.run(["gcc", "-MM", *(f"-I{d}" for d in INCLUDES), str(source)],
                              capture_output=True, text=True, check=True).stdout
        return any(word.endswith("/urwire.h") for word in deps.split())
    return tuple(s for s in CLI_SOURCES if not includes_it(s))


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_pinned_cli_decodes_its_generation_as_the_full_decoder(pinned, cc):
    version, src = pinned
    exe = OUT / "pinned" / f"urwire-decode-{version}-{cc}"
    # The sources that do not see the pinned header are linked from the session's -O2 build of the
    # same compiler (the same strict flags); the others are compiled against the pinned header.
    shared = sources_without_the_primary_header()
    objects = [get_build(cc).object(s) for s in shared]
    compile_c(cc, ["-O2", f"-I{src}"], [*(s for s in CLI_SOURCES if s not in shared), src / "urwire.c", *objects],
              exe, ["-lm"])
    names = [n for base in PINS[version] for n in (base, base + "~no_version_message") if n in CASES]
    assert len(names) >= len(PINS[version])
    for name in names:
        case = CASES[name]
        args = ["--version-hint", case.version] if case.version else []
        result = subprocess.run([str(exe), *args, "-"], input=case.data, capture_output=True)
        assert result.returncode == 0 and result.stderr == b"", (name, result.stderr)
        assert parse_lines(result.stdout) == case.expect, name
        assert result.stdout.decode("utf-8").splitlines() == python_lines(case.data, case.version)[0], name


def test_make_pinned_c_writes_the_files_and_an_object(tmp_path):
    result = subprocess.run(["make", "--no-print-directory", "-C", str(ROOT), "pinned-c", "PIN=3.2"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    for rel in ("c/urwire.h", "c/urwire.c", "urwire.o"):
        assert (ROOT / "build" / "pinned" / rel).is_file(), rel
    assert "Documented versions: 3.2." in (ROOT / "build" / "pinned" / "c" / "urwire.h").read_text()
    assert STRICT[0] in result.stdout  # built with the strict flags
