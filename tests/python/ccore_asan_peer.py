"""Run by tests/python/test_c_backend.py: the differentials of that file (JSON lines, and robot
states' records) over every vector and kept fuzz input, and the hostile robot states, and those
of test_c_backend_flat.py (real-time packets) and test_capture_json.py (lines with an envelope),
against an urwire._ccore built with ASan and UBSan (its path: argv[1]), loaded in place of the
in-tree one. A sanitizer's report ends the process with an error. Prints the inputs of each
differential."""
import random
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python"), str(ROOT)]

from tests.python import test_c_backend as differential  # noqa: E402
from tests.python import test_c_backend_flat as flat  # noqa: E402
from tests.python import test_capture_json as capture_json  # noqa: E402
from tests.tools import ccore_sanitized  # noqa: E402
from tests.tools.fuzz_inputs import HARNESSES, decodable  # noqa: E402
from tests.vectors import all_cases  # noqa: E402


def main(path: str) -> int:
    ccore = ccore_sanitized.load(path)
    count = records = 0
    states = differential.new_states(ccore)
    for case in all_cases():
        differential.assert_same(ccore, case.data, case.version, case.name)
        differential.assert_same_records(states, case.data, case.version, case.name, pieces=(1, 97))
        count += 1
        records += 1
    for harness in HARNESSES:
        for hint, data, name in decodable(harness):
            differential.assert_same(ccore, data, hint, name, pieces=(1, 97))
            differential.assert_same_records(states, data, hint, name, pieces=(97,))
            count += 1
            records += 1
    rng = random.Random(25)
    for state in differential.real_states():
        for msg in [state, *differential.hostile(state, rng)]:
            differential.assert_same_records(states, msg, "5.11", msg[:40].hex(), pieces=())
            records += 1
    for case in flat.interface_cases("ur_realtime"):
        flat.test_every_realtime_vector_gives_the_same_records(ccore, case)
        records += 1
    for cls in flat.FLAT_LAYOUTS:
        flat.test_every_realtime_layout_made_in_c_is_its_decoders_record(ccore, cls)
    capture_json.assert_heads_replace_braces(ccore)
    print(count, records)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
