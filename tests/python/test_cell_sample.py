"""The bundled capture of a whole cell (dissector/samples/cell_session.pcapng, written by `make
samples` from the golden vectors): current, and decoded by `urwire decode` with no error record,
every interface of the cell in it, in JSON and in the readable views the demo shows. tshark's
reading of it is tested in tests/lua/test_cell_sample.py."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from urwire.interfaces import INTERFACES

from tests.tools import cell_session

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "dissector" / "samples" / "cell_session.pcapng"
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}


def urwire_decode(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "urwire", "decode", *args, str(SAMPLE)], capture_output=True,
                          text=True, env=ENV, timeout=120)


def test_the_sample_is_what_make_samples_writes(tmp_path):
    assert cell_session.write(tmp_path / "cell.pcapng").read_bytes() == SAMPLE.read_bytes(), \
        "dissector/samples/cell_session.pcapng is stale: run make samples"


def test_every_interface_decodes_with_no_error_record():
    res = urwire_decode()
    assert res.returncode == 0, res.stderr
    records = [json.loads(line) for line in res.stdout.splitlines()]
    assert not [r for r in records if r.get("type") == "error" or isinstance(r.get("error"), str)]
    assert {r.get("interface", "ur") for r in records} == set(INTERFACES)
    rtde = [r for r in records if r.get("interface") == "rtde"]
    assert any(r.get("refused") == {"not_a_variable": "NOT_FOUND"} for r in rtde)
    session = [r["type"] for r in rtde if r["conversation"].endswith(":50103")]
    assert session.index("start_reply") < session.index("data_package")
    assert len([r for r in rtde if r["type"] == "data_package"]) == 3


def test_the_readable_views_show_every_record():
    lines = urwire_decode().stdout.splitlines()
    for view in ("text", "tree"):
        res = urwire_decode("--format", view)
        assert res.returncode == 0, res.stderr
        if view == "text":
            assert len(res.stdout.splitlines()) == len(lines)
    text = urwire_decode("--format", "text").stdout.splitlines()
    data = next(line for line in text if "Output data package" in line and ":50103]" in line)
    assert data.startswith("[rtde from_robot 192.168.56.101:30004-") and "Recipe id: 2" in data
    assert all(name in data for name in ("timestamp", "actual_q", "robot_mode"))
