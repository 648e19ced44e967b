"""The native plugin as Wireshark sees it: `make native-dissector` builds it, gcc and clang build
it with -Werror, it exports exactly the four symbols Wireshark 4.0 looks up, it loads (`tshark -G
plugins`), and each protocol it registers has the same fields and names as its Lua twin
(`tshark -G fields`, `-G protocols`). The plugin source guards the 4.2 API by version.

The fixture of tests/native/fixtures (a dissector laid out as the generated ones, with a Lua
twin) is built beside generated/epan, so that these checks run before any generated file exists
and keep testing the comparison itself.
"""
from __future__ import annotations

import functools
import os
import shutil
import subprocess
from pathlib import Path
from typing import Callable

import pytest
import yaml

from codegen.epan_c import SHARED_STEM
from tests.native import harness

ROOT = harness.ROOT
FIXTURES = Path(__file__).resolve().parent / "fixtures"
FIXTURE_EPAN = FIXTURES / "epan"
WIRESHARK_4_0_EXPORTS = ["plugin_register", "plugin_version", "plugin_want_major", "plugin_want_minor"]


def protocol_of(packet_file: Path) -> str:
    """packet-ur-realtime.c registers ur_realtime (the rule dissector/native/CMakeLists.txt keeps)."""
    return packet_file.stem[len("packet-"):].replace("-", "_")


GENERATED = sorted(protocol_of(p) for p in harness.EPAN.glob("packet-*.c") if p.stem != SHARED_STEM)
# The protocols of the text-line kind: their Lua dissectors guard the runtime with an expert of their own.
LINES_PROTOCOLS = sorted(path.stem for path in (harness.ROOT / "spec").glob("*.yaml")
                         if (yaml.safe_load(path.read_text(encoding="utf-8")).get("framing") or {}).get("kind") == "lines")
NO_GENERATED = pytest.mark.skipif(not GENERATED, reason="no generated/epan/packet-*.c yet (make generate)")


def exports(library: Path) -> list[str]:
    out = subprocess.run(["nm", "-D", "--defined-only", str(library)], capture_output=True, text=True, check=True)
    return sorted(line.split()[-1] for line in out.stdout.splitlines() if line.strip())


@pytest.mark.parametrize("variant", ["gcc", "clang"])
def test_fixture_builds_with_werror_and_exports_four_symbols(variant):
    built = harness.build_plugin(variant, FIXTURE_EPAN)
    assert exports(built.library) == WIRESHARK_4_0_EXPORTS


@NO_GENERATED
@pytest.mark.parametrize("variant", ["gcc", "clang"])
def test_generated_builds_with_werror_and_exports_four_symbols(variant):
    assert exports(harness.plugin(variant).library) == WIRESHARK_4_0_EXPORTS


def test_werror_is_on(tmp_path):
    """A warning in a packet file fails the build: -Wall -Wextra -Werror reach the dissectors."""
    shutil.copy(FIXTURE_EPAN / "packet-urwire-fixture.c", tmp_path)
    (tmp_path / "packet-urwire-fixture.c").write_text(
        (FIXTURE_EPAN / "packet-urwire-fixture.c").read_text()
        + "\nstatic int urwire_fixture_unused(int x) { int y; return x; }\n")
    configure = subprocess.run(["cmake", "-S", str(harness.SOURCE), "-B", str(tmp_path / "build"),
                                f"-DURWIRE_EPAN_DIR={tmp_path}"], capture_output=True, text=True)
    assert configure.returncode == 0, configure.stderr
    build = subprocess.run(["cmake", "--build", str(tmp_path / "build")], capture_output=True, text=True)
    assert build.returncode != 0
    assert "-Werror" in build.stdout + build.stderr


def test_make_native_dissector_builds_and_says_where(tmp_path):
    result = subprocess.run(["make", "--no-print-directory", "native-dissector", f"URWIRE_EPAN_DIR={FIXTURE_EPAN}",
                             f"NATIVE_BUILD={tmp_path / 'native'}"], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    said = result.stdout.strip().splitlines()[-1]
    assert said.startswith("native-dissector: ")
    library = Path(said.split(": ", 1)[1])
    assert library.name == "urwire.so" and library.is_file()
    assert library.parent.parent.name == "4.0" and library.parent.name == "epan"
    assert exports(library) == WIRESHARK_4_0_EXPORTS


def glossary(result: subprocess.CompletedProcess) -> str:
    """`tshark -G ...`'s stdout after failing on a bad exit or anything on stderr but the root
    warning (harness.checked does not fit: -G fields lists _ws.lua.error itself)."""
    err = "\n".join(line for line in result.stderr.decode(errors="replace").splitlines()
                    if "Running as user" not in line)
    assert result.returncode == 0 and err.strip() == "", f"tshark exited {result.returncode}: {err[:3000]}"
    return result.stdout.decode("utf-8", errors="replace")


def loaded_plugins(built: harness.Plugin) -> str:
    return glossary(harness.tshark_with(built, ["-G", "plugins"]))


def test_fixture_loads():
    built = harness.build_plugin("gcc", FIXTURE_EPAN)
    lines = [line.split("\t") for line in loaded_plugins(built).splitlines()]
    ours = [cols for cols in lines if cols[0].strip() == "urwire.so"]
    assert len(ours) == 1, lines
    assert ours[0][2].strip() == "dissector" and ours[0][3].strip() == str(built.library)


@NO_GENERATED
def test_generated_plugin_loads():
    built = harness.plugin("gcc")
    assert str(built.library) in loaded_plugins(built)


# -G fields and -G protocols, native against Lua

def lua_home(scripts: list[Path], name: str) -> Path:
    """A HOME whose personal Lua folder holds only these scripts: `-G` must be tshark's first
    option, so -X lua_script cannot bring them."""
    home = harness.BUILDS / f"lua-home-{name}"
    shutil.rmtree(home, ignore_errors=True)
    folder = home / ".local" / "lib" / "wireshark" / "plugins"
    folder.mkdir(parents=True)
    for script in scripts:
        shutil.copy(script, folder)
    return home


@functools.lru_cache(maxsize=None)
def native_glossary(built: harness.Plugin, what: str) -> str:
    """`tshark -G <what>` with this build of the plugin, once per test process."""
    return glossary(harness.tshark_with(built, ["-G", what]))


def lua_glossary(what: str, scripts: list[Path], name: str) -> str:
    env = {**os.environ, "HOME": str(lua_home(scripts, name))}
    env.pop("XDG_CONFIG_HOME", None)
    return glossary(subprocess.run(["tshark", "-G", what], capture_output=True, env=env, timeout=300))


def twin_glossary(script: Path) -> Callable[[str], str]:
    """`tshark -G <what>` with this Lua script alone."""
    return lambda what: lua_glossary(what, [script], script.stem)


@functools.lru_cache(maxsize=None)
def generated_lua_glossary(what: str) -> str:
    """`tshark -G <what>` with every generated Lua dissector installed together, as dissector/
    installs them: one tshark run per test process, not one per protocol. Each protocol's rows
    (of_protocol) are those it registers with its script alone."""
    return lua_glossary(what, [harness.lua_plugin(protocol) for protocol in GENERATED], "generated")


def of_protocol(glossary: str, what: str, protocol: str) -> list[str]:
    """The lines of one protocol: `-G fields` P and F lines (F's fifth column is the protocol),
    `-G protocols` the line whose filter name it is."""
    return sorted(_by_protocol(glossary, what).get(protocol, []))


@functools.lru_cache(maxsize=None)
def _by_protocol(glossary: str, what: str) -> dict[str, list[str]]:
    """The lines of a glossary by protocol, read once: Wireshark 4.0's -G fields is some 236,000
    lines, and each protocol's test reads the same one."""
    out: dict[str, list[str]] = {}
    for line in glossary.splitlines():
        r = line.split("\t")
        if what == "fields":
            key = r[2] if r[0] == "P" else r[4] if r[0] == "F" else None
        else:
            key = r[2] if len(r) == 3 else None
        if key is not None:
            out.setdefault(key, []).append(line)
    return out


def assert_same_glossary(built: harness.Plugin, protocol: str, lua_of: Callable[[str], str]):
    for what in ("fields", "protocols"):
        native = of_protocol(native_glossary(built, what), what, protocol)
        lua = of_protocol(lua_of(what), what, protocol)
        assert native, f"the native plugin registers no {what} of {protocol}"
        missing = sorted(set(lua) - set(native))
        extra = sorted(set(native) - set(lua))
        assert native == lua, f"-G {what} of {protocol}: only Lua has {missing[:20]}, only native {extra[:20]}"


def test_fixture_glossary_matches_its_lua_twin():
    assert_same_glossary(harness.build_plugin("gcc", FIXTURE_EPAN), "urwire_fixture",
                         twin_glossary(FIXTURES / "lua" / "urwire_fixture.lua"))


def test_glossary_comparison_sees_a_difference(tmp_path):
    """The comparison fails when a field differs (here the Lua twin names a field otherwise)."""
    twin = tmp_path / "urwire_fixture.lua"
    twin.write_text((FIXTURES / "lua" / "urwire_fixture.lua").read_text().replace('"Kind"', '"Sort"'))
    with pytest.raises(AssertionError, match="only Lua has"):
        assert_same_glossary(harness.build_plugin("gcc", FIXTURE_EPAN), "urwire_fixture", twin_glossary(twin))


def _string_blurb_dropped_by_lua(lua: list[str] | None, native: list[str] | None) -> bool:
    return (lua is not None and native is not None and lua[3] in ("FT_STRING", "FT_STRINGZ")
            and lua[:7] == native[:7] and lua[7:] in ([], [""]) and native[7] != "")


def _lua_internal_error_expert(lua: list[str] | None, native: list[str] | None) -> bool:
    return native is None and lua is not None and lua[2].endswith(".internal_error")


# Differences between the generated twins that are known and open, each with what fixes it. The
# test fails on any other difference, and when a known one is gone (remove it from here).
KNOWN_DIVERGENCES = {
    "ur": ("Wireshark 4.0's Lua drops the description of ProtoField.string(abbr, name, base.UNICODE, desc) "
           "(the three-argument form ProtoField.string(abbr, name, desc) keeps it): the Lua string fields have "
           "no blurb, the native ones have the spec's", _string_blurb_dropped_by_lua),
    # Every text-line interface (framing.kind: lines).
    **{name: (f"the Lua dissector registers the expert {name}.internal_error (its guard around the runtime), "
              "the native one does not", _lua_internal_error_expert) for name in LINES_PROTOCOLS},
}


@pytest.mark.parametrize("protocol", GENERATED or ["(none)"])
@NO_GENERATED
def test_generated_glossary_matches_lua(protocol):
    if protocol not in KNOWN_DIVERGENCES:
        assert_same_glossary(harness.plugin("gcc"), protocol, generated_lua_glossary)
        return
    reason, known = KNOWN_DIVERGENCES[protocol]
    built = harness.plugin("gcc")
    open_known = []
    for what in ("fields", "protocols"):
        native = {r.split("\t")[2]: r.split("\t")
                  for r in of_protocol(native_glossary(built, what), what, protocol)}
        lua = {r.split("\t")[2]: r.split("\t") for r in of_protocol(generated_lua_glossary(what), what, protocol)}
        for abbrev in sorted(set(native) | set(lua)):
            if native.get(abbrev) == lua.get(abbrev):
                continue
            assert known(lua.get(abbrev), native.get(abbrev)), \
                f"-G {what} of {protocol}, {abbrev}: Lua {lua.get(abbrev)}, native {native.get(abbrev)}"
            open_known.append(abbrev)
    assert open_known, f"the known divergence of {protocol} is fixed: remove it from KNOWN_DIVERGENCES"
    pytest.xfail(f"{reason} ({len(open_known)}: {', '.join(open_known[:4])}...)")


# plugin.c guards the API of newer Wireshark releases by version

def compile_plugin_c(tmp_path: Path, version: tuple[int, int] | None) -> list[str]:
    """plugin.c as CMake writes it, compiled alone; `version` fakes ws_version.h (and 4.2's
    wsutil/plugins.h, which 4.0 lacks) to see what a newer Wireshark would get."""
    built = harness.build_plugin("gcc", FIXTURE_EPAN)
    plugin_c = harness.BUILDS / built.home.name.removeprefix("home-") / "plugin.c"
    assert plugin_c.is_file(), plugin_c
    includes = [f"-I{tmp_path}"] if version else []
    if version:
        major, minor = version
        (tmp_path / "ws_version.h").write_text(
            f"#define WIRESHARK_VERSION_MAJOR {major}\n#define WIRESHARK_VERSION_MINOR {minor}\n"
            "#define WIRESHARK_VERSION_MICRO 0\n")
        (tmp_path / "wsutil").mkdir()
        (tmp_path / "wsutil" / "plugins.h").write_text("#define WS_PLUGIN_DESC_DISSECTOR (1UL << 0)\n")
    glib = subprocess.run(["pkg-config", "--cflags", "glib-2.0"], capture_output=True, text=True, check=True)
    obj = tmp_path / "plugin.o"
    result = subprocess.run(["gcc", "-c", "-Wall", "-Wextra", "-Werror", *includes, "-I/usr/include/wireshark",
                             *glib.stdout.split(), str(plugin_c), "-o", str(obj)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    symbols = subprocess.run(["nm", "--defined-only", str(obj)], capture_output=True, text=True, check=True)
    return sorted(line.split()[-1] for line in symbols.stdout.splitlines())


def test_plugin_c_declares_plugin_describe_from_4_2(tmp_path):
    assert "plugin_describe" in compile_plugin_c(tmp_path, (4, 2))


def test_plugin_c_has_no_plugin_describe_on_4_0(tmp_path):
    defined = compile_plugin_c(tmp_path, None)
    assert "plugin_describe" not in defined and "plugin_register" in defined


# Everything but the two registration functions is static (what Wireshark's tools/check_static.py
# asks of a dissector in the tree; it needs a whole Wireshark build, so the objects are read here),
# but in the helpers the dissectors share (packet-ur-common.c), whose globals are all ur_*, each
# called by a dissector.

def globals_of_packet_objects(built: harness.Plugin) -> dict[str, list[str]]:
    folder = harness.BUILDS / built.home.name.removeprefix("home-")
    out = {}
    for obj in sorted(folder.rglob("packet-*.c.o")):
        listing = subprocess.run(["nm", "--defined-only", str(obj)], capture_output=True, text=True, check=True)
        out[obj.name.removesuffix(".c.o")] = sorted(parts[2] for parts in map(str.split, listing.stdout.splitlines())
                                                    if len(parts) == 3 and parts[1].isupper())
    return out


def registration_only(objects: dict[str, list[str]]) -> None:
    assert objects, "no packet-*.c object in the build"
    for stem, names in objects.items():
        if stem == SHARED_STEM:
            continue
        protocol = protocol_of(Path(stem + ".c"))
        assert names == sorted([f"proto_register_{protocol}", f"proto_reg_handoff_{protocol}"]), (stem, names)


def shared_helpers_used(folder: Path, objects: dict[str, list[str]]) -> list[str]:
    """The globals of the shared helpers (ur_*), each called by some dissector of the build."""
    helpers = objects[SHARED_STEM]
    assert helpers and all(name.startswith("ur_") for name in helpers), helpers
    called = set()
    for obj in folder.rglob("packet-*.c.o"):
        listing = subprocess.run(["nm", "--undefined-only", str(obj)], capture_output=True, text=True, check=True)
        called |= {line.split()[-1] for line in listing.stdout.splitlines() if line.strip()}
    assert set(helpers) <= called, sorted(set(helpers) - called)
    return helpers


def test_fixture_defines_only_its_registration_functions_globally():
    registration_only(globals_of_packet_objects(harness.build_plugin("gcc", FIXTURE_EPAN)))


def test_static_check_sees_a_global(tmp_path):
    (tmp_path / "packet-urwire-fixture.c").write_text((FIXTURE_EPAN / "packet-urwire-fixture.c").read_text()
                                                      + "\nint urwire_fixture_leak;\n")
    with pytest.raises(AssertionError, match="urwire_fixture_leak"):
        registration_only(globals_of_packet_objects(harness.build_plugin("gcc", tmp_path)))


@NO_GENERATED
def test_generated_define_only_their_registration_functions_globally():
    built = harness.plugin("gcc")
    objects = globals_of_packet_objects(built)
    registration_only(objects)
    helpers = shared_helpers_used(harness.BUILDS / built.home.name.removeprefix("home-"), objects)
    assert "ur_exchange_request" in helpers
