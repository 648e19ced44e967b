"""The fuzzers' kept corpora (tests/fuzz/corpus/, and tests/c/regressions) and the long seeds as
TCP sessions in tshark: cut in three ways, with each input's version hint as the `ur.version`
preference, the dissector never makes a Lua error and tshark never fails, and every session with
a message or a fault shows the protocol."""
from __future__ import annotations

import random

import pytest

from tests.lua.harness import run_tshark, write_sessions
from tests.c.seeds import long_messages
from tests.tools.fuzz_inputs import HARNESSES, kept, split

import urwire

SEGMENT_MAX = 65000          # what one IPv4 packet carries
SMALL_INPUT = 4096           # cut into 1-7 byte segments only up to this size (frames add up)


def whole(data: bytes, rng: random.Random) -> list[bytes]:
    return [data[i:i + SEGMENT_MAX] for i in range(0, len(data), SEGMENT_MAX)]


def tiny(data: bytes, rng: random.Random) -> list[bytes]:
    out, pos = [], 0
    while pos < len(data):
        n = rng.randint(1, 7)
        out.append(data[pos:pos + n])
        pos += n
    return out


def random_splits(data: bytes, rng: random.Random) -> list[bytes]:
    cuts = sorted(rng.sample(range(1, len(data)), min(len(data) - 1, rng.randint(1, 12)))) if len(data) > 1 else []
    return [s for a, b in zip([0] + cuts, cuts + [len(data)]) for s in whole(data[a:b], rng)]


CUTS = {"whole": whole, "1-7 bytes": tiny, "random splits": random_splits}


def sessions_by_version() -> dict[str, list[bytes]]:
    """Every kept input's stream, grouped by its version hint (normalized; "" for none), and the
    long seeds (messages at and around the 1 MiB limit). A hint that is no version stops
    urwire-decode before it reads a byte: those inputs are left out."""
    groups: dict[str, list[bytes]] = {"": long_messages()}
    for harness in HARNESSES:
        for raw in kept(harness):
            hint, data = split(harness, raw)
            try:
                version = urwire.parse_version(hint) if hint else None
            except ValueError:
                continue
            if data:
                groups.setdefault(".".join(map(str, version)) if version else "", []).append(data)
    return groups


GROUPS = sessions_by_version()


def test_there_is_a_corpus_to_replay():
    assert sum(len(g) for g in GROUPS.values()) > 100


@pytest.mark.parametrize("cut", list(CUTS))
@pytest.mark.parametrize("version", sorted(GROUPS), ids=lambda v: v or "no hint")
def test_the_corpus_never_makes_a_lua_error(tmp_path, version, cut):
    rng = random.Random(f"{version} {cut}")
    streams = [d for d in GROUPS[version] if cut != "1-7 bytes" or len(d) <= SMALL_INPUT]
    pcap = write_sessions(tmp_path / "corpus.pcap", [CUTS[cut](d, rng) for d in streams])
    prefs = ("-o", f"ur.version:{version}") if version else ()
    out = run_tshark(pcap, *prefs, "-Y", "ur", "-T", "fields", "-e", "tcp.stream")   # raises on a Lua error
    missing = set(shows_a_record(streams, version)) - {int(s) for s in out.split()}
    assert not missing, f"sessions without a ur item: {sorted(missing)[:20]}"


def shows_a_record(streams: list[bytes], version: str) -> list[int]:
    """The sessions whose first record is not a tail cut short: TCP reassembly keeps waiting for
    that message and never hands it, nor what the stream decoders rescan inside it, to the
    dissector."""
    return [i for i, data in enumerate(streams)
            if not _cut_tail(next(iter(urwire.decode_stream(data, version or None)), None))]


def _cut_tail(record) -> bool:
    return record is None or (isinstance(record, urwire.StreamError) and record.error.startswith("truncated"))
