"""The fuzzers' inputs replayed: the kept corpora (tests/fuzz/corpus/), tests/c/regressions, the
long seeds, and what the last `make fuzz` found (build/fuzz/corpus/, when there).

- through both C harnesses again, built as `make fuzz` builds them (ASan, UBSan), each with its
  own checks: the strict flags, and every input and seed run once;
- through urwire-decode's record loop and the Python decoder: the same lines, byte for byte,
  and the same exit status, for the same hint text (one driver process for all inputs)."""
from __future__ import annotations

import shutil

import pytest

from tests.c.harness_c import CLI_LIBRARY, GEN, OUT, ROOT, CommandPeer, compile_c, python_answer
from tests.c.seeds import long_messages, seeds
from tests.tools.fuzz_inputs import CORPUS, HARNESSES, kept, libfuzzer_runs, run_once, split, write_seeds

FOUND = ROOT / "build" / "fuzz" / "corpus"
FUZZER_FLAGS = ["-g", "-O1", "-fsanitize=fuzzer,address,undefined", "-fno-sanitize-recover=all"]


def found(harness: str) -> list[bytes]:
    folder = FOUND / harness
    return [p.read_bytes() for p in sorted(folder.iterdir())] if folder.is_dir() else []


@pytest.mark.parametrize("harness", ["urwire", pytest.param("json", marks=pytest.mark.deep)])   # json: test-deep
def test_the_kept_corpus_and_seeds_pass_their_harness(harness, tmp_path):
    """The harness builds as `make fuzz` builds it, and runs once over every kept input and seed
    (-runs=0: no fuzzing), with the checks it makes on every input."""
    if shutil.which("clang") is None:
        pytest.fail("clang is not installed (scripts/setup.sh installs it)")
    fuzzer = OUT / "fuzz" / f"fuzz_{harness}"
    compile_c("clang", FUZZER_FLAGS, [ROOT / "tests" / "c" / f"fuzz_{harness}.c", *CLI_LIBRARY, GEN / "urwire.c"],
              fuzzer, ["-lm"])
    folders = [CORPUS / harness] + ([ROOT / "tests" / "c" / "regressions"] if harness == "urwire" else [])
    count = sum(1 for f in folders for p in f.iterdir() if p.is_file())
    folders.append(write_seeds(harness, tmp_path / "seeds"))
    result = run_once([str(fuzzer)], folders, tmp_path / "crashes")
    assert result.returncode == 0, result.stderr[-3000:]
    assert count > 20 and libfuzzer_runs(result.stderr) >= count + len(set(seeds(harness)))


def test_the_fuzzers_inputs_agree_with_python(fast):
    """Coverage-guided inputs reach corners random mutation does not; Python must agree on each."""
    inputs = [(h, raw) for h in HARNESSES for raw in kept(h) + found(h)]
    inputs += [("urwire", b"\0" + stream) for stream in long_messages()]
    assert len(inputs) > 100
    with CommandPeer(fast.driver) as peer:
        for harness, raw in inputs:
            hint, data = split(harness, raw)
            assert peer.decode(data, hint) == python_answer(data, hint), f"{harness} input {raw[:80].hex()}"
