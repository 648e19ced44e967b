"""How the fuzzers' inputs read, for the tests that replay them (tests/fuzz/corpus/<harness>/).

    urwire  (tests/c/fuzz_urwire.c): a control byte (bits 0-1: version hint), then the stream
    json    (tests/c/fuzz_json.c) and python (tests/python/fuzz_decoder.py): a control byte
            (bits 0-1: version hint; bit 2: the hint is the text that follows, up to a NUL;
            bits 3-7: chunk size), then the stream
"""
from __future__ import annotations

import hashlib
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CORPUS = ROOT / "tests" / "fuzz" / "corpus"
HARNESSES = ("urwire", "json", "python")
HINTS = ("", "3.2", "5.0", "5.12")   # by the control byte's low bits ("": none)
HINT_MAX = 32


def split(harness: str, raw: bytes) -> tuple[str, bytes]:
    """(version hint, stream) of one input of a harness."""
    if not raw:
        return "", b""
    control, rest = raw[0], raw[1:]
    if harness == "urwire" or not control & 4:
        return HINTS[control & 3], rest
    text = rest[:HINT_MAX].split(b"\0", 1)[0]
    rest = rest[len(text) + 1:] if len(text) < len(rest) else b""
    return text.decode("utf-8", "surrogateescape"), rest


def chunk_size(raw: bytes) -> int:
    """The size of the chunks a json or python input is fed in: 1 byte to 63 KiB, times one
    more for every 16 KiB of input (a byte at a time through 1 MiB shows nothing new)."""
    k = raw[0] >> 3 if raw else 0
    return (1 + k * k * 67) * (1 + len(raw[1:]) // 16384)


def kept(harness: str) -> list[bytes]:
    """The kept corpus of a harness (minimized with libFuzzer's -merge=1), and for the C
    framer harness the inputs that once crashed it (tests/c/regressions)."""
    folders = [CORPUS / harness] + ([ROOT / "tests" / "c" / "regressions"] if harness == "urwire" else [])
    return [p.read_bytes() for folder in folders if folder.is_dir()
            for p in sorted(folder.iterdir()) if p.is_file() and p.name != "README"]


def decodable(harness: str) -> list[tuple[str | None, bytes, str]]:
    """(version hint or None, stream, name) of each kept input of a harness whose hint is a
    version: the ones a decoder reads (the command stops at any other hint, exit 2)."""
    import urwire

    out = []
    for raw in kept(harness):
        hint, data = split(harness, raw)
        try:
            urwire.parse_version(hint or None)
        except ValueError:
            continue
        out.append((hint or None, data, f"{harness} input {raw[:40].hex()}"))
    return out


def fuzz_max_len() -> int:
    """mk/fuzz.mk's -max_len: two messages at the length limit, the framer's slack, the control byte."""
    from urwire.generated.spec import MAX_MESSAGE_LENGTH

    return 2 * MAX_MESSAGE_LENGTH + 4096 + 1


def write_seeds(harness: str, folder: Path) -> Path:
    """The seeds `make fuzz` gives a harness (tests/c/seeds.py), one file each, in folder."""
    from tests.c.seeds import seeds

    folder.mkdir(parents=True, exist_ok=True)
    for seed in seeds(harness):
        (folder / hashlib.sha1(seed).hexdigest()).write_bytes(seed)
    return folder


def libfuzzer_runs(stderr: str) -> int:
    """How many inputs a libFuzzer (or atheris) run executed, from its final line."""
    return int(re.search(r"Done (\d+) runs", stderr).group(1))


def run_once(harness: list[str], folders: list[Path], artifacts: Path) -> subprocess.CompletedProcess:
    """A fuzz harness run once over every input of the folders (-runs=0: no fuzzing), with
    `make fuzz`'s -max_len and its default memory limit; what fails lands in `artifacts`.
    It is started from a shell in the background: Linux counts into a child's peak memory the
    peak of the process it was started from, and a long test run's pytest would pass
    libFuzzer's limit (tests/tools/measure.py)."""
    artifacts.mkdir(parents=True, exist_ok=True)
    cmd = [*harness, "-runs=0", f"-max_len={fuzz_max_len()}", f"-artifact_prefix={artifacts}/", *map(str, folders)]
    return subprocess.run(["sh", "-c", '"$@" & wait $!', "sh", *cmd], capture_output=True, text=True)
