"""The hand-written C runtime of the primary interface (runtime/c/packages/, and what it joins
of runtime/c/common/) on its own: each file compiles
alone under the strict flags with gcc and clang (tests/c/runtime_spec.h and runtime_support.h
stand in for the generated part), tests/c/runtime_unit.c checks it over a made-up protocol, and
the generator joins the files into generated/c/urwire.{h,c} minus their standalone-only lines.
Also: a step kind with no template fragment is an error when generating."""
from __future__ import annotations

import subprocess

import jinja2
import pytest

from codegen.emit import RUNTIME as RUNTIME_ROOT, environment, runtime_source
from codegen.kinds.packages.c import FOLDER, RUNTIME
from codegen.view import Step
from tests.c.harness_c import GEN, OUT, ROOT, SANITIZE, STRICT

RUNTIME_DIR = RUNTIME_ROOT / "c"
# The other kinds keep their runtimes in folders of their own (runtime/c/lines/, ...), each tested
# with its kind; the shared folder's files are tested in tests/c/test_c_common.py, and those the
# primary joins are compiled here too.
SHARED = ("common/macros.h", "common/loads.h", "common/buffer.h", "common/buffer.c", "common/held.h",
          "common/held.c", "common/version_text.h", "common/version_text.c")
FILES = sorted([f"packages/{p.name}" for p in (RUNTIME_DIR / "packages").iterdir()] + list(SHARED))
STANDALONE = [f"-I{RUNTIME_DIR / 'packages'}", f"-I{RUNTIME_DIR / 'common'}", f"-I{ROOT / 'tests' / 'c'}"]


def compile_standalone(cc: str, flags: list[str], sources: list, output) -> None:
    output.parent.mkdir(parents=True, exist_ok=True)
    cmd = [cc, *STRICT, *flags, *STANDALONE, "-o", str(output), *map(str, sources)]
    result = subprocess.run(cmd, capture_output=True, text=True)
    assert result.returncode == 0 and result.stderr == "", f"{' '.join(cmd)}\n{result.stderr}"


@pytest.mark.parametrize("cc", ["gcc", "clang"])
@pytest.mark.parametrize("name", FILES)
def test_each_runtime_file_compiles_on_its_own(cc, name):
    header = ["-x", "c"] if name.endswith(".h") else []
    output = OUT / "runtime" / f"{name.replace('/', '-')}-{cc}.o"
    compile_standalone(cc, ["-O2", "-c", *header], [RUNTIME_DIR / name], output)


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_runtime_unit_checks(cc):
    exe = OUT / "runtime" / f"runtime-unit-{cc}"
    sources = [ROOT / "tests" / "c" / "runtime_unit.c", *[RUNTIME_DIR / name for name in FILES if name.endswith(".c")]]
    compile_standalone(cc, ["-O1", "-g", *SANITIZE], sources, exe)
    result = subprocess.run([str(exe)], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.strip() == "all runtime checks passed"


def test_every_runtime_file_is_joined_once():
    joined = [name for names in RUNTIME.values() for name in names]
    assert sorted(joined) == FILES


def test_joined_files_are_the_runtime_minus_its_standalone_lines():
    generated = (GEN / "urwire.h").read_text() + (GEN / "urwire.c").read_text()
    for name in FILES:
        text = runtime_source(FOLDER, name).rstrip("\n")
        assert "standalone>" not in text and "runtime_support.h" not in text and "runtime_spec.h" not in text
        assert text.strip() and text in generated, name
    assert "standalone>" not in generated


def test_standalone_blocks_only_include_or_guard():
    """What a runtime file needs only on its own is an include, a guard or the linkage of its
    private functions: never code that the joined file would lack."""
    for name in FILES:
        raw = (RUNTIME_DIR / name).read_text()
        kept = runtime_source(FOLDER, name)
        dropped = [line for line in raw.splitlines() if line not in kept.splitlines()]
        for line in dropped:
            assert line.startswith(("/*", "#include", "#ifndef", "#define", "#endif", "#undef")), (name, line)


@pytest.mark.parametrize("macro", ["decode", "encode", "visit"])
def test_an_unknown_step_kind_is_an_error_when_generating(macro):
    steps = environment(FOLDER).get_template("packages/steps.c.j2").module
    known = {"decode": Step("rest", dict(name="x")), "encode": Step("bytes", dict(name="x")),
             "visit": Step("text", dict(name="x", when=[]))}[macro]
    assert '"x"' in str(getattr(steps, macro)([known], "    ")) or "->x" in str(getattr(steps, macro)([known], "    "))
    with pytest.raises(jinja2.UndefinedError):
        getattr(steps, macro)([Step("no_such_kind", dict(name="x", when=[]))], "    ")


def run_step(members: list[dict], terms: list[dict]) -> Step:
    return Step("cond", dict(test=dict(terms=terms), zero=[], steps=[
        Step("run", dict(table="t", size=4, loops=False, members=members))]))


SCALAR = dict(kind="scalar", name="x", offset=2, reader="urwire__u16", writer="urwire__put_u16", into="", out="")
FLAG = dict(kind="flag", name="f")


def test_members_and_terms_are_data_rendered_by_kind():
    steps = environment(FOLDER).get_template("packages/steps.c.j2").module
    text = str(steps.decode([run_step([SCALAR], [FLAG, dict(kind="from", major=5, minor=25, bugfix=1)])], ""))
    assert "if (out->f != 0 && ver->key >= URWIRE__V(5, 25, 1)) {" in text
    assert "out->x = urwire__u16(p + 2);" in text
    wide = dict(SCALAR, into="int32_t", out="uint16_t", offset=0)
    assert "out->x = (int32_t)urwire__u16(p);" in str(steps.decode([run_step([wide], [FLAG])], ""))
    assert "urwire__put_u16(p, (uint16_t)in->x);" in str(steps.encode([run_step([wide], [FLAG])], ""))


@pytest.mark.parametrize("member, term", [(dict(SCALAR, kind="no_such_member"), FLAG),
                                          (SCALAR, dict(FLAG, kind="no_such_term"))])
def test_an_unknown_member_or_term_kind_is_an_error_when_generating(member, term):
    steps = environment(FOLDER).get_template("packages/steps.c.j2").module
    with pytest.raises(jinja2.UndefinedError):
        steps.decode([run_step([member], [term])], "")
