"""Run by tests/python/test_capture_readers.py: the C capture reader through urwire._ccore built
with ASan and UBSan (its path: argv[1]) against the Python reader, and against itself with runs of
segments joined (capture.Segments), over every capture the tests have, damaged copies of them and
sessions of reordered, lost and changed segments. A difference or a sanitizer's report ends the
process with an error."""
import random
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python"), str(ROOT)]

from urwire import capture  # noqa: E402

from tests.python import test_capture_readers as readers  # noqa: E402
from tests.tools import capture as pcap  # noqa: E402
from tests.tools import ccore_sanitized  # noqa: E402


class Patch:
    """What assert_same takes of pytest's monkeypatch."""

    @staticmethod
    def setattr(target, name, value):
        setattr(target, name, value)


def main(path: str) -> int:
    readers.CCORE = ccore_sanitized.load(path)
    count = 0
    with tempfile.TemporaryDirectory() as folder:
        inputs = list(readers.CAPTURES)
        for seed in range(4):
            frames = readers.shuffled_session(seed, 30003) + readers.shuffled_session(seed + 100, 29999)
            inputs.append(pcap.write(Path(folder) / f"shuffled{seed}.pcapng", frames, pcapng=bool(seed % 2)))
        rng = random.Random(1)
        for n, source in enumerate(readers.CAPTURES[:8]):
            damaged = bytearray(source.read_bytes())
            for _ in range(3):
                damaged[rng.randrange(24, len(damaged))] = rng.randrange(256)
            copy = Path(folder) / f"damaged{n}{source.suffix}"
            copy.write_bytes(bytes(damaged[:rng.randrange(len(damaged) // 2, len(damaged) + 1)]))
            inputs.append(copy)
        for item in inputs:
            readers.assert_same(item, Patch)      # leaves capture.CCORE the sanitized build
            readers.assert_joined_the_same(item)
            count += 1
    capture.CCORE = readers.CCORE
    print(count)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
