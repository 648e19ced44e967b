"""Merge what a fuzzer found into its kept corpus, minimized with libFuzzer's -merge=1.

    python3 tests/fuzz/keep.py HARNESS FUZZER-COMMAND...        (make fuzz-corpus runs it)

tests/fuzz/corpus/HARNESS/ becomes the fewest inputs, out of itself and build/fuzz/corpus/HARNESS/,
that reach every edge they reach beyond the seeds (build/fuzz/seeds/HARNESS/, rebuilt by every
fuzz run, which is why no seed is kept), and none above 64 KiB: the seeds bring the long
messages. Edges, not hit counts (-use_counters=0): a few hundred KiB to check in, not MiBs;
fuzzing grows the counts back within seconds.
"""
from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
LARGEST = 64 * 1024


def keep(harness: str, command: list[str]) -> int:
    kept, found = ROOT / "tests" / "fuzz" / "corpus" / harness, ROOT / "build" / "fuzz" / "corpus" / harness
    seeds, merged = ROOT / "build" / "fuzz" / "seeds" / harness, ROOT / "build" / "fuzz" / "merged" / harness
    if not seeds.is_dir():
        print(f"keep: no seeds in {seeds}: run make fuzz first", file=sys.stderr)
        return 2
    shutil.rmtree(merged, ignore_errors=True)
    shutil.copytree(seeds, merged)   # merged into first: what they reach counts, and is not kept
    kept.mkdir(parents=True, exist_ok=True)
    found.mkdir(parents=True, exist_ok=True)
    subprocess.run([*command, "-merge=1", "-use_counters=0", str(merged), str(kept), str(found)], check=True, cwd=ROOT)
    seed_names = {p.name for p in seeds.iterdir()}
    chosen = [p for p in merged.iterdir() if p.name not in seed_names and p.stat().st_size <= LARGEST]
    for old in kept.iterdir():
        old.unlink()
    for p in chosen:
        shutil.copy(p, kept / p.name)
    print(f"keep: {harness}: {len(chosen)} inputs, {sum(p.stat().st_size for p in chosen)} bytes in {kept}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(keep(sys.argv[1], sys.argv[2:]))
