"""The pictures in dissector/README.md, taken from the real Wireshark GUI with the dissector on the
bundled capture: `make screenshots` runs this under xvfb-run.

packet_list.png     the packet list of the UR messages, with the Info column
robot_state.png     one robot state expanded: labels, values and units
display_filter.png  a display filter on a joint value
io_graph.png        Statistics > I/O Graphs of the joint positions over time (100 ms interval)
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.tools.gui import HEIGHT, WIDTH, Wireshark, make_home  # noqa: E402

CAPTURE = ROOT / "dissector" / "samples" / "primary_session.pcapng"
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
    details_only = ["-o", "gui.layout_content_1:PDETAILS", "-o", "gui.layout_content_2:NONE",
                    "-o", "gui.layout_content_3:NONE"]
    with Wireshark(CAPTURE, home, ["-g", str(STATE_FRAME), *details_only]) as ws:
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


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for shot in (packet_list, robot_state, display_filter, io_graph):
            print(f"wrote {shot(Path(tmp)).relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
