"""The three targets choose a type code's form by version from the same tables: for every
version the spec names, every segment's first version and the gaps between series, the Python
runtime's lookup, the C runtime's (urwire__segment, then urwire__mine) and the Lua runtime's
(segment_of over the generated segments) give the form that the plan's version ranges give
(the form those versions send, else the nearest below's, flagged so)."""
from __future__ import annotations

import importlib
import re
import shutil
import subprocess

import pytest

from codegen import ir
from codegen.compile import DEFAULT_SPEC, compile_file
from codegen.kinds.packages.plan import plan
from tests.c.harness_c import GEN, OUT, ROOT

LUA_PLUGIN = ROOT / "generated" / "lua" / "urwire.lua"
LUA_RUNTIME = ROOT / "runtime" / "lua"
LUA_TESTS = ROOT / "tests" / "lua" / "runtime"


@pytest.fixture(scope="module")
def planned():
    return plan(compile_file(DEFAULT_SPEC))


@pytest.fixture(scope="module")
def versions(planned) -> list[ir.Version]:
    p = planned.protocol
    named = set(p.documented_versions) | {p.default_version} | {s.first for s in planned.segments if s.first}
    named |= {(2, 0, 0), (4, 0, 0), (1, 8, 5), (5, 25, 0), (5, 99, 3), (6, 0, 0), (11, 0, 0), (0, 0, 0)}
    return sorted(named)


def expected(variants, version: ir.Version) -> tuple[int, bool]:
    """The rule, from the forms' version ranges alone: (form index, nearest below?)."""
    n = ir.version_number(version)
    sent = [k for k, v in enumerate(variants) if any(lo <= n <= hi for lo, hi in v.ranges)]
    if sent:
        return sent[0], False
    below = [(lo, k) for k, v in enumerate(variants) for lo, _ in v.ranges if lo <= n]
    return (max(below)[1] if below else 0), True


def oracle(planned, versions) -> dict:
    return {(mp.message.name, code, v): expected(variants, v)
            for mp in planned.messages for code, variants in mp.variants.items() for v in versions}


def python_choices(planned, versions) -> dict:
    messages = importlib.import_module("urwire.generated.messages")
    rt = importlib.import_module("urwire._runtime")
    out = {}
    for mp in planned.messages:
        forms = getattr(messages, f"_{mp.message.name.upper()}_FORMS")
        for v in versions:
            row = forms.rows[rt.segment(forms.starts, v)]
            for code in mp.variants:
                k = row[code]
                out[(mp.message.name, code, v)] = (k, False) if k >= 0 else (~k, True)
    return out


C_PROGRAM = """#include "urwire.c"
#include <stdio.h>
#include <stdlib.h>

static void show(const char *name, const urwire__form_table *t, size_t segment)
{
    size_t code;
    for (code = 0; code < t->ncodes; code++) {
        bool nearest;
        const urwire__form *f;
        if (t->codes[code].count == 0)
            continue;
        f = urwire__mine(t, segment, code, &nearest);
        printf(" %s:%d:%d:%d", name, (int)code, (int)(f - t->codes[code].forms), nearest ? 1 : 0);
    }
}

int main(int argc, char **argv)
{
    int i;
    for (i = 1; i + 2 < argc; i += 3) {
        urwire_sw_version v;
        size_t segment;
        memset(&v, 0, sizeof v);
        v.major = atoi(argv[i]);
        v.minor = atoi(argv[i + 1]);
        v.bugfix = atoi(argv[i + 2]);
        segment = urwire__segment(urwire__version_key(v));
%SHOW%        printf("\\n");
    }
    return 0;
}
"""


def c_choices(planned, versions) -> dict:
    if shutil.which("gcc") is None:
        pytest.fail("gcc is not installed (scripts/setup.sh installs it)")
    tables = {mp.message.name: "urwire__package_form_table" if not mp.is_dispatch
              else f"urwire__{mp.message.name}_form_table" for mp in planned.messages}
    # A body message's one code (its type) is code 0 of its C table.
    body_codes = {mp.message.name: min(mp.variants) for mp in planned.messages
                  if mp.is_dispatch and not mp.message.has_subtype}
    show = "".join(f'        show("{name}", &{table}, segment);\n' for name, table in tables.items())
    OUT.mkdir(parents=True, exist_ok=True)
    source, exe = OUT / "form_tables.c", OUT / "form_tables"
    source.write_text(C_PROGRAM.replace("%SHOW%", show), encoding="utf-8")
    subprocess.run(["gcc", "-std=c99", "-O0", f"-I{GEN}", "-o", str(exe), str(source)], check=True,
                   capture_output=True)
    args = [str(part) for v in versions for part in v]
    lines = subprocess.run([str(exe), *args], check=True, capture_output=True, text=True).stdout.splitlines()
    out = {}
    for v, line in zip(versions, lines):
        for item in line.split():
            name, code, form, nearest = item.split(":")
            out[(name, body_codes.get(name, int(code)), v)] = (int(form), nearest == "1")
    return out


LUA_SCRIPT = """local S = dofile("stubs.lua")
local rt = S.base_rt({ default_version = "5.9", segment_starts = { %STARTS% } })
for _, text in ipairs({ %VERSIONS% }) do print(rt.segment_of(rt.parse_version(text))) end
"""


def lua_choices(planned, versions) -> dict:
    if shutil.which("lua5.2") is None:
        pytest.fail("lua5.2 is not installed (scripts/setup.sh installs it)")
    text = LUA_PLUGIN.read_text(encoding="utf-8")
    starts = re.search(r"segment_starts = \{(.*?)\}", text, re.S).group(1)
    texts = ", ".join('"%d.%d.%d"' % v for v in versions)
    script = LUA_SCRIPT.replace("%STARTS%", starts.strip().rstrip(",")).replace("%VERSIONS%", texts)
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / "form_tables.lua"
    path.write_text(script, encoding="utf-8")
    result = subprocess.run(["lua5.2", str(path)], cwd=LUA_TESTS, capture_output=True, text=True,
                            env={"URWIRE_RUNTIME": str(LUA_RUNTIME), "PATH": "/usr/bin:/bin"})
    assert result.returncode == 0, result.stderr
    segments = [int(n) for n in result.stdout.split()]
    out = {}
    for mp in planned.messages:
        kind = ("SUBTYPES" if mp.message.has_subtype else "FORMS") if mp.is_dispatch else "PACKAGES"
        var = f"{mp.message.name.upper()}_{kind}"
        table = text[text.index(f"local {var} = {{"):]
        for code in mp.variants:
            row = re.search(r"\[%d\] = \{ single = \w+.*?segments = \{ ([-\d, ]+) \}" % code, table, re.S).group(1)
            entries = [int(n) for n in row.split(",")]
            for v, segment in zip(versions, segments):
                e = entries[segment - 1]
                out[(mp.message.name, code, v)] = (e - 1, False) if e > 0 else (-e - 1, True)
    return out


def test_every_target_chooses_the_plans_form_at_every_version(planned, versions):
    want = oracle(planned, versions)
    assert any(nearest for _, nearest in want.values())      # the gaps between series are covered
    for target, got in [("python", python_choices(planned, versions)), ("c", c_choices(planned, versions)),
                        ("lua", lua_choices(planned, versions))]:
        wrong = {key: (got.get(key), form) for key, form in want.items() if got.get(key) != form}
        assert not wrong, f"{target}: {dict(list(wrong.items())[:5])}"
