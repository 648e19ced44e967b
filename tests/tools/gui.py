"""Drive the Wireshark GUI (wireshark-qt) on an X server without a window manager, as xvfb-run
gives one: start it on a capture with the dissector, find its windows, press keys, click, take
screenshots, stop it. The GUI smoke test (tests/lua/test_gui.py) and `make screenshots`
(scripts/screenshots.py) use it. Needs DISPLAY, wireshark, xdotool and ImageMagick's import.

    python3 -m tests.tools.gui smoke CAPTURE FILTER    # under xvfb-run: prints what the GUI showed, as JSON
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Optional, Sequence

ROOT = Path(__file__).resolve().parents[2]
PLUGIN = ROOT / "generated" / "lua" / "urwire.lua"
PROBE = Path(__file__).resolve().parent / "gui_probe.lua"
WIDTH, HEIGHT = 1600, 1000   # the main window; the X screen must be at least this large
SCREEN = f"-screen 0 {WIDTH}x{HEIGHT}x24"


def make_home(root: Path, recent: Optional[dict] = None, io_graphs: Sequence[str] = ()) -> Path:
    """A fresh Wireshark configuration under root/.config/wireshark (used as HOME): the main
    window at the size of the screen, the given `recent` settings (gui.packet_list_show: FALSE
    hides a pane) and I/O graphs (lines of the io_graphs UAT file)."""
    config = root / ".config" / "wireshark"
    config.mkdir(parents=True, exist_ok=True)
    common = {"gui.geometry_main_x": 0, "gui.geometry_main_y": 0, "gui.geometry_main_width": WIDTH,
              "gui.geometry_main_height": HEIGHT, "gui.geometry_main_maximized": "FALSE",
              "privs.warn_if_elevated": "FALSE"}
    (config / "recent_common").write_text("".join(f"{k}: {v}\n" for k, v in common.items()))
    if recent:
        (config / "recent").write_text("".join(f"{k}: {v}\n" for k, v in recent.items()))
    if io_graphs:
        (config / "io_graphs").write_text("".join(line + "\n" for line in io_graphs))
    return root


def xdotool(*args: str, check: bool = True) -> str:
    res = subprocess.run(["xdotool", *args], capture_output=True, text=True, timeout=30)
    if check and res.returncode != 0:
        raise RuntimeError(f"xdotool {' '.join(args)}: {res.stderr.strip()}")
    return res.stdout


class Wireshark:
    """One wireshark process on a capture, with the dissector (and more Lua scripts) loaded."""

    def __init__(self, capture: Path, home: Path, args: Sequence[str] = (), lua: Sequence[Path] = (),
                 env: Optional[dict] = None, plugin: Path = PLUGIN):
        self.capture = Path(capture)
        self.log = home / "wireshark.log"
        scripts = [f"lua_script:{p}" for p in (plugin, *lua)]
        self.cmd = ["wireshark", "-r", str(self.capture), *[a for s in scripts for a in ("-X", s)], *args,
                    "--log-file", str(home / "wireshark-log.txt")]
        self.env = dict(os.environ, HOME=str(home), XDG_RUNTIME_DIR=str(home), **(env or {}))
        self.proc: Optional[subprocess.Popen] = None

    def __enter__(self) -> "Wireshark":
        with self.log.open("wb") as out:
            self.proc = subprocess.Popen(self.cmd, stdout=out, stderr=subprocess.STDOUT, env=self.env)
        return self

    def __exit__(self, *exc) -> None:
        self.stop()

    def stop(self) -> None:
        if self.proc and self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(10)

    def output(self) -> str:
        """What it wrote to its console and its log file."""
        logs = [self.log, self.log.with_name("wireshark-log.txt")]
        return "".join(p.read_text(errors="replace") for p in logs if p.exists())

    def windows(self) -> list[tuple[str, str]]:
        """Its visible top-level windows: (id, title)."""
        assert self.proc is not None
        ids = xdotool("search", "--onlyvisible", "--pid", str(self.proc.pid), check=False).split()
        return [(w, xdotool("getwindowname", w, check=False).strip()) for w in ids]

    def wait_window(self, title: str, timeout: float = 60) -> str:
        """The id of its visible window whose title holds `title`, once it shows."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.proc is not None and self.proc.poll() is not None:
                raise RuntimeError(f"wireshark exited {self.proc.returncode}: {self.output()[-2000:]}")
            for wid, name in self.windows():
                if title in name:
                    return wid
            time.sleep(0.3)
        raise TimeoutError(f"no window '{title}' after {timeout} s; windows: {self.windows()}")

    def main_window(self, timeout: float = 60) -> str:
        return self.wait_window(self.capture.name, timeout)

    def keys(self, window: Optional[str], *keys: str) -> None:
        """Press keys in a window (given the focus first), or, with no window, wherever the focus
        is: in an open menu or list that a click popped up."""
        if window is not None:
            xdotool("windowfocus", "--sync", window)
        for k in keys:
            xdotool("key", "--clearmodifiers", k)
            time.sleep(0.15)

    def click(self, window: str, x: int, y: int) -> None:
        xdotool("mousemove", "--window", window, str(x), str(y), "click", "1")
        time.sleep(0.3)

    def resize(self, window: str, x: int, y: int, width: int, height: int) -> None:
        xdotool("windowsize", "--sync", window, str(width), str(height))
        xdotool("windowmove", "--sync", window, str(x), str(y))

    @staticmethod
    def screenshot(window: str, path: Path) -> Path:
        # Park the pointer in a corner first: a tooltip or a hover highlight is not the picture.
        xdotool("mousemove", "0", str(HEIGHT - 1))
        time.sleep(0.8)
        # A 256-colour palette (screens have few colours) and no date chunks: small files, and the
        # same picture gives the same file.
        subprocess.run(["import", "-window", window, "-define", "png:exclude-chunks=date,time", f"PNG8:{path}"],
                       check=True, timeout=60)
        return path


def read_counts(path: Path) -> Optional[dict]:
    try:
        text = path.read_text().split()
    except FileNotFoundError:
        return None
    return {k: int(v) for k, v in (pair.split("=") for pair in text)}


def smoke(capture: Path, display_filter: str, timeout: float = 60, plugin: Path = PLUGIN) -> dict:
    """Open the capture in the GUI with the dissector and a display filter. What it showed: the
    probe's counts (frames read, frames the filter shows, frames with a Lua error or a fault),
    its windows (a failing Lua script opens an error dialog), and the Lua lines of its output."""
    with tempfile.TemporaryDirectory() as tmp:
        home = make_home(Path(tmp))
        out = home / "probe.txt"
        env = {"URWIRE_PROBE_OUT": str(out), "URWIRE_PROBE_FILTER": display_filter}
        result: dict = {"counts": None, "windows": [], "lua_lines": []}
        with Wireshark(capture, home, ["-Y", display_filter], [PROBE], env, plugin) as ws:
            deadline, last, steady = time.monotonic() + timeout, None, 0
            while time.monotonic() < deadline and steady < 4:
                time.sleep(0.5)
                counts = read_counts(out)
                steady = steady + 1 if counts and counts == last else 0
                last = counts
                if ws.proc.poll() is not None:
                    break
            result["counts"] = last
            result["windows"] = [name for _, name in ws.windows()]
            result["lua_lines"] = [ln for ln in ws.output().splitlines() if "Lua" in ln or "lua" in ln]
        return result


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m tests.tools.gui")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("smoke", help="open a capture in the GUI with a display filter; print what it showed")
    run.add_argument("capture", type=Path)
    run.add_argument("filter")
    run.add_argument("--plugin", type=Path, default=PLUGIN)
    run.add_argument("--timeout", type=float, default=60)
    args = parser.parse_args(argv)
    print(json.dumps(smoke(args.capture, args.filter, args.timeout, args.plugin)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
