"""docs/adding-a-firmware.md's checklist, walked on a throwaway copy of the tree with a made-up
software 5.27: one float64 appended to additional_info for the e-Series only, one RTDE output
variable and one dashboard command from 5.27. The spec edits, `make generate`, `make spec-diff`,
`make new-vector`, the vector laid out by hand (the bytes and values are written here, as a
maintainer writes them), then the targeted command on the primary vectors through Python, C (gcc,
clang, ASan/UBSan) and the Lua dissector in tshark, and the RTDE and dashboard vectors through
Python. `make test-vectors` runs the native dissectors and the other targets' RTDE and dashboard
vectors too; they are left out here to keep this walk near a minute.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

# Step 1: the spec edits, as the checklist says to write them.
PRIMARY_FIELD = """\
          - name: tcp_speed_scaling
            label: "TCP speed scaling"
            type: float64
            versions: {from: "5.27", through: "e-Series"}
            field_note: "Made up for tests/test_adding_a_firmware.py."
"""
RTDE_VARIABLE = """\
  - {name: tcp_speed_scaling, type: DOUBLE, direction: output, label: TCP speed scaling,
     since: {cb3: none, eseries: "5.27", polyscope_x: none}, field_note: "Made up for tests/test_adding_a_firmware.py."}
"""
DASHBOARD_COMMAND = """\
  - name: unlock_speed_scaling
    text: unlock speed scaling
    since: {e_series: "5.27", polyscope_x: none}
    doc: Made up for tests/test_adding_a_firmware.py.
    replies:
      - {name: unlocked, pattern: "Speed scaling unlocked"}
"""

# Step 3: what the maintainer changes in the scaffolded vector (copied from 5.25.1's), by hand.
HAND_EDITS = [
    ("# 1530 bytes in all", "# 1538 bytes in all"),
    ("  00 00 05 c3                                       # messageSize = 1475\n",
     "  00 00 05 cb                                       # messageSize = 1483\n"),
    ("  00 00 00 09                                       # packageSize = 9\n"
     "  08                                                # packageType = 8 (additional_info)\n",
     "  00 00 00 11                                       # packageSize = 17\n"
     "  08                                                # packageType = 8 (additional_info)\n"),
    ("  00                                                # reserved = 0\n  00 00 00 2b",
     "  00                                                # reserved = 0\n"
     "  3f e0 00 00 00 00 00 00                           # tcp_speed_scaling = 0.5 (double)\n  00 00 00 2b"),
    ('        reserved: 0\n      - type: "safety_data"',
     '        reserved: 0\n        tcp_speed_scaling: 0.5\n      - type: "safety_data"'),
]
VECTOR = "tests/golden/generation_eseries_5_27_robot_state.yaml"
GENERATED = ("c/{0}.c", "lua/{0}.lua", "epan/packet-{1}.c", "python/urwire/generated/{0}.py")
TARGETED = ("tests/python/test_vectors.py tests/python/test_rtde_vectors.py tests/python/test_dashboard.py "
            "tests/c/test_c_vectors.py tests/lua/test_vectors.py")


def once(text: str, old: str, new: str) -> str:
    assert text.count(old) == 1, old
    return text.replace(old, new)


@pytest.fixture
def tree(tmp_path) -> Path:
    """The tracked files of the working tree, as they are now, in a folder of their own."""
    listed = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True)
    if listed.returncode != 0:
        pytest.skip("not a git checkout: nothing says which files make the tree")
    out = tmp_path / "tree"
    for rel in filter(None, listed.stdout.decode().split("\0")):
        if (ROOT / rel).is_file():
            (out / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / rel, out / rel)
    return out


def make(tree: Path, *args: str) -> str:
    done = subprocess.run(["make", "--no-print-directory", *args], cwd=tree, capture_output=True, text=True,
                          env={**os.environ, "PYTHON": sys.executable})
    assert done.returncode == 0, f"make {' '.join(args)}:\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return done.stdout


def in_tree(tree: Path, code: str) -> str:
    """Python run against the copy's own package and generated bindings."""
    path = os.pathsep.join(str(tree / p) for p in ("python", "generated/python", "."))
    done = subprocess.run([sys.executable, "-c", code], cwd=tree, capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": path, "URWIRE_BACKEND": "python"})
    assert done.returncode == 0, done.stderr
    return done.stdout


@pytest.mark.deep          # about a minute: `make test-deep` walks the whole checklist
def test_the_checklist_with_a_made_up_5_27(tree):
    # 1. The spec: a field for the e-Series only, an RTDE variable, a dashboard command.
    primary = tree / "spec" / "ur_primary.yaml"
    primary.write_text(once(primary.read_text(encoding="utf-8"), "\n      calibration_data:\n",
                            PRIMARY_FIELD + "\n      calibration_data:\n"), encoding="utf-8")
    for name, tail in (("rtde.yaml", RTDE_VARIABLE), ("ur_dashboard.yaml", DASHBOARD_COMMAND)):
        spec = tree / "spec" / name
        spec.write_text(spec.read_text(encoding="utf-8").rstrip("\n") + "\n" + tail, encoding="utf-8")
    make(tree, "generate")

    # 2. What the decoders will do: 5.27 grows additional_info, PolyScope X does not.
    assert "+ tcp_speed_scaling: float64" in make(tree, "spec-diff", "FROM=5.26", "TO=5.27")
    assert make(tree, "spec-diff", "FROM=5.26", "TO=10.7").startswith("5.26 -> 10.7: no change\n")

    # 3. The vector: scaffolded, refused while unchecked, then laid out by hand.
    assert VECTOR in make(tree, "new-vector", "VERSION=5.27")
    vector = tree / VECTOR
    text = vector.read_text(encoding="utf-8")
    assert text.startswith("# TODO: check")
    text = "description:" + text.split("\ndescription:", 1)[1]
    text = once(text, text.splitlines()[0] + "\n",
                'description: "e-Series 5.27 (made up): additional_info grows tcp_speed_scaling (float64)."\n')
    for old, new in HAND_EDITS:
        text = once(text, old, new)
    vector.write_text(text, encoding="utf-8")

    # 4. The targeted command: the 5.27 vector, with and without its Version message, passes in
    # every target run, and so does every vector that was there before (PolyScope X's among them).
    out = make(tree, "test-vectors", f"VECTOR_TESTS={TARGETED}", f"PYTEST={sys.executable} -m pytest -rA")
    runs = [line for line in out.splitlines() if "generation_eseries_5_27_robot_state" in line]
    # Twice (with and without the Version message) in Python, under each of 4 C builds, and in 6
    # segmentations in tshark.
    assert len(runs) == 2 + 2 * 4 + 2 * 6 and all(line.startswith("PASSED") for line in runs), runs

    # The RTDE variable and the dashboard command reach every target and the simulated robot's tables.
    for interface, name in (("rtde", "tcp_speed_scaling"), ("ur_dashboard", "unlock speed scaling")):
        for generated in GENERATED:
            path = tree / "generated" / generated.format(interface, interface.replace("_", "-"))
            assert name in path.read_text(encoding="utf-8"), path
    told = in_tree(tree, """
from urwire import rtde
from urwire.generated import ur_dashboard
from urwire.live.serve_rtde import offers
from urwire.text_lines import find_command
row = rtde.variable("tcp_speed_scaling", "output")
command, _ = find_command(ur_dashboard.LOOKUP, "unlock speed scaling")
print(row.type, offers(row, (5, 26, 0)), offers(row, (5, 27, 0)))
print(command.name, command.available((5, 26, 0)), command.available((5, 27, 0)))
""")
    assert told.split("\n")[:2] == ["DOUBLE False True", "unlock_speed_scaling False True"]

    # `urwire serve` answers the new command from the spec's reply, on 5.27 only.
    told = in_tree(tree, """
from urwire.live.robot_cell import RobotCell
from urwire.live.robot_models import model_for
from urwire.live.serve_dashboard import DashboardSession
for version in ((5, 26, 0), (5, 27, 0)):
    print(DashboardSession(RobotCell(version, model_for(version)), lambda: 0.0).answer("unlock speed scaling"))
""")
    assert told.splitlines() == ["could not understand: 'unlock speed scaling'", "Speed scaling unlocked"]
