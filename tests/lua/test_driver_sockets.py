"""The ROS driver's sockets in real tshark (generated/lua/ur_reverse.lua, ur_trajectory.lua,
ur_script_command.lua, each loaded on its own): the golden vectors in whole and one-byte
segments, the release preference, scaled fields beside their raw int32, Decode As."""
from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import pytest

from tests.interface_vectors import bytewise, conversation_cases
from tests.lua.harness import TsharkError
from tests.tools import capture

ROOT = Path(__file__).resolve().parents[2]
NAMES = ("ur_reverse", "ur_trajectory", "ur_script_command")
PORTS = {"ur_reverse": 50001, "ur_trajectory": 50003, "ur_script_command": 50004}
CASES = [(name, case) for name in NAMES for case in conversation_cases(name)]


def _lists(pairs: list) -> dict:
    out: dict = {}
    for key, value in pairs:
        out.setdefault(key, []).append(value)
    return {k: v[0] if len(v) == 1 else v for k, v in out.items()}


def tshark_json(name: str, pcap: Path, *args: str) -> list:
    plugin = ROOT / "generated" / "lua" / f"{name}.lua"
    result = subprocess.run(["tshark", "-r", str(pcap), "-X", f"lua_script:{plugin}", "-2", "-T", "json", *args],
                            capture_output=True, text=True, timeout=600)
    if result.returncode != 0 or "Lua: Error" in result.stderr + result.stdout or "internal_error" in result.stdout:
        raise TsharkError(result.stderr[:2000] + result.stdout[:2000])
    return json.loads(result.stdout or "[]", object_pairs_hook=_lists)


def write_capture(tmp_path: Path, name: str, segments, port: int = 0) -> Path:
    # The control PC listens on the port, and the robot connects: in the capture writer's terms
    # (the side on the port sends "from_robot") the directions are swapped.
    frames = capture.session_frames([capture.Segment(not s.from_robot, s.data) for s in segments],
                                    port=port or PORTS[name])
    return capture.write(tmp_path / f"{name}.pcap", frames)


def records(name: str, frames: list) -> list[dict]:
    """Each record item -> {field: value or list}, fields as tshark shows them (numbers)."""
    out = []
    for frame in frames:
        layer = frame["_source"]["layers"].get(name)
        if layer is None:
            continue
        for item in layer if isinstance(layer, list) else [layer]:
            rec = {}
            for key, value in item.items():
                if key.startswith(name + ".") and not key.endswith("_tree"):
                    values = value if isinstance(value, list) else [value]
                    rec[key[len(name) + 1:]] = [float(v) for v in values]
            for key, value in item.items():      # a scaled value's raw int32 is in its subtree
                if key.endswith("_tree"):
                    for sub, raw in (value.items() if isinstance(value, dict) else []):
                        rec.setdefault(sub[len(name) + 1:], []).extend(float(v) for v in
                                                                       (raw if isinstance(raw, list) else [raw]))
            if not rec and f"{name}.unspecified" in json.dumps(item.get("_ws.expert")):
                continue                         # bytes where no record is specified: flagged, not a record
            out.append(rec)
    return out


def expected(case) -> list[dict]:
    """The vector's records as tshark shows them: every value a list of numbers, no error records
    (a cut tail waits for the rest of its record; bytes where none are specified are flagged)."""
    out = []
    for r in case.expect:
        if r["type"] == "error":
            continue
        out.append({k: [float(x) for x in (v if isinstance(v, list) else [v])] for k, v in r.items() if k != "type"})
    return out


def close(a: list[dict], b: list[dict]) -> bool:
    return len(a) == len(b) and all(x.keys() >= y.keys() and all(
        len(x[k]) == len(y[k]) and all(math.isclose(p, q, rel_tol=1e-12, abs_tol=1e-12) for p, q in zip(x[k], y[k]))
        for k in y) for x, y in zip(a, b))


def preference(name: str, version) -> tuple:
    return ("-o", f"{name}.release:{version}") if version else ()


@pytest.mark.parametrize("name,case", CASES, ids=[f"{n}/{c.name}" for n, c in CASES])
def test_golden_vectors_whole_and_in_one_byte_segments(tmp_path, name, case):
    for segments in (case.segments, bytewise(case.segments)):
        shown = records(name, tshark_json(name, write_capture(tmp_path, name, segments), *preference(name, case.version)))
        assert close(shown, expected(case)), (shown, expected(case))


def test_scaled_fields_show_their_raw_int32_and_filter_by_value(tmp_path):
    (case,) = [c for n, c in CASES if c.name == "servoj_and_idle"]
    pcap = write_capture(tmp_path, "ur_reverse", case.segments)
    plugin = ROOT / "generated" / "lua" / "ur_reverse.lua"
    out = subprocess.run(["tshark", "-r", str(pcap), "-X", f"lua_script:{plugin}", "-2", "-Y",
                          "ur_reverse.control_mode == 1 && ur_reverse.target > 2000", "-T", "fields",
                          "-e", "ur_reverse.target_raw"], capture_output=True, text=True, check=True).stdout
    # Both records came in one segment: the frame holds both.
    assert out.split() == ["500000,-1570796,0,3141593,-1,2147483647,0,0,0,0,0,-2147483648"]
    none = subprocess.run(["tshark", "-r", str(pcap), "-X", f"lua_script:{plugin}", "-2", "-Y",
                           "ur_reverse.control_mode == 4"], capture_output=True, text=True, check=True).stdout
    assert none == ""
    text = subprocess.run(["tshark", "-r", str(pcap), "-X", f"lua_script:{plugin}", "-2", "-O", "ur_reverse"],
                          capture_output=True, text=True, check=True).stdout
    assert "Control mode: SERVOJ (1)" in text and "(raw 500000, scaled by MULT_JOINTSTATE = 1000000)" in text


def test_decode_as_on_another_port(tmp_path):
    (case,) = [c for n, c in CASES if c.name == "point_and_result_2_14"]
    pcap = write_capture(tmp_path, "ur_trajectory", case.segments, port=40003)
    shown = records("ur_trajectory", tshark_json("ur_trajectory", pcap, "-d", "tcp.port==40003,ur_trajectory"))
    assert close(shown, expected(case))


@pytest.mark.parametrize("name", NAMES)
def test_no_global_is_assigned(name):
    plugin = ROOT / "generated" / "lua" / f"{name}.lua"
    listing = subprocess.run(["luac5.2", "-l", "-p", str(plugin)], capture_output=True, text=True, check=True).stdout
    assert [line for line in listing.splitlines() if "SETTABUP" in line and "_ENV" in line] == []


@pytest.mark.parametrize("name", NAMES)
def test_random_bytes_in_both_directions_never_raise_a_lua_error(tmp_path, name):
    import random

    from tests.interface_vectors import Segment

    rng = random.Random(name)
    segments = [Segment(rng.random() < 0.5, bytes(rng.randrange(256) for _ in range(rng.randint(1, 300))))
                for _ in range(30)]
    for release in ("", "1.0.0", "not a release"):
        frames = tshark_json(name, write_capture(tmp_path, name, segments), "-o", f"{name}.release:{release}")
        assert any(name in f["_source"]["layers"] for f in frames)
