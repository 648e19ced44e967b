"""Request/response tracking in the Lua dissectors, as Wireshark's request/response protocols show
it: on a dashboard command and an RTDE request, `<protocol>.response_in` (the frame of its reply);
on a reply, `<protocol>.response_to` (the frame of its request) and `<protocol>.time` (the seconds
since it). Read with `tshark -2` (a request learns its reply's frame on the first pass, after it
was dissected), on the cell sample and on captures that cut every message into pieces, interleave
two conversations, keep more requests awaiting replies than a conversation keeps, and start after
a request was sent.

The expected links are worked out here from the protocol's rule, not from the dissector: the n-th
dashboard reply after the banner answers the n-th command of its conversation; an RTDE reply the
oldest request of its pair (the spec's exchanges.pairs) still awaiting one, at most max_pending
kept per pair. The times must be the frames' time difference exactly. tests/native/
test_exchanges_native.py runs the same checks on the native plugin and compares it with Lua."""
from __future__ import annotations

import random
from dataclasses import dataclass, field
from decimal import Decimal
from pathlib import Path
from typing import Callable, Optional

import pytest

from codegen.compile import SPEC_DIR, compile_file
from codegen.kinds.typed_messages.dissector import exchanges_of
from codegen.kinds.typed_messages.plan import plan
from tests.native import harness
from tests.tools import capture

ROOT = Path(__file__).resolve().parents[2]
CELL = ROOT / "dissector" / "samples" / "cell_session.pcapng"
PROTOCOLS = ("ur_dashboard", "rtde")
PORTS = {"ur_dashboard": 29999, "rtde": 30004}
RTDE = exchanges_of(plan(compile_file(SPEC_DIR / "rtde.yaml")))
DASHBOARD_KEPT = 256           # commands awaiting replies a dashboard conversation keeps (both runtimes)

Run = Callable[..., str]       # (capture, *tshark arguments) -> tshark's checked output


def lua(capture_: Path, *args: str) -> str:
    return harness.checked(harness.run_lua(capture_, *args, lua=[harness.lua_plugin(p) for p in PROTOCOLS]))


# ---- what tshark shows, and what it should ----

@dataclass
class Frame:
    number: int
    stream: str
    epoch: Decimal
    items: list                # (pair, is_reply) per message or line in order; None: neither (a banner)
    response_in: list[str]
    response_to: list[str]
    time: list[str]
    want_in: list[str] = field(default_factory=list)
    want_to: list[str] = field(default_factory=list)
    want_time: list[Decimal] = field(default_factory=list)


def _list(text: str) -> list[str]:
    return [v for v in text.split("|") if v]


def shown(run: Run, capture_: Path, protocol: str, *args: str) -> list[Frame]:
    """Each frame of the protocol: its messages (RTDE: by kind; the dashboard: its command or reply
    lines) and the links shown."""
    what = ("rtde.kind",) if protocol == "rtde" else ("ur_dashboard.command", "ur_dashboard.reply")
    out = run(capture_, *args, "-Y", protocol, "-T", "fields", "-E", "occurrence=a", "-E", "aggregator=|",
              "-e", "frame.number", "-e", "tcp.stream", "-e", "frame.time_epoch",
              *[a for f in what + ("response_in", "response_to", "time") for a in
                ("-e", f if f.startswith(protocol) else f"{protocol}.{f}")])
    frames, greeted = [], set()
    for line in out.splitlines():
        cells = line.split("\t")
        number, stream, epoch = int(cells[0]), cells[1], Decimal(cells[2])
        if protocol == "rtde":
            items = [RTDE.role(kind) for kind in _list(cells[3])]
            items = [(pair, reply) if pair >= 0 else None for pair, reply in items]
            rest = cells[4:]
        else:
            commands, replies = _list(cells[3]), _list(cells[4])
            items = [(0, False)] * len(commands) + [(0, True)] * len(replies)
            if replies and stream not in greeted:        # the server's first line is its banner
                greeted.add(stream)
                items[len(commands)] = None
            rest = cells[5:]
        frames.append(Frame(number, stream, epoch, items, *[_list(c) for c in rest]))
    return frames


def expect(frames: list[Frame], kept: int) -> None:
    """The links the protocol's rule gives (Frame.want_*): replies answer the requests of their
    pair in order, per conversation; a request past `kept` awaiting, or behind one that was, is not
    linked, nor its reply."""
    queues: dict = {}
    for frame in frames:
        for item in frame.items:
            if item is None:
                continue
            q = queues.setdefault((frame.stream, item[0]), {"pending": [], "lost": 0})
            if not item[1]:
                if q["lost"] or len(q["pending"]) == kept:
                    q["lost"] += 1
                else:
                    q["pending"].append(frame)
            elif q["pending"]:
                request = q["pending"].pop(0)
                request.want_in.append(str(frame.number))
                frame.want_to.append(str(request.number))
                frame.want_time.append(frame.epoch - request.epoch)
            elif q["lost"]:
                q["lost"] -= 1


def check(run: Run, capture_: Path, protocol: str, *args: str) -> list[Frame]:
    """The links shown are the rule's, each time the frames' difference; returns the frames."""
    frames = shown(run, capture_, protocol, "-2", *args)
    expect(frames, DASHBOARD_KEPT if protocol == "ur_dashboard" else RTDE.max_pending)
    for f in frames:
        assert f.response_in == f.want_in, f"frame {f.number}: response_in"
        assert f.response_to == f.want_to, f"frame {f.number}: response_to"
        assert [Decimal(t) for t in f.time] == f.want_time, f"frame {f.number}: time"
        assert all(Decimal(t) >= 0 for t in f.time), f"frame {f.number}: time"
    return frames


def linked(frames: list[Frame]) -> tuple[int, int]:
    """How many requests and replies are linked."""
    return sum(len(f.want_in) for f in frames), sum(len(f.want_to) for f in frames)


# ---- captures ----

def pieces(data: bytes, rng: random.Random) -> list[bytes]:
    out, at = [], 0
    while at < len(data):
        n = rng.randint(1, 3)
        out.append(data[at:at + n])
        at += n
    return out


def session(port: int, client_port: int, steps: list[tuple[bool, bytes]], rng: Optional[random.Random] = None,
            handshake: bool = True) -> list[bytes]:
    """One TCP session: each step (from the robot?, bytes) whole, or in 1-3 byte segments."""
    segments = [capture.Segment(robot, piece) for robot, data in steps
                for piece in (pieces(data, rng) if rng else [data])]
    return capture.session_frames(segments, port=port, client_port=client_port, handshake=handshake)


def interleaved(*sessions: list[bytes]) -> list[bytes]:
    out, lists = [], [list(s) for s in sessions]
    while any(lists):
        for frames in lists:
            if frames:
                out.append(frames.pop(0))
    return out


def written(path: Path, frames: list[bytes], seed: int = 1) -> Path:
    """Frames at irregular times, microseconds apart to half a second, always forward."""
    rng, t, times = random.Random(seed), 0.0, []
    for _ in frames:
        t += rng.randint(1, 500_000) / 1e6
        times.append(t)
    return capture.write(path, frames, times=times)


BANNER = b"Connected: Universal Robots Dashboard Server\n"


def dashboard_capture(tmp_path: Path) -> Path:
    """Two dashboard conversations at once, every line in 1-3 byte segments; commands sent
    several before their replies; a conversation seen from after its first command was sent."""
    rng = random.Random(7)
    one = [(True, BANNER), (False, b"PolyscopeVersion\nload /a.urp\r\n"), (True, b"URSoftware 5.11.1.108318 (x)\n"),
           (False, b"play\n"), (True, b"Loading program: /a.urp\r\n"), (True, b"Starting program\n"),
           (False, b"stop\nbogus\n"), (True, b"Stopped\ncould not understand: 'bogus'\n")]
    two = [(True, BANNER), (False, b"robotmode\n"), (True, b"Robotmode: IDLE\n"), (False, b"quit\n"),
           (True, b"Disconnected\n")]
    late = [(True, b"Stopped\n"), (False, b"pause\n"), (True, b"Pausing program\n")]
    frames = interleaved(session(29999, 41001, one, rng), session(29999, 41002, two, rng),
                         session(29999, 41003, late, handshake=False))
    return written(tmp_path / "dashboard.pcap", frames)


def rtde(code: str, body: bytes = b"") -> bytes:
    return (len(body) + 3).to_bytes(2, "big") + code.encode() + body


def rtde_capture(tmp_path: Path) -> Path:
    """RTDE: a version exchange, a pause sent while a setup awaits its reply, data packages and
    text messages between, ten starts before their ten replies (two past max_pending), each
    message in 1-3 byte segments; and a conversation seen from after its request was sent."""
    rng = random.Random(11)
    steps = [(False, rtde("V", b"\x00\x02")), (True, rtde("V", b"\x01")),
             (False, rtde("v")), (True, rtde("v", bytes(16))),
             (False, rtde("O", b"\x40\x5f\x40\x00\x00\x00\x00\x00timestamp")), (False, rtde("P")),
             (True, rtde("O", b"\x01DOUBLE")), (True, rtde("P", b"\x01")),
             (False, rtde("S")), (True, rtde("S", b"\x01")),
             (True, rtde("U", b"\x01" + bytes(8))), (True, rtde("M", b"\x02hi\x01x\x03")),
             (False, rtde("M", b"\x02hi\x01x\x03")), (False, rtde("I", b"speed_slider_mask")),
             (True, rtde("I", b"\x01UINT32"))]
    steps += [(False, rtde("S"))] * 10 + [(True, rtde("S", b"\x01"))] * 10
    late = [(True, rtde("S", b"\x01")), (False, rtde("P")), (True, rtde("P", b"\x01"))]
    frames = interleaved(session(30004, 42001, steps, rng), session(30004, 42002, late, handshake=False))
    return written(tmp_path / "rtde.pcap", frames, seed=2)


# ---- the Lua dissectors ----

def test_the_cell_samples_replies_link_with_their_requests():
    dashboard = check(lua, CELL, "ur_dashboard")
    requests, replies = linked(dashboard)
    shown_replies = sum(1 for f in dashboard for item in f.items if item and item[1])
    assert replies == shown_replies and requests == replies and replies >= 2, "every reply after the banner"
    frames = check(lua, CELL, "rtde")
    requests, replies = linked(frames)
    assert replies == sum(1 for f in frames for item in f.items if item and item[1]) and replies >= 6
    assert requests == replies, "every request answered in the sample"


def test_segmented_and_interleaved_conversations(tmp_path):
    frames = check(lua, dashboard_capture(tmp_path), "ur_dashboard")
    assert linked(frames) == (8, 8), "5 + 2 + 1 commands answered; the late conversation's first reply links to none"
    assert len({f.stream for f in frames}) == 3


def test_rtde_pairs_apart_past_max_pending_and_from_mid_session(tmp_path):
    frames = check(lua, rtde_capture(tmp_path), "rtde")
    # version, controller version, setup outputs, pause, start, setup inputs, then 8 of the 10
    # starts; the late conversation's pause.
    assert linked(frames) == (6 + 8 + 1, 6 + 8 + 1)


@pytest.mark.parametrize("protocol", PROTOCOLS)
def test_one_pass_shows_replies_links_but_not_yet_requests(tmp_path, protocol):
    """Without -2 a request is dissected before its reply is seen: as in Wireshark's own protocols
    (dns.response_in), only the two-pass read or the GUI shows it."""
    pcap = dashboard_capture(tmp_path) if protocol == "ur_dashboard" else rtde_capture(tmp_path)
    frames = shown(lua, pcap, protocol)
    assert not any(f.response_in for f in frames)
    assert sum(len(f.response_to) for f in frames) > 0


@pytest.mark.parametrize("protocol", PROTOCOLS)
def test_a_filter_on_the_links_selects_the_requests(tmp_path, protocol):
    pcap = CELL
    out = lua(pcap, "-2", "-Y", f"{protocol}.response_in", "-T", "fields", "-e", "frame.number")
    frames = {f.number: f for f in check(lua, pcap, protocol)}
    assert [int(n) for n in out.split()] == sorted(n for n, f in frames.items() if f.want_in)
    out = lua(pcap, "-2", "-Y", f"{protocol}.time >= 0", "-T", "fields", "-e", "frame.number")
    assert [int(n) for n in out.split()] == sorted(n for n, f in frames.items() if f.want_to)

