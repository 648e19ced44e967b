"""Run real tshark with the native plugin (dissector/native, built from generated/epan) or with one
Lua dissector alone, on the same capture, and compare what the two show.

Wireshark loads a plugin from its plugin folders only. A personal folder under $HOME is skipped
when tshark runs as root (Wireshark drops plugins for a privileged user), so under root tshark
runs as the user nobody, with a HOME that holds only the plugin built here, and reads a copy of
the capture that every user may read (pytest's temporary folders are private to root; a pipe
would do, but tshark reads a pipe in one pass only and `-2` needs a file). The Lua runs get an empty HOME too,
so that nothing installed on the machine loads beside the dissector under test.
"""
from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Sequence, Union

import pytest

ROOT = Path(__file__).resolve().parents[2]
SOURCE = ROOT / "dissector" / "native"
EPAN = ROOT / "generated" / "epan"
LUA = ROOT / "generated" / "lua"
BUILDS = ROOT / "build" / "native-tests"
NOBODY = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"]
SANITIZE = "-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -g -O1"

# variant -> (C compiler, extra CFLAGS, extra LDFLAGS)
VARIANTS = {
    "gcc": ("gcc", "", ""),
    "clang": ("clang", "", ""),
    "asan": ("gcc", SANITIZE, "-fsanitize=address,undefined"),
}


@dataclass(frozen=True)
class Plugin:
    variant: str
    home: Path          # a HOME whose personal plugin folder holds this build, and nothing else
    library: Path       # the .so


def _stamp(variant: str, epan_dir: Path) -> str:
    digest = hashlib.sha256(repr((VARIANTS[variant], str(epan_dir))).encode())
    for path in sorted([*epan_dir.glob("*"), *SOURCE.glob("*")]):
        if path.is_file():
            digest.update(path.name.encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()


def build_plugin(variant: str = "gcc", epan_dir: Path = EPAN) -> Plugin:
    """The plugin built with CMake under build/native-tests/<variant>, once for every test process
    (under a lock; a stamp of the sources says whether a build is current). `epan_dir` builds it
    from other packet-*.c (the fixture of tests/native/fixtures/epan), under <variant>-<folder>."""
    cc, cflags, ldflags = VARIANTS[variant]
    for tool in ("cmake", cc, "setpriv"):
        if shutil.which(tool) is None:
            pytest.fail(f"{tool} is not installed (scripts/setup.sh installs it)")
    name = variant if epan_dir == EPAN else f"{variant}-{hashlib.sha256(str(epan_dir).encode()).hexdigest()[:12]}"
    folder = BUILDS / name
    home = BUILDS / f"home-{name}"
    BUILDS.mkdir(parents=True, exist_ok=True)
    with open(BUILDS / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        stamp, want = folder / "stamp", _stamp(variant, epan_dir)
        if not (stamp.is_file() and stamp.read_text() == want):
            stamp.unlink(missing_ok=True)
            shutil.rmtree(folder, ignore_errors=True)
            env = {**os.environ, "CC": cc}
            configure = ["cmake", "-S", str(SOURCE), "-B", str(folder), "-DCMAKE_BUILD_TYPE=RelWithDebInfo",
                         f"-DURWIRE_EPAN_DIR={epan_dir}",
                         f"-DURWIRE_EXTRA_CFLAGS={cflags.replace(' ', ';')}",
                         f"-DURWIRE_EXTRA_LDFLAGS={ldflags.replace(' ', ';')}"]
            for cmd in (configure, ["cmake", "--build", str(folder)]):
                result = subprocess.run(cmd, capture_output=True, text=True, env=env)
                assert result.returncode == 0, f"{' '.join(cmd)}\n{result.stdout[-4000:]}\n{result.stderr[-4000:]}"
            _install(folder / "plugins", home)
            stamp.write_text(want)
    return _installed(variant, home)


def _install(plugins: Path, home: Path) -> None:
    """A HOME under build/native-tests whose personal plugin folder holds these plugins only,
    readable by the user nobody."""
    shutil.rmtree(home, ignore_errors=True)
    target = home / ".local" / "lib" / "wireshark"
    target.mkdir(parents=True)
    shutil.copytree(plugins, target / "plugins")
    for path in [home, *home.rglob("*")]:
        path.chmod(0o755 if path.is_dir() else 0o644)
    for path in [BUILDS, *BUILDS.parents]:
        if path == Path("/"):
            break
        path.chmod(path.stat().st_mode | 0o001)   # nobody may pass through to HOME


def _installed(name: str, home: Path) -> Plugin:
    libraries = list((home / ".local" / "lib" / "wireshark" / "plugins").rglob("*.so"))
    assert len(libraries) == 1, libraries
    return Plugin(name, home, libraries[0])


def installed_plugin(name: str, build: Path) -> Plugin:
    """A plugin built elsewhere (a CMake build folder of dissector/native, as `make upstream-patch`
    leaves one), given a HOME of its own under build/native-tests/home-<name>."""
    BUILDS.mkdir(parents=True, exist_ok=True)
    home = BUILDS / f"home-{name}"
    _install(build / "plugins", home)
    return _installed(name, home)


_PLUGINS: dict[str, Plugin] = {}


def plugin(variant: str = "gcc") -> Plugin:
    if variant not in _PLUGINS:
        _PLUGINS[variant] = build_plugin(variant)
    return _PLUGINS[variant]


def _empty_home() -> Path:
    home = BUILDS / "home-empty"
    home.mkdir(parents=True, exist_ok=True)
    home.chmod(0o755)
    return home


Capture = Union[bytes, Path]


def _readable(capture: Capture) -> Path:
    """The capture as a file every user may read (tshark reads a pipe in one pass only, and `-2`
    needs a file): a copy under build/native-tests/captures named by its content."""
    data = capture if isinstance(capture, bytes) else Path(capture).read_bytes()
    folder = BUILDS / "captures"
    folder.mkdir(parents=True, exist_ok=True)
    folder.chmod(0o755)
    for path in [BUILDS, *BUILDS.parents]:
        if path == Path("/"):
            break
        path.chmod(path.stat().st_mode | 0o001)   # nobody may pass through to it
    path = folder / f"{hashlib.sha256(data).hexdigest()[:24]}.pcap"
    if not path.is_file():
        partial = path.with_suffix(f".{os.getpid()}.part")
        partial.write_bytes(data)
        partial.chmod(0o644)
        partial.replace(path)
    return path


def native_tshark(args: Sequence[str], stdin: bytes = b"", variant: str = "gcc", env: Optional[dict] = None,
                  timeout: float = 600) -> subprocess.CompletedProcess:
    """tshark with the native plugin and these arguments (`-G plugins`, `-r - ...`)."""
    return tshark_with(plugin(variant), args, stdin, env, timeout)


def tshark_with(built: Plugin, args: Sequence[str], stdin: bytes = b"", env: Optional[dict] = None,
                timeout: float = 600) -> subprocess.CompletedProcess:
    """tshark with this build of the plugin (as nobody under root) and these arguments."""
    as_user = NOBODY if os.geteuid() == 0 else []
    environment = {**os.environ, "HOME": str(built.home), **(env or {})}
    environment.pop("XDG_CONFIG_HOME", None)
    return subprocess.run([*as_user, "tshark", *args], input=stdin, capture_output=True, env=environment,
                          timeout=timeout)


def run_native(capture: Capture, *args: str, variant: str = "gcc", env: Optional[dict] = None,
               timeout: float = 600) -> subprocess.CompletedProcess:
    """tshark -r with the native plugin."""
    return native_tshark(["-r", str(_readable(capture)), *args], b"", variant, env, timeout)


def run_plugin(built: Plugin, capture: Capture, *args: str, timeout: float = 600) -> subprocess.CompletedProcess:
    """tshark -r with this build of the plugin."""
    return tshark_with(built, ["-r", str(_readable(capture)), *args], timeout=timeout)


def run_lua(capture: Capture, *args: str, lua: Sequence[Path] = (), timeout: float = 600) -> subprocess.CompletedProcess:
    """tshark -r with these Lua dissectors only (generated/lua/<name>.lua)."""
    scripts = [a for path in lua for a in ("-X", f"lua_script:{path}")]
    environment = {**os.environ, "HOME": str(_empty_home())}
    environment.pop("XDG_CONFIG_HOME", None)
    return subprocess.run(["tshark", "-r", str(_readable(capture)), *scripts, *args], capture_output=True,
                          env=environment, timeout=timeout)


def lua_plugin(name: str) -> Path:
    """The Lua dissector of one interface: urwire.lua for the primary (`ur`), else <name>.lua."""
    return LUA / ("urwire.lua" if name == "ur" else f"{name}.lua")


def checked(result: subprocess.CompletedProcess) -> str:
    """tshark's stdout, after failing on a bad exit, a Lua error or anything on stderr but the
    root warning."""
    err = "\n".join(line for line in result.stderr.decode(errors="replace").splitlines()
                    if "Running as user" not in line)
    assert result.returncode == 0, f"tshark exited {result.returncode}: {err[:3000]}"
    out = result.stdout.decode("utf-8", errors="replace")
    assert "Lua: Error" not in err + out and "_ws.lua.error" not in out, (err + out)[:3000]
    assert err.strip() == "", err[:3000]
    return out


@dataclass
class Shown:
    """What one dissector shows of a capture: each frame's layers of the protocols under test
    (tshark -T json), each frame's Info column, and the expert infos in frame order."""
    layers: list
    info: list
    experts: list


def _layers_of(frames: list, protocols: Sequence[str]) -> list:
    return [{p: f["_source"]["layers"][p] for p in protocols if p in f["_source"]["layers"]} for f in frames]


def _experts_in(node, out: list) -> None:
    if isinstance(node, dict):
        for key, value in node.items():
            if key == "_ws.expert":
                out.extend(value if isinstance(value, list) else [value])
            else:
                _experts_in(value, out)
    elif isinstance(node, list):
        for item in node:
            _experts_in(item, out)


def shown(run, capture: Capture, protocols: Sequence[str], *args: str) -> Shown:
    """run is run_native or a run_lua with its scripts bound (functools.partial)."""
    frames = json.loads(checked(run(capture, "-2", "-T", "json", "--no-duplicate-keys", *args)) or "[]")
    layers = _layers_of(frames, protocols)
    info = checked(run(capture, "-2", "-T", "fields", "-e", "_ws.col.Info", *args)).splitlines()
    experts: list = []
    _experts_in(layers, experts)
    return Shown(layers, info, experts)
