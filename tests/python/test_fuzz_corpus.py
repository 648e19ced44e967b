"""The fuzzers' kept corpora (tests/fuzz/corpus/) through the Python fuzzer's checks
(tests/python/fuzz_decoder.py: no exception, chunks change nothing, lossless), without atheris.
The C command's agreement on the same inputs is tests/c/test_c_fuzz_corpus.py's."""
from __future__ import annotations

import pytest

from tests.python.fuzz_decoder import check
from tests.tools.fuzz_inputs import HARNESSES, kept


def as_python_input(harness: str, raw: bytes) -> bytes:
    """The framer harness's control byte keeps its version bits only (its others cut chunks)."""
    return bytes([raw[0] & 3]) + raw[1:] if harness == "urwire" and raw else raw


@pytest.mark.parametrize("harness", HARNESSES)
def test_the_kept_corpus_passes_the_python_checks(harness):
    inputs = kept(harness)
    assert len(inputs) > 20
    for raw in inputs:
        check(as_python_input(harness, raw))
