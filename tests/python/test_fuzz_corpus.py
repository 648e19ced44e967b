"""The fuzzers' kept corpora (tests/fuzz/corpus/) through the Python fuzzer's checks
(tests/python/fuzz_decoder.py: no exception, chunks change nothing, lossless), without atheris;
and the atheris harness itself, run once over its corpus and seeds so that it cannot rot.
The C command's agreement on the same inputs is tests/c/test_c_fuzz_corpus.py's."""
from __future__ import annotations

import sys

import pytest

from tests.c.harness_c import ROOT, get_build
from tests.c.seeds import seeds
from tests.python.fuzz_decoder import check
from tests.tools.fuzz_inputs import CORPUS, HARNESSES, kept, libfuzzer_runs, run_once, write_seeds


def as_python_input(harness: str, raw: bytes) -> bytes:
    """The framer harness's control byte keeps its version bits only (its others cut chunks)."""
    return bytes([raw[0] & 3]) + raw[1:] if harness == "urwire" and raw else raw


@pytest.mark.parametrize("harness", HARNESSES)
def test_the_kept_corpus_passes_the_python_checks(harness):
    inputs = kept(harness)
    assert len(inputs) > 20
    for raw in inputs:
        check(as_python_input(harness, raw))


def test_the_atheris_harness_runs_over_its_corpus_and_seeds(tmp_path):
    """tests/python/fuzz_decoder.py as `make fuzz-python` runs it (atheris, the C command beside
    it in the test driver), once over its kept corpus and seeds (-runs=0: no fuzzing)."""
    try:
        import atheris  # noqa: F401
    except ImportError:
        pytest.fail("atheris is not installed (scripts/setup.sh installs requirements-dev.txt)")
    driver = get_build("gcc").driver
    folders = [CORPUS / "python", write_seeds("python", tmp_path / "seeds")]
    count = len(kept("python")) + len(set(seeds("python")))
    result = run_once([sys.executable, str(ROOT / "tests" / "python" / "fuzz_decoder.py"), f"--peer={driver}"],
                      folders, tmp_path / "crashes")
    assert result.returncode == 0, result.stderr[-3000:]
    assert libfuzzer_runs(result.stderr) >= count
