"""`make install-dissector` installs the native plugin where it builds, else the Lua dissectors,
never both (they register the same protocols); `make uninstall-dissector` removes both. Each
test runs with HOME in a folder of its own, so tshark's personal folders are that HOME's, and
builds the fixture dissector (tests/native/fixtures/epan) so as not to depend on generated/epan.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import uuid
from pathlib import Path

import pytest

from tests.native import harness

ROOT = harness.ROOT
FIXTURE_EPAN = Path(__file__).resolve().parent / "fixtures" / "epan"
LUA_FILES = sorted(p.name for p in harness.LUA.glob("*.lua"))


@pytest.fixture
def home():
    """A HOME that the user nobody may read (tshark loads personal plugins only when not root)."""
    folder = harness.BUILDS / f"install-home-{uuid.uuid4().hex[:8]}"
    folder.mkdir(parents=True)
    for path in [harness.BUILDS, *harness.BUILDS.parents]:
        if path == Path("/"):
            break
        path.chmod(path.stat().st_mode | 0o001)
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


def folders(home: Path) -> tuple[Path, Path]:
    """The personal plugins folder's epan/ and the personal Lua folder, as tshark names them."""
    env = {**os.environ, "HOME": str(home)}
    env.pop("XDG_CONFIG_HOME", None)
    out = subprocess.run(["tshark", "-G", "folders"], env=env, capture_output=True, text=True, check=True).stdout
    named = dict(line.split(":", 1) for line in out.splitlines() if ":" in line)
    return Path(named["Personal Plugins"].strip()) / "epan", Path(named["Personal Lua Plugins"].strip())


def make(home: Path, target: str, *variables: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "HOME": str(home)}
    env.pop("XDG_CONFIG_HOME", None)
    env.pop("MAKEFLAGS", None)
    return subprocess.run(["make", "--no-print-directory", "-C", str(ROOT), target, *variables], env=env,
                          capture_output=True, text=True, timeout=600)


def fixture_build(home: Path, epan_dir: Path = FIXTURE_EPAN) -> list[str]:
    return [f"URWIRE_EPAN_DIR={epan_dir}", f"NATIVE_BUILD={home / 'build'}"]


def installed(home: Path) -> tuple[bool, list[str]]:
    native, lua = folders(home)
    return (native / "urwire.so").is_file(), sorted(p.name for p in lua.glob("*.lua")) if lua.is_dir() else []


def assert_lua_only(home: Path, result: subprocess.CompletedProcess):
    assert result.returncode == 0, result.stdout + result.stderr
    assert installed(home) == (False, LUA_FILES)


def test_native_where_it_builds_and_the_lua_files_go(home):
    assert_lua_only(home, make(home, "install-dissector", "NATIVE=no"))
    result = make(home, "install-dissector", *fixture_build(home))
    assert result.returncode == 0, result.stdout + result.stderr
    native, lua = folders(home)
    assert installed(home) == (True, [])
    assert (native / "urwire.so").read_bytes() == next((home / "build" / "plugins").rglob("urwire.so")).read_bytes()
    assert f"installed {native / 'urwire.so'}" in result.stdout
    assert f"removed {lua / 'urwire.lua'}" in result.stdout
    if os.geteuid() == 0:
        assert "does not load personal plugins when it runs as root" in result.stderr
    for path in [home, *home.rglob("*")]:
        path.chmod(0o755 if path.is_dir() else 0o644)
    plugins = harness.tshark_with(harness.Plugin("installed", home, native / "urwire.so"), ["-G", "plugins"])
    assert str(native / "urwire.so") in plugins.stdout.decode(), plugins.stderr.decode()


def test_native_no_installs_lua_and_removes_the_plugin(home):
    assert make(home, "install-dissector", *fixture_build(home)).returncode == 0
    assert installed(home) == (True, [])
    assert_lua_only(home, make(home, "install-dissector", "NATIVE=no"))


@pytest.mark.parametrize("failure, reason", [
    ("no packet files", "no generated/epan/packet-*.c to build"),
    ("compile error", "the native plugin did not build"),
    ("no cmake", "cmake is not installed"),
    ("no wireshark-dev", "install wireshark-dev"),
])
def test_a_native_build_that_fails_falls_back_to_lua(home, tmp_path, failure, reason):
    assert make(home, "install-dissector", *fixture_build(home)).returncode == 0   # a plugin to remove
    epan = tmp_path / "epan"
    epan.mkdir()
    failing = f"NATIVE_BUILD={home / 'build-failing'}"     # a fresh build folder: nothing cached
    variables = [f"URWIRE_EPAN_DIR={epan}", failing]
    if failure == "compile error":
        (epan / "packet-urwire-fixture.c").write_text(
            (FIXTURE_EPAN / "packet-urwire-fixture.c").read_text().replace("return tvb_captured_length(tvb);\n}",
                                                                              "return tvb_captured_length(tvb)\n}", 1))
    elif failure == "no cmake":
        variables = [f"URWIRE_EPAN_DIR={FIXTURE_EPAN}", failing, "CMAKE=/nonexistent/cmake"]
    elif failure == "no wireshark-dev":
        # CMake told to look nowhere a Wireshark is installed, as on a machine without wireshark-dev
        variables = [f"URWIRE_EPAN_DIR={FIXTURE_EPAN}", failing,
                     "NATIVE_CMAKE_FLAGS=-DCMAKE_IGNORE_PREFIX_PATH='/usr;/' -DCMAKE_SYSTEM_IGNORE_PREFIX_PATH='/usr;/'"]
    result = make(home, "install-dissector", *variables)
    assert_lua_only(home, result)
    assert reason in result.stderr and "installing the Lua dissectors instead" in result.stderr, result.stderr


def test_native_yes_fails_rather_than_fall_back(home):
    result = make(home, "install-dissector", "NATIVE=yes", "CMAKE=/nonexistent/cmake")
    assert result.returncode != 0 and "cmake is not installed" in result.stderr
    assert installed(home) == (False, [])


def test_uninstall_removes_both(home):
    native, lua = folders(home)
    native.mkdir(parents=True)
    lua.mkdir(parents=True, exist_ok=True)
    (native / "urwire.so").write_bytes(b"")
    for name in LUA_FILES:
        (lua / name).write_text("")
    (lua / "someone_else.lua").write_text("")
    result = make(home, "uninstall-dissector")
    assert result.returncode == 0, result.stderr
    assert installed(home) == (False, ["someone_else.lua"])
