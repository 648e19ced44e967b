"""The pictures in dissector/README.md, taken from the real Wireshark GUI with the dissector on the
bundled capture: `make screenshots` runs this under xvfb-run.

packet_list.png     the packet list of the UR messages, with the Info column
robot_state.png     one robot state expanded: labels, values and units
display_filter.png  a display filter on a joint value
io_graph.png        Statistics > I/O Graphs of the joint positions over time (100 ms interval)

and a picture of each other interface of the cell (TREE_SHOTS: realtime.png, rtde_output.png, ...),
from the cell capture with every Lua dissector of generated/lua/, as `make install-dissector
NATIVE=no` installs them: the details pane of one telling frame, opened at the rows its caption
in the README points to. `python3 scripts/screenshots.py NAME.png ...` takes only those named.
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.tools.gui import HEIGHT, PLUGIN, WIDTH, Wireshark, make_home  # noqa: E402

CAPTURE = ROOT / "dissector" / "samples" / "primary_session.pcapng"
CELL = ROOT / "dissector" / "samples" / "cell_session.pcapng"
CELL_LUA = sorted(p for p in PLUGIN.parent.glob("*.lua") if p != PLUGIN)   # beside the primary's plugin
DETAILS_ONLY = ["-o", "gui.layout_content_1:PDETAILS", "-o", "gui.layout_content_2:NONE",
                "-o", "gui.layout_content_3:NONE"]
OUT = ROOT / "dissector" / "images"
STATE_FRAME = 30              # a robot state (and a global-variables update) while the program runs
FILTER = 'ur.robot_mode_data.robot_mode == "RUNNING" && ur.joint_data.q_actual > 1.8'
# The io_graphs UAT: enabled, name, display filter, colour, style, Y axis, Y field, SMA period, factor.
IO_GRAPHS = [f'"TRUE","{name}","ur.joint_data","{colour}","Line","{axis}(Y Field)","ur.joint_data.q_actual","None","1"'
             for name, colour, axis in (("Highest joint position (rad)", "#d62728", "MAX"),
                                        ("Mean of the six joints (rad)", "#1f77b4", "AVG"),
                                        ("Lowest joint position (rad)", "#2ca02c", "MIN"))]
IO_SIZE = (1400, 900)
IO_INTERVAL_COMBO = (582, 845)   # where the Interval box sits in an I/O Graphs dialog of IO_SIZE


def packet_list(tmp: Path) -> Path:
    home = make_home(tmp / "list")
    with Wireshark(CAPTURE, home, ["-Y", "ur", "-g", "18"]) as ws:
        return ws.screenshot(ws.main_window(), OUT / "packet_list.png")


def robot_state(tmp: Path) -> Path:
    """The details pane alone, the robot state's subtrees expanded: a click in the pane's empty
    lower part gives it the focus, then Home, four rows down (past Frame, Ethernet, IP and TCP)
    and Shift+Right (Expand Subtrees)."""
    home = make_home(tmp / "state")
    with Wireshark(CAPTURE, home, ["-g", str(STATE_FRAME), *DETAILS_ONLY]) as ws:
        main = ws.main_window()
        ws.click(main, WIDTH // 2, HEIGHT - 100)
        ws.keys(main, "Home", *["Down"] * 4, "shift+Right")
        return ws.screenshot(main, OUT / "robot_state.png")


def display_filter(tmp: Path) -> Path:
    home = make_home(tmp / "filter")
    with Wireshark(CAPTURE, home, ["-Y", FILTER]) as ws:
        return ws.screenshot(ws.main_window(), OUT / "display_filter.png")


def io_graph(tmp: Path) -> Path:
    """Statistics (Alt+S) > I/O Graphs (the seventh item), its graphs from the io_graphs file,
    the interval set to 100 ms (three steps up from 1 s), one robot state per interval."""
    home = make_home(tmp / "io", io_graphs=IO_GRAPHS)
    with Wireshark(CAPTURE, home) as ws:
        main = ws.main_window()
        ws.keys(main, "alt+s", *["Down"] * 6, "Return")
        dialog = ws.wait_window("I/O Graphs")
        ws.resize(dialog, 100, 50, *IO_SIZE)
        ws.click(dialog, *IO_INTERVAL_COMBO)
        ws.keys(None, "Up", "Up", "Up", "Return")
        return ws.screenshot(dialog, OUT / "io_graph.png")


@dataclass
class Row:
    """One row of the details pane: its text and the rows under it."""
    text: str
    children: list["Row"] = field(default_factory=list)


def frame_tree(frame: int) -> list[Row]:
    """The top rows of a cell frame's details, as `tshark -V` prints them with the same dissectors
    (two passes, as the GUI reads a file: a request's link to its later reply shows)."""
    lua = [a for p in (PLUGIN, *CELL_LUA) for a in ("-X", f"lua_script:{p}")]
    text = subprocess.run(["tshark", "-2", "-r", str(CELL), *lua, "-Y", f"frame.number == {frame}", "-V"],
                          capture_output=True, text=True, check=True, timeout=120).stdout
    roots: list[Row] = []
    parents: list[Row] = []          # the row open at each depth
    for line in filter(str.strip, text.splitlines()):
        depth = (len(line) - len(line.lstrip(" "))) // 4
        row = Row(line.strip())
        (parents[depth - 1].children if depth else roots).append(row)
        parents[depth:] = [row]
    return roots


class DetailsPane:
    """The keys that walk a details pane to its rows, counted over the tree tshark prints: Qt's tree
    would find a row by its typed text, but Wireshark sends typed letters to the display filter.
    After Home the first row is selected and every row is collapsed."""

    def __init__(self, roots: list[Row]):
        self.shown = list(roots)
        self.at = 0

    def find(self, path: tuple[str, ...]) -> Row:
        """The row at a path of text beginnings (the first match at each level)."""
        rows, row = self.shown, None
        for prefix in path:
            row = next((r for r in rows if r.text.startswith(prefix)), None)
            if row is None:
                raise LookupError(f"no row {prefix!r} under {path}: {[r.text for r in rows]}")
            rows = row.children
        assert row is not None
        return row

    def go(self, path: tuple[str, ...]) -> list[str]:
        target = self.shown.index(self.find(path))      # ValueError: a parent is not expanded
        steps, self.at = target - self.at, target
        return ["Down"] * steps if steps >= 0 else ["Up"] * -steps

    def expand(self, path: tuple[str, ...], everything: bool = False) -> list[str]:
        """Right opens a row; Shift+Right (Expand Subtrees) opens it and every row under it."""
        keys = self.go(path)
        row = self.shown[self.at]
        self.shown[self.at + 1:self.at + 1] = list(descendants(row)) if everything else row.children
        return [*keys, "shift+Right" if everything else "Right"]


def descendants(row: Row):
    for child in row.children:
        yield child
        yield from descendants(child)


@dataclass
class TreeShot:
    """A cell frame in the details pane: rows opened (`expand`), opened with all under them
    (`expand_all`), then one row selected; each row is a path of text beginnings. The window
    shows at most `rows` rows, if given (a long tail of alike rows tells no more)."""
    image: str
    frame: int
    select: tuple[str, ...]
    expand: tuple[tuple[str, ...], ...] = ()
    expand_all: tuple[tuple[str, ...], ...] = ()
    rows: Optional[int] = None


RT, RTDE = "Universal Robots real-time", "Universal Robots Real-Time Data Exchange"
DASH, INTERPRETER = "Universal Robots dashboard server", "Universal Robots interpreter mode"
TREE_SHOTS = (
    # A real-time packet: the joints and the tool pose with units, the modes by name.
    TreeShot("realtime.png", 35, (RT, "Robot mode"),
             expand=((RT,), (RT, "Actual joint position"), (RT, "Actual tool pose"))),
    # RTDE: an output data package of a recipe of time, joints and robot mode; a setup reply.
    TreeShot("rtde_output.png", 156, (RTDE, "Robot mode"), expand_all=((RTDE,),)),
    TreeShot("rtde_setup_reply.png", 134, (RTDE, "[Request in"), expand_all=((RTDE,),)),
    # Three dashboard replies in one segment, each paired with its command.
    TreeShot("dashboard.png", 110, (DASH, "[Request in"),
             expand_all=((f"{DASH}: Loading",), (f"{DASH}: Starting",), (f"{DASH}: Stopped",))),
    # The ROS driver's sockets.
    TreeShot("reverse.png", 39, ("Reverse interface command", "Control mode"),
             expand=(("Reverse interface command",),)),
    TreeShot("script_sender.png", 62, ("Universal Robots driver script sender", "[Request in"),
             expand_all=(("Universal Robots driver script sender",),)),
    TreeShot("trajectory.png", 41, ("Trajectory point", "Segment duration"), expand=(("Trajectory point",),)),
    TreeShot("script_command.png", 42, ("Script command", "Command"), expand=(("Script command",),), rows=12),
    # Interpreter mode: the acks of two statements; the gripper: three GET replies.
    TreeShot("interpreter.png", 65, (INTERPRETER, "[Request in"),
             expand_all=((f"{INTERPRETER}: ack: 1",), (f"{INTERPRETER}: ack: 2",))),
    TreeShot("gripper.png", 136, ("Robotiq gripper", "[Request in"),
             expand_all=(("Robotiq gripper URCap socket: PRE",), ("Robotiq gripper URCap socket: OBJ",),
                         ("Robotiq gripper URCap socket: POS",))),
)
TREE_WIDTH = 1100    # the longest row (Frame) fits
ROW = 17             # the height of a details row, in pixels
PANE_TOP = 92        # menu, tool and filter bars above the details pane
STATUS_BAR = 28      # below it


def walk(shot: TreeShot) -> tuple[DetailsPane, list[str]]:
    """The pane as the shot leaves it, and the keys that get it there."""
    pane = DetailsPane(frame_tree(shot.frame))
    keys = ["Home"]
    for path in shot.expand:
        keys += pane.expand(path)
    for path in shot.expand_all:
        keys += pane.expand(path, everything=True)
    return pane, keys + pane.go(shot.select)


def tree_shot(shot: TreeShot, tmp: Path) -> Path:
    """The window sized to the rows the shot opens (and one empty row, where a click gives the pane
    the focus), at most the screen's height; then Home and the counted keys."""
    pane, keys = walk(shot)
    rows = min(len(pane.shown), shot.rows or len(pane.shown))
    height = min(HEIGHT, PANE_TOP + ROW * (rows + 1) + STATUS_BAR)
    home = make_home(tmp / shot.image)
    with Wireshark(CELL, home, ["-g", str(shot.frame), *DETAILS_ONLY], CELL_LUA) as ws:
        main = ws.main_window()
        ws.resize(main, 0, 0, TREE_WIDTH, height)
        ws.click(main, TREE_WIDTH // 2, height - STATUS_BAR - ROW // 2)
        ws.keys(main, *keys)
        return ws.screenshot(main, OUT / shot.image)


SHOTS = {"packet_list.png": packet_list, "robot_state.png": robot_state, "display_filter.png": display_filter,
         "io_graph.png": io_graph,
         **{s.image: (lambda tmp, s=s: tree_shot(s, tmp)) for s in TREE_SHOTS}}


def main(argv: list[str]) -> int:
    """Every picture, or those named on the command line (`python3 scripts/screenshots.py gripper.png`)."""
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for name in argv or SHOTS:
            print(f"wrote {SHOTS[name](Path(tmp)).relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
