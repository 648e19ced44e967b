"""What the differential tests of a native dissector and its Lua twin share: captures that hold
many robot streams (one TCP session each, so that a few tshark runs cover them all), the
registered fields of either dissector (`tshark -G fields`), and the comparison itself.

Helpers of the fixed-layout interfaces (real-time, the ROS driver's sockets); harness.py runs
tshark."""
from __future__ import annotations

import functools
import os
import random
import re
import shutil
import subprocess
from functools import partial
from pathlib import Path
from typing import Iterable, Sequence, Union

from tests.native import harness
from tests.tools import capture
from tests.tools.capture import Segment


Protocols = Union[str, Sequence[str]]


def _names(protocols: Protocols) -> list[str]:
    return [protocols] if isinstance(protocols, str) else sorted(protocols)


def cuts(data: bytes, seed: int, smallest: int = 1, largest: int = 7) -> list[bytes]:
    """The stream in segments of `smallest` to `largest` bytes."""
    rng = random.Random(seed)
    out, pos = [], 0
    while pos < len(data):
        n = rng.randint(smallest, largest)
        out.append(data[pos:pos + n])
        pos += n
    return out


def sessions(streams: Iterable[Sequence[Union[bytes, Segment]]], port: int, name: str, first_client_port: int = 41000,
             client_says: bytes = b"") -> Path:
    """A pcap of one TCP session per stream (each a list of segment payloads the side on `port`
    sends, or of capture.Segment in either direction); `client_says` is sent by each client first
    when given. It is written where
    tshark, run as nobody, can read it by name: tshark reads a pipe in one pass only, and the
    comparison runs two (-2)."""
    frames: list[bytes] = []
    for i, segments in enumerate(streams):
        said = [Segment(False, client_says)] if client_says else []
        ours = [s if isinstance(s, Segment) else Segment(True, s) for s in segments]
        frames += capture.session_frames(said + [s for s in ours if s.payload], port=port,
                                         client_port=first_client_port + i)
    return readable(capture.write(_captures() / f"{name}-{os.getpid()}.pcap", frames))


def _captures() -> Path:
    folder = harness.BUILDS / "captures"
    folder.mkdir(parents=True, exist_ok=True)
    harness.plugin("gcc")                   # makes build/native-tests passable to nobody
    folder.chmod(0o755)
    return folder


def readable(path: Path) -> Path:
    """The capture, copied where nobody may read it unless it is there already."""
    if path.parent != _captures():
        path = Path(shutil.copy(path, _captures() / path.name))
    path.chmod(0o644)
    return path


def run_native(path: Path, *args: str, variant: str = "gcc", alone: Protocols = ()) -> subprocess.CompletedProcess:
    """tshark with the native plugin; `alone`: only these of its protocols enabled, as only their
    Lua dissectors are loaded in the run it is compared with."""
    keep = _names(alone)
    others = [a for name in _plugin_protocols(variant) if name not in keep for a in ("--disable-protocol", name)] \
        if keep else []
    return harness.native_tshark(["-r", str(path), *others, *args], variant=variant)


def run_sanitized(path: Path, *args: str) -> subprocess.CompletedProcess:
    """tshark with the plugin built under ASan and UBSan (harness variant "asan"): the ASan runtime
    preloaded into tshark, which is not built with it; leaks are Wireshark's own at exit, so not
    reported. A report goes to stderr (and UBSan aborts), which harness.checked refuses."""
    libasan = subprocess.run(["gcc", "-print-file-name=libasan.so"], capture_output=True, text=True,
                             check=True).stdout.strip()
    env = {"LD_PRELOAD": libasan, "ASAN_OPTIONS": "detect_leaks=0:abort_on_error=1",
           "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1"}
    return harness.native_tshark(["-r", str(path), *args], variant="asan", env=env)


_PROTOCOLS: dict[str, list[str]] = {}


def _plugin_protocols(variant: str) -> list[str]:
    """The protocols the plugin registers: those of tshark -G protocols that have a Lua twin."""
    if variant not in _PROTOCOLS:
        out = harness.native_tshark(["-G", "protocols"], variant=variant).stdout.decode().splitlines()
        known = {"ur" if path.stem == "urwire" else path.stem for path in harness.LUA.glob("*.lua")}
        _PROTOCOLS[variant] = sorted({line.split("\t")[2] for line in out if line.count("\t") == 2} & known)
    return _PROTOCOLS[variant]


def run_lua(path: Path, *args: str, protocol: Protocols) -> subprocess.CompletedProcess:
    """tshark with only these protocols' Lua dissectors, as harness.run_lua, reading the file by name."""
    env = {**os.environ, "HOME": str(harness.BUILDS / "home-empty")}
    (harness.BUILDS / "home-empty").mkdir(parents=True, exist_ok=True)
    env.pop("XDG_CONFIG_HOME", None)
    scripts = [a for name in _names(protocol) for a in ("-X", f"lua_script:{harness.lua_plugin(name)}")]
    return subprocess.run(["tshark", "-r", str(path), *scripts, *args], capture_output=True, env=env, timeout=600)


def compare(path: Path, protocol: Protocols, *args: str, variant: str = "gcc") -> harness.Shown:
    """The native dissectors and the Lua ones of these protocols, each side alone, on one capture:
    the same -T json layers of the protocols, Info column and expert infos. Returns what the
    native ones showed."""
    names = _names(protocol)
    native = harness.shown(partial(run_native, variant=variant, alone=names), path, names, *args)
    twin = harness.shown(partial(run_lua, protocol=names), path, names, *args)
    native.layers = [as_lua_writes(layer) for layer in native.layers]
    assert len(native.info) == len(twin.info)
    for frame, (mine, theirs) in enumerate(zip(native.info, twin.info)):
        assert mine == theirs, f"Info of frame {frame + 1}"
    assert native.experts == twin.experts
    for frame, (mine, theirs) in enumerate(zip(native.layers, twin.layers)):
        assert mine == theirs, f"frame {frame + 1}"
    assert len(native.layers) == len(twin.layers)
    return native


_ABBREV = re.compile(r"[A-Za-z0-9_.-]+")     # RTDE names hold capitals: rtde.actual_TCP_pose
LUA_TEXT = "_ws.lua.text"


def as_lua_writes(node):
    """-T json of a native tree as tshark writes the same tree built by Lua: a text item (a
    subtree such as "Actual joint position (rad)") is keyed by its text in C, while Lua adds it
    with the field _ws.lua.text, whose key hides the text. The text items of one level become one
    _ws.lua.text entry, in order (a list when there are several, as --no-duplicate-keys writes)."""
    if isinstance(node, list):
        return [as_lua_writes(item) for item in node]
    if not isinstance(node, dict):
        return node
    out: dict = {}
    texts = []
    for key, value in node.items():
        if _ABBREV.fullmatch(key):
            out[key] = as_lua_writes(value)
        else:
            texts.append(as_lua_writes(value))
    if texts:
        out[LUA_TEXT] = texts[0] if len(texts) == 1 else texts
    return out


def _lua_home(protocols: tuple[str, ...]) -> Path:
    """A HOME whose personal plugin folder holds only these protocols' Lua dissectors: where
    `tshark -G` sees a Lua dissector's fields (it reads -G before any -X option)."""
    home = harness.BUILDS / f"home-lua-{'-'.join(protocols)}"
    folder = home / ".local" / "lib" / "wireshark" / "plugins"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True, exist_ok=True)
    for name in protocols:
        shutil.copy(harness.lua_plugin(name), folder / harness.lua_plugin(name).name)
    for path in [home, *home.rglob("*")]:
        path.chmod(0o755 if path.is_dir() else 0o644)
    return home


REPORTS = ("fields", "protocols", "defaultprefs")


@functools.lru_cache(maxsize=None)
def _report(report: str, lua_of: tuple[str, ...]) -> tuple[str, ...]:
    """The lines of `tshark -G <report>`: with the native plugin, or with only the Lua dissectors
    of the protocols `lua_of`."""
    if lua_of:
        as_user = harness.NOBODY if os.geteuid() == 0 else []
        env = {**os.environ, "HOME": str(_lua_home(lua_of))}
        env.pop("XDG_CONFIG_HOME", None)
        out = subprocess.run([*as_user, "tshark", "-G", report], capture_output=True, env=env, timeout=300)
    else:
        out = harness.native_tshark(["-G", report])
    assert out.returncode == 0, out.stderr
    return tuple(out.stdout.decode().splitlines())


def native_report(report: str) -> tuple[str, ...]:
    """The lines of `tshark -G <report>` with the native plugin, once per test process."""
    return _report(report, ())


def registered(protocol: str, lua: bool, loaded: Protocols = ()) -> list[str]:
    """What the protocol registers, as tshark -G reports it: its fields (`fields`), its names
    (`protocols`) and its preferences with their defaults (`defaultprefs`), sorted (Lua registers
    its fields in table order). With `lua`, the Lua dissectors of `loaded` (default: the protocol
    alone) are those tshark loads."""
    def ours(line: str) -> bool:
        if protocol not in line:      # most of Wireshark's lines: no need to split them
            return False
        words = line.lstrip("#").split("\t")
        return any(w == protocol or w.startswith(protocol + ".") for w in words)

    lua_of = tuple(_names(loaded or protocol)) if lua else ()
    return sorted(f"{report}: {line}" for report in REPORTS for line in _report(report, lua_of) if ours(line))
