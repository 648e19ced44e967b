"""Captures cut short or damaged, as the field has them: every whole message read before the
damage, an error record naming the capture file offset where it was met, reading going on
where the format allows, and the exit status of a decode with errors (1), for decode, export
and plot alike. The cases are a fixed table of cuts and corruptions of the bundled sample."""
from __future__ import annotations

import csv
import io
import json
import struct
from pathlib import Path

import dpkt
import pytest

from tests.python.test_cli import records, urwire
from tests.tools import capture

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = (ROOT / "dissector" / "samples" / "primary_session.pcapng").read_bytes()
EPB = 6


def blocks(data: bytes) -> list[tuple[int, int, int]]:
    """(offset, type, length) of each block of a little-endian pcapng."""
    out, at = [], 0
    while at < len(data):
        kind, length = struct.unpack_from("<II", data, at)
        out.append((at, kind, length))
        at += length
    return out


PACKETS = [b for b in blocks(SAMPLE) if b[1] == EPB]


def decoded(path: Path) -> tuple[int, list[dict]]:
    result = urwire("decode", str(path))
    return result.returncode, records(result)


FULL = None


def full_records(tmp_path) -> list[dict]:
    global FULL
    if FULL is None:
        path = tmp_path / "full.pcapng"
        path.write_bytes(SAMPLE)
        code, FULL = decoded(path)
        assert code == 0
    return FULL


def messages(recs: list[dict]) -> list[dict]:
    return [r for r in recs if r["type"] != "error"]


def errors(recs: list[dict]) -> list[dict]:
    return [r for r in recs if r["type"] == "error"]


def with_length(data: bytes, at: int, length: int) -> bytes:
    return data[:at] + struct.pack("<I", length) + data[at + 4:]


# name -> (the damaged capture, the offset its first error names, reading goes on after it)
CUTS = {f"cut at {n}": SAMPLE[:n] for n in (100_000, 50_000, PACKETS[40][0] + 7, PACKETS[12][0] + 30)}
CUT_BLOCK = {name: max(at for at, _, _ in blocks(SAMPLE) if at < len(data)) for name, data in CUTS.items()}


def _damaged() -> dict[str, tuple[bytes, int, bool]]:
    cases = {name: (data, CUT_BLOCK[name], False) for name, data in CUTS.items()}
    at, _, length = PACKETS[20]
    cases["leading length disagrees with trailer"] = (with_length(SAMPLE, at + 4, length + 4), at, False)
    cases["length past the end of the file"] = (with_length(SAMPLE, at + 4, 1 << 30), at, False)
    cases["length not a multiple of 4"] = (with_length(SAMPLE, at + 4, 13), at, False)
    # the captured length (after type, length, interface, two time words) runs past the block
    cases["captured length beyond its block"] = (with_length(SAMPLE, at + 20, length), at, True)
    return cases


DAMAGED = _damaged()


@pytest.mark.parametrize("name", sorted(DAMAGED))
def test_decode_gives_the_messages_before_the_damage_then_an_error_naming_its_offset(tmp_path, name):
    data, offset, goes_on = DAMAGED[name]
    path = tmp_path / "damaged.pcapng"
    path.write_bytes(data)
    code, recs = decoded(path)
    full = messages(full_records(tmp_path))
    assert code == 1
    first = errors(recs)[0]
    assert first["offset"] == offset and str(first["error"])
    before = messages(recs[:recs.index(first)])
    assert before == full[:len(before)] and before, "the messages read before the damage"
    after = messages(recs[recs.index(first):])
    assert bool(after) == goes_on


def test_a_skipped_block_costs_only_its_own_messages(tmp_path):
    data, offset, _ = DAMAGED["captured length beyond its block"]
    path = tmp_path / "damaged.pcapng"
    path.write_bytes(data)
    _, recs = decoded(path)
    assert len(errors(recs)) >= 1 and errors(recs)[0]["offset"] == offset
    assert len(messages(recs)) >= len(messages(full_records(tmp_path))) - 3


def _pcap_of_sample(tmp_path) -> bytes:
    frames = [frame for _, frame in dpkt.pcapng.Reader(io.BytesIO(SAMPLE))]
    return capture.write(tmp_path / "sample.pcap", frames).read_bytes()


def _pcap_record_offsets(data: bytes) -> list[int]:
    out, at = [], 24
    while at < len(data):
        out.append(at)
        at += 16 + struct.unpack_from("<I", data, at + 8)[0]
    return out


@pytest.mark.parametrize("damage", ["cut", "caplen beyond snaplen"])
def test_a_pcap_record_that_cannot_be_read_ends_the_reading(tmp_path, damage):
    data = _pcap_of_sample(tmp_path)
    at = _pcap_record_offsets(data)[60]
    if damage == "cut":
        data = data[:at + 20]
    else:
        data = data[:at + 8] + struct.pack("<I", 1 << 20) + data[at + 12:]
    path = tmp_path / "damaged.pcap"
    path.write_bytes(data)
    code, recs = decoded(path)
    assert code == 1
    assert errors(recs)[0]["offset"] == at
    before = messages(recs)
    assert before and before == messages(full_records(tmp_path))[:len(before)]


def test_a_capture_with_only_part_of_its_header_is_an_error_record_at_0(tmp_path):
    path = tmp_path / "head.pcapng"
    path.write_bytes(SAMPLE[:30])
    code, recs = decoded(path)
    assert code == 1 and recs == [errors(recs)[0]] and recs[0]["offset"] == 0


def test_export_writes_the_tables_of_everything_before_the_cut_and_exits_1(tmp_path):
    path = tmp_path / "cut.pcapng"
    path.write_bytes(CUTS["cut at 100000"])
    _, recs = decoded(path)
    result = urwire("export", str(path), "--format", "csv", "--out", str(tmp_path / "tables"))
    assert result.returncode == 1, result.stderr
    with open(tmp_path / "tables" / "errors.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [json.loads(row["record"]) for row in rows] == errors(recs)
    with open(tmp_path / "tables" / "version.csv", newline="") as fh:
        assert len(list(csv.DictReader(fh))) == sum(r["type"] == "version" for r in recs)


def test_plot_draws_what_was_read_before_the_cut_and_exits_1(tmp_path):
    pytest.importorskip("matplotlib")
    path = tmp_path / "cut.pcapng"
    path.write_bytes(CUTS["cut at 100000"])
    out = tmp_path / "plot.png"
    result = urwire("plot", str(path), "--field", "joint_data.q_actual", "--out", str(out))
    assert result.returncode == 1, result.stderr
    assert out.stat().st_size > 0
    assert b"99332" in result.stderr or b"offset" in result.stderr


def _mutations(count: int = 120) -> list[tuple[str, bytes]]:
    """A fixed table of cut and corrupted copies of the sample: cuts anywhere, and 4 bytes
    overwritten at a block's length, its captured length or anywhere."""
    import random

    rng = random.Random(20261126)
    heads = [at for at, _, _ in blocks(SAMPLE)]
    out = []
    for i in range(count):
        how = i % 4
        if how == 0:
            cut = rng.randrange(1, len(SAMPLE))
            out.append((f"cut at {cut}", SAMPLE[:cut]))
            continue
        at = {1: lambda: rng.choice(heads) + 4, 2: lambda: rng.choice(PACKETS)[0] + 20,
              3: lambda: rng.randrange(0, len(SAMPLE) - 4)}[how]()
        word = rng.choice([0, 1, 13, 0xFFFFFFFF, rng.getrandbits(32)])
        out.append((f"{word:#x} at {at}", SAMPLE[:at] + struct.pack("<I", word) + SAMPLE[at + 4:]))
    return out


def test_no_mutated_capture_makes_reading_raise():
    """Every cut or corrupted copy reads to its end in records, without an exception; a cut
    one ends in an error record."""
    for name, data in _mutations():
        recs = list(_records_of_bytes(data))
        assert all(hasattr(r, "TYPE") for r in recs), name
        if name.startswith("cut"):
            assert recs and recs[-1].TYPE == "error", name


def _records_of_bytes(data: bytes):
    from urwire.reading import records_of

    return records_of(io.BufferedReader(io.BytesIO(data)))


EXPORTED = _mutations(12)[::3] + _mutations(12)[1::3]


@pytest.mark.parametrize("name, data", EXPORTED, ids=[name for name, _ in EXPORTED])
def test_export_of_a_mutated_capture_exits_as_decode_does(tmp_path, name, data):
    path = tmp_path / "mutated.pcapng"
    path.write_bytes(data)
    code, _ = decoded(path)
    result = urwire("export", str(path), "--format", "csv", "--out", str(tmp_path / "t"))
    assert b"Traceback" not in result.stderr
    assert result.returncode == code in (0, 1), result.stderr
