#!/usr/bin/env python3
"""Coverage-guided fuzzing of the Python decoder with atheris (libFuzzer for Python).

An input is a control byte, then a stream, read as tests/c/fuzz_json.c reads it (see
tests/tools/fuzz_inputs.py): the control byte picks the version hint, or takes it from the
text that follows, and the size of the chunks fed to the framer. Checked on every input:

- `parse_version` raises ValueError alone; decoding, `to_json_line` and `to_dict` raise nothing;
- fed in chunks, the framer gives the records it gives fed whole;
- lossless: in a stream without stream faults, every message encodes back to its bytes, and so
  does the stream read as one message (its length field set to its length);
- with `--peer DRIVER` (tests/c/driver.c built, `driver batch`): urwire-decode prints the same
  lines, byte for byte, with the same exit status, for the same hint text and bytes.

    make fuzz-python FUZZ_SECONDS=600
    python3 tests/python/fuzz_decoder.py --peer=build/fuzz/driver [libFuzzer flags] CORPUS...

tests/python/test_fuzz_corpus.py runs `check` on the kept corpus without atheris.
"""
from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT), str(ROOT / "python"), str(ROOT / "generated" / "python")]

from tests.c.harness_c import CommandPeer  # noqa: E402
from tests.tools.fuzz_inputs import chunk_size, split  # noqa: E402

NOT_A_VERSION = object()


def answer(records: list) -> tuple[list[str], int]:
    """The lines and exit status of the Python command for these records."""
    import urwire
    from urwire.canonical import has_error

    return [urwire.to_json_line(r) for r in records], 1 if any(has_error(r) for r in records) else 0


def messages_reencode(data: bytes, version) -> None:
    """Each message of a stream without faults, encoded in the version the framer read it in."""
    import urwire

    framer, pos = urwire.Framer(version), 0
    while pos < len(data):
        piece = data[pos:pos + int.from_bytes(data[pos:pos + 4], "big")]
        in_force = framer.version
        (record,) = framer.feed(piece)
        assert urwire.encode_message(record, in_force) == piece, f"message at {pos} re-encodes otherwise"
        pos += len(piece)


def whole_reencodes(data: bytes, version) -> None:
    """The stream as one message, whatever its type byte and however its parts fail."""
    import urwire
    from urwire.generated.spec import MAX_MESSAGE_LENGTH

    if not 5 <= len(data) <= MAX_MESSAGE_LENGTH:
        return
    buf = len(data).to_bytes(4, "big") + data[4:]
    assert urwire.encode_message(urwire.decode_message(buf, version), version) == buf


def check(raw: bytes, peer: CommandPeer | None = None) -> None:
    import urwire

    hint, data = split("python", raw)
    try:
        version = urwire.parse_version(hint) if hint else None
    except ValueError:
        version = NOT_A_VERSION
    if peer is not None:
        expected = ([], 2) if version is NOT_A_VERSION else answer(list(urwire.decode_stream(data, version)))
        assert peer.decode(data, hint) == expected, f"urwire-decode disagrees with Python (hint {hint!r})"
    if version is NOT_A_VERSION:
        return
    records = list(urwire.decode_stream(data, version))
    lines, _ = answer(records)
    for record in records:
        urwire.to_dict(record)

    framer, chunk, chunked = urwire.Framer(version), chunk_size(raw), []
    for at in range(0, len(data), chunk):
        chunked += framer.feed(data[at:at + chunk])
    assert answer(chunked + framer.close())[0] == lines, f"chunks of {chunk} bytes give other records"

    if not any(isinstance(r, urwire.StreamError) for r in records):
        messages_reencode(data, version)
    whole_reencodes(data, version)


def main(argv: list[str]) -> None:
    import atheris

    peers = [a.split("=", 1)[1] for a in argv if a.startswith("--peer=")]
    argv = [a for a in argv if not a.startswith("--peer=")]
    with atheris.instrument_imports(include=["urwire"]):
        import urwire  # noqa: F401
    peer = CommandPeer(Path(peers[0])) if peers else None
    atheris.Setup(argv, lambda raw: check(raw, peer))
    atheris.Fuzz()


if __name__ == "__main__":
    main(sys.argv)
