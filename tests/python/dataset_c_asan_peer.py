"""Run by tests/python/test_dataset_c.py: the C columns against pure Python's over every vector and
kept fuzz input, and every golden vector of every interface in a capture cut in segments, with an
urwire._ccore built with ASan and UBSan (its path: argv[1]) in place of the in-tree one, in batches
of a few rows and chunks of a few bytes. A sanitizer's report ends the process with an error."""
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python"), str(ROOT)]

from urwire import backends  # noqa: E402

from tests.python import test_dataset_c as differential  # noqa: E402
from tests.tools import ccore_sanitized, golden_sessions  # noqa: E402
from tests.tools.fuzz_inputs import HARNESSES, decodable  # noqa: E402
from tests.vectors import all_cases  # noqa: E402


def main(path: str) -> int:
    ccore = ccore_sanitized.load(path)
    backends._CCORE = ccore
    count = 0
    for case in all_cases():
        differential.assert_same(case.data, case.version, case.name, batches=(2,), chunks=(7,))
        count += 1
    for harness in HARNESSES:
        for hint, data, name in decodable(harness):
            differential.assert_same(data, hint, name, batches=(3,), chunks=(97,))
            count += 1
    with tempfile.TemporaryDirectory() as folder:
        path = golden_sessions.write(Path(folder) / "golden.pcapng", cut=True, pcapng=True)
        differential.assert_same(path.read_bytes(), None, "golden capture", batches=(3,), robot=None, date="2024-01-01")
    print(count)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
