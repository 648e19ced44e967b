"""The native dissector of the primary/secondary interface (generated/epan/packet-ur.c, protocol
`ur`) against its Lua twin (generated/lua/urwire.lua): each loaded alone in real tshark, they
must register the same fields and show the same layers (-T json), Info column and expert infos
on every capture the Lua dissector is tested with. The captures are batched: many TCP sessions
per capture, so that a few tshark runs cover every vector."""
from __future__ import annotations

import functools
import json
import os
import random
import subprocess
import tempfile
from pathlib import Path
from typing import Optional

import pytest

from tests.native import harness
from tests.tools import capture, valid
from tests.lua import test_fuzz_corpus as fuzz_corpus
from tests.vectors import golden_cases

SAMPLES = harness.ROOT / "dissector" / "samples"
LUA = functools.partial(harness.run_lua, lua=[harness.lua_plugin("ur")])


def _fields(result) -> list[list[str]]:
    """The `ur` protocol line and field lines of `tshark -G fields`, split into columns."""
    err = result.stderr.decode(errors="replace")
    assert result.returncode == 0 and "Lua: Error" not in err, err[:3000]
    rows = [line.split("\t") for line in result.stdout.decode().splitlines()]
    return [r for r in rows if (r[0] == "P" and r[2:3] == ["ur"]) or (r[0] == "F" and r[4:5] == ["ur"])]


def test_both_register_the_same_fields_in_the_same_order():
    native = _fields(harness.native_tshark(["-G", "fields"]))
    lua = _fields(_lua_fields())
    assert len(native) > 300
    # Kind, name, abbreviation, type, protocol, base and bitmask, line for line.
    assert [r[:7] for r in native] == [r[:7] for r in lua]
    # Descriptions too, where Lua has one: Wireshark 4.0 drops the description of a Lua string field.
    differ = [(n[2], n[7], l[7]) for n, l in zip(native, lua) if len(l) > 7 and l[7] and n[7:8] != l[7:8]]
    assert not differ, differ[:5]


def _lua_fields() -> subprocess.CompletedProcess:
    """tshark -G fields with the Lua dissector alone (-G must come first, so not through run_lua)."""
    environment = {**os.environ, "HOME": str(harness._empty_home())}
    environment.pop("XDG_CONFIG_HOME", None)
    return subprocess.run(["tshark", "-G", "fields", "-X", f"lua_script:{harness.lua_plugin('ur')}"],
                          capture_output=True, env=environment, timeout=120)


# ---- captures: many sessions each, fed to both dissectors ----

def _sessions(streams: list[list[bytes]], handshakes: Optional[list[bool]] = None,
              retransmit: Optional[list[int]] = None) -> bytes:
    """One TCP session per stream (a list of robot segment payloads), as tests/lua writes them;
    per stream, whether it opens with a handshake and every how many segments one is sent twice."""
    frames = []
    for i, segments in enumerate(streams):
        every = retransmit[i] if retransmit else 0
        again = range(0, len(segments), every) if every else ()
        frames += capture.session_frames([capture.Segment(True, s) for s in segments], port=30001,
                                         client_port=20000 + i % 40000,
                                         handshake=handshakes[i] if handshakes else True, retransmit=again)
    with tempfile.TemporaryDirectory() as folder:
        return capture.write(Path(folder) / "sessions.pcap", frames).read_bytes()


def _first_difference(a, b, path="") -> str:
    """Where two JSON values first differ, for a readable failure."""
    if type(a) is not type(b):
        return f"{path}: {json.dumps(a)[:300]} != {json.dumps(b)[:300]}"
    if isinstance(a, dict):
        if list(a) != list(b):
            return f"{path}: keys {list(a)[:20]} != {list(b)[:20]}"
        for k in a:
            if a[k] != b[k]:
                return _first_difference(a[k], b[k], f"{path}.{k}")
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{path}: {len(a)} items != {len(b)} items"
        for i, (x, y) in enumerate(zip(a, b)):
            if x != y:
                return _first_difference(x, y, f"{path}[{i}]")
    return f"{path}: {json.dumps(a)[:300]} != {json.dumps(b)[:300]}"


def assert_same(capture_bytes: bytes, *args: str) -> harness.Shown:
    """Both dissectors show the same layers, Info column and expert infos of the capture's frames
    that show `ur` (-Y ur: the frames that carry only part of a message show nothing of it, and
    a frame one of them shows and the other does not makes the counts differ)."""
    native = harness.shown(harness.run_native, capture_bytes, ["ur"], "-Y", "ur", *args)
    lua = harness.shown(LUA, capture_bytes, ["ur"], "-Y", "ur", *args)
    assert len(native.layers) == len(lua.layers)
    for frame, (n, l) in enumerate(zip(native.layers, lua.layers), start=1):
        assert n == l, f"frame {frame}: native {_first_difference(n, l)}"
    for frame, (n, l) in enumerate(zip(native.info, lua.info), start=1):
        assert n == l, f"frame {frame}: Info column\n native: {n}\n    lua: {l}"
    assert native.info == lua.info
    assert native.experts == lua.experts
    return native


def _split(data: bytes) -> list[bytes]:
    """A stream cut at its declared lengths where they are plausible (else kept whole)."""
    out, pos = [], 0
    while len(data) - pos >= 5:
        n = int.from_bytes(data[pos:pos + 4], "big", signed=True)
        if n < 5 or pos + n > len(data):
            break
        out.append(data[pos:pos + n])
        pos += n
    if pos < len(data):
        out.append(data[pos:])
    return out


GOLDEN = golden_cases()
HINTS = sorted({c.version or "" for c in GOLDEN})


# The tail of a real message: a capture that starts in the middle of the stream.
MID_STREAM = bytes.fromhex("3ff000000000000000000001")


def tiny(messages: list[bytes], seed: int = 0) -> list[bytes]:
    """The stream in segments of 1 to 7 bytes."""
    data, rng, out = b"".join(messages), random.Random(seed), []
    while data:
        n = rng.randint(1, 7)
        out.append(data[:n])
        data = data[n:]
    return out


# As tests/lua/test_vectors.py cuts them (segments, handshake, retransmit every k), and 1-7 bytes.
SEGMENTATIONS = {
    "whole": (capture.whole, True, 0),
    "bytewise": (capture.bytewise, True, 0),
    "1-7 bytes": (tiny, True, 0),
    "random_cuts": (lambda msgs: capture.random_cuts(msgs, seed=7, max_len=40), True, 0),
    "packed": (lambda msgs: capture.packed(msgs, per_segment=3), True, 0),
    "mid_stream": (lambda msgs: capture.random_cuts([MID_STREAM] + list(msgs), seed=3, max_len=300), False, 0),
    "retransmitted": (lambda msgs: capture.random_cuts(msgs, seed=5, max_len=200), True, 3),
}


def _golden_capture(hint: str) -> bytes:
    """Every golden vector of this version hint, in every segmentation, one session each."""
    streams, handshakes, retransmit = [], [], []
    for cut, handshake, every in SEGMENTATIONS.values():
        for case in GOLDEN:
            if (case.version or "") == hint:
                streams.append(cut(_split(case.data)))
                handshakes.append(handshake)
                retransmit.append(every)
    return _sessions(streams, handshakes, retransmit)


def _prefs(hint: str) -> tuple[str, ...]:
    return ("-o", f"ur.version:{hint}") if hint else ()


@pytest.mark.parametrize("hint", HINTS, ids=lambda h: h or "no hint")
def test_golden_vectors_in_every_segmentation(hint):
    shown = assert_same(_golden_capture(hint), *_prefs(hint))
    assert sum(1 for layer in shown.layers if layer) > len(SEGMENTATIONS)


def test_generation_sessions():
    """Sessions of random valid messages of every controller generation (tests/tools/valid.py),
    with and without their Version message, in 7- and 400-byte segments."""
    streams = []
    for max_len in (7, 400):
        rng = random.Random(max_len)
        for version in valid.versions():
            for _ in range(3):
                session = valid.session(rng, version, 10)
                for data in (session, session[int.from_bytes(session[:4], "big"):]):
                    streams.append(capture.random_cuts([data], seed=len(streams), max_len=max_len))
    assert_same(_sessions(streams))


@pytest.mark.parametrize("sample", ["primary_session.pcapng", "secondary_session.pcap"])
def test_bundled_samples(sample):
    shown = assert_same(SAMPLES / sample)
    assert any(shown.layers)


# ---- the fuzzers' kept corpora, as tests/lua/test_fuzz_corpus.py feeds them ----

def _corpus_capture(version: str) -> bytes:
    """Every kept input of this version hint, cut the three ways tests/lua cuts them."""
    streams = []
    for cut in fuzz_corpus.CUTS:
        rng = random.Random(f"{version} {cut}")
        for data in fuzz_corpus.GROUPS[version]:
            if cut != "1-7 bytes" or len(data) <= fuzz_corpus.SMALL_INPUT:
                streams.append(fuzz_corpus.CUTS[cut](data, rng))
    return _sessions(streams)


@pytest.mark.parametrize("version", sorted(fuzz_corpus.GROUPS), ids=lambda v: v or "no hint")
def test_fuzz_corpus(version):
    """Faults, resynchronisation and their experts included."""
    shown = assert_same(_corpus_capture(version), *_prefs(version))
    assert shown.experts
