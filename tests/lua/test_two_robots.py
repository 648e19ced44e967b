"""Two robots of different software versions in one capture, on the same port numbers (30001 and
client port 50123), their messages interleaved: the dissector keeps each conversation's state (the
version its Version message announced) apart, so each robot's global variables read with its own
version's value types, as the golden vectors say."""
from __future__ import annotations

from tests.lua.harness import F32_TOL, comparable, to_records, tshark_json
from tests.tools import capture
from tests.tools.capture import Segment
from tests.vectors import golden_cases, mismatches

CASES = {c.name: c for c in golden_cases()}
ROBOTS = {"192.168.56.101": CASES["global_variables_update_3_2_version_message"],
          "192.168.56.102": CASES["global_variables_update_5_0_version_message"]}


def messages(data: bytes) -> list[bytes]:
    out, pos = [], 0
    while pos < len(data):
        n = int.from_bytes(data[pos:pos + 4], "big")
        out.append(data[pos:pos + n])
        pos += n
    return out


def test_each_robot_keeps_its_own_version(tmp_path):
    sessions = [capture.session_frames([Segment(True, m) for m in messages(case.data)], port=30001,
                                       client_port=50123, robot=robot)
                for robot, case in ROBOTS.items()]
    assert all(len(messages(c.data)) >= 2 for c in ROBOTS.values())   # a Version message, then more
    frames = [f for pair in zip(*sessions) for f in pair]
    longest = max(sessions, key=len)
    frames += longest[len(min(sessions, key=len)):]
    pcap = capture.write(tmp_path / "two_robots.pcap", frames)
    got: dict[str, list] = {robot: [] for robot in ROBOTS}
    for frame in tshark_json(pcap, "-Y", "ur"):
        layers = frame["_source"]["layers"]
        items = layers["ur"] if isinstance(layers["ur"], list) else [layers["ur"]]
        got[layers["ip"]["ip.src"]] += [r for u in items if isinstance(u, dict) for r in to_records(u)]
    for robot, case in ROBOTS.items():
        problems = mismatches(comparable(case.expect), got[robot], partial=False, tolerance=F32_TOL)
        assert not problems, f"{robot} ({case.name}):\n" + "\n".join(problems[:10])
