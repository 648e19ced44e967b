"""make fuzz-wireshark: Wireshark's own fuzzing, as its tools/fuzz-test.sh does it: `editcap -E
<probability>` mutates a sample capture, and `tshark -nVxr` reads the result, with the debugging
environment of its tools/test-common.sh (the strict wmem allocator, abort on a dissector bug or
too many tree items). Here tshark reads each mutation twice: with the native plugin built under
ASan and UBSan (tests/native/harness.py, variant asan; libasan preloaded, as tshark itself is not
instrumented) and, separately, with every Lua dissector of generated/lua.

A run fails on a crash, a non-zero exit, a sanitizer report, a dissector bug or a Lua error; the
capture that failed and what tshark said are kept under build/fuzz-wireshark/failures/.

Inputs: dissector/samples/*, a capture holding every golden vector of every interface (one TCP
session each, tests/tools/golden_sessions.py) and the same cut into 1-7 byte segments; each read
unmutated first. Then mutations of inputs picked at random (seeded), until --seconds (counted
from the end of the unmutated pass) or --mutations runs out.
"""
from __future__ import annotations

import argparse
import os
import random
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT), str(ROOT / "python"), str(ROOT / "generated" / "python")]
from tests.native import harness  # noqa: E402
from tests.tools import golden_sessions  # noqa: E402

OUT = ROOT / "build" / "fuzz-wireshark"
SAMPLES = ROOT / "dissector" / "samples"
TSHARK_ARGS = ["-nVx"]                  # fuzz-test.sh's -nVxr, reading the capture from stdin
PROBABILITY = 0.02                      # fuzz-test.sh's default ERR_PROB
TIMEOUT = 300                           # fuzz-test.sh's MAX_CPU_TIME, per tshark run

# tools/test-common.sh: what Wireshark's fuzz bot sets
WIRESHARK_DEBUG = {
    "WIRESHARK_DEBUG_WMEM_OVERRIDE": "strict",
    "WIRESHARK_ABORT_ON_DISSECTOR_BUG": "1",
    "WIRESHARK_ABORT_ON_TOO_MANY_ITEMS": "1",
    "G_SLICE": "debug-blocks",
}
SANITIZERS = {
    "ASAN_OPTIONS": "detect_leaks=0:abort_on_error=0:exitcode=86",
    "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1",
}
SANITIZER_REPORTS = ("ERROR: AddressSanitizer", "runtime error:", "UndefinedBehaviorSanitizer",
                     "ERROR: LeakSanitizer")
LUA_ERRORS = ("Lua: Error", "Lua Error", "_ws.lua.error")


@dataclass(frozen=True)
class Reader:
    """One way of reading a capture: `run(bytes)` gives tshark's finished process."""
    name: str
    run: object


def asan_preload() -> str:
    return subprocess.run(["gcc", "-print-file-name=libasan.so"], capture_output=True, text=True,
                          check=True).stdout.strip()


def native_reader(epan_dir: Path) -> Reader:
    built = harness.build_plugin("asan", epan_dir)
    env = {**WIRESHARK_DEBUG, **SANITIZERS, "LD_PRELOAD": asan_preload()}
    return Reader(f"native (ASan+UBSan, {built.library.name})",
                  lambda data: harness.tshark_with(built, [*TSHARK_ARGS, "-r", "-"], data, env, TIMEOUT))


def lua_reader(scripts: list[Path]) -> Reader:
    env = {**os.environ, **WIRESHARK_DEBUG, "MALLOC_CHECK_": "3", "HOME": str(harness._empty_home())}
    env.pop("XDG_CONFIG_HOME", None)
    args = [a for script in scripts for a in ("-X", f"lua_script:{script}")]

    def run(data: bytes) -> subprocess.CompletedProcess:
        return subprocess.run(["tshark", *TSHARK_ARGS, "-r", "-", *args], input=data, capture_output=True, env=env,
                              timeout=TIMEOUT)
    return Reader(f"Lua ({len(scripts)} dissectors)", run)


def problem(result: subprocess.CompletedProcess) -> Optional[str]:
    """What is wrong with one tshark run, or None."""
    err = result.stderr.decode(errors="replace")
    out = result.stdout.decode(errors="replace")
    if result.returncode < 0:
        return f"killed by signal {-result.returncode}"
    for report in SANITIZER_REPORTS:
        if report in err:
            return f"sanitizer report ({report})"
    for error in LUA_ERRORS:
        if error in err or error in out:
            return f"Lua error ({error})"
    if "Dissector bug" in out or "dissector bug" in err.lower():
        return "dissector bug"
    if result.returncode != 0:
        return f"exit status {result.returncode}"
    return None


def inputs(folder: Path) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    made = [golden_sessions.write(folder / "golden_vectors.pcap"),
            golden_sessions.write(folder / "golden_vectors_1_7_byte_segments.pcap", cut=True)]
    return [*sorted(p for p in SAMPLES.iterdir() if p.suffix in (".pcap", ".pcapng")), *made]


def mutate(source: Path, target: Path, probability: float, seed: int) -> bool:
    """editcap -E, as fuzz-test.sh runs it; False when editcap cannot write the format."""
    result = subprocess.run(["editcap", "-E", str(probability), "--seed", str(seed), str(source), str(target)],
                            capture_output=True)
    return result.returncode == 0


def keep(capture: Path, reader: Reader, result: subprocess.CompletedProcess, why: str, label: str,
         out: Path) -> Path:
    failures = out / "failures"
    failures.mkdir(parents=True, exist_ok=True)
    kept = failures / f"{label}{capture.suffix}"
    shutil.copy(capture, kept)
    (failures / f"{label}.txt").write_text(
        f"{why}\nreader: {reader.name}\ntshark {' '.join(TSHARK_ARGS)} -r {kept.name}\n\nstderr:\n"
        + result.stderr.decode(errors="replace")[-20000:])
    return kept


def read_all(capture: Path, readers: list[Reader], label: str, out: Path) -> bool:
    data = capture.read_bytes()
    for reader in readers:
        result = reader.run(data)
        why = problem(result)
        if why:
            kept = keep(capture, reader, result, why, label, out)
            print(f"fuzz-wireshark: FAILED: {reader.name} on {label}: {why}; kept {kept} "
                  f"(and {kept.with_suffix('.txt').name})", file=sys.stderr)
            return False
    return True


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=60,
                        help="stop starting mutations this long after the unmutated pass (60)")
    parser.add_argument("--mutations", type=int, default=0, help="stop after this many (0: no limit)")
    parser.add_argument("--seed", type=int, default=None, help="editcap's first seed (default: from the clock)")
    parser.add_argument("--probability", type=float, default=PROBABILITY, help=f"editcap -E ({PROBABILITY})")
    parser.add_argument("--epan-dir", type=Path, default=harness.EPAN,
                        help="the packet-*.c of the native plugin (default generated/epan)")
    parser.add_argument("--lua", type=Path, nargs="*", default=None,
                        help="the Lua dissectors (default every generated/lua/*.lua)")
    parser.add_argument("--out", type=Path, default=OUT, help="where inputs, work and failures go")
    parser.add_argument("--only-inputs", type=Path, nargs="*", default=None, help="these captures instead")
    args = parser.parse_args()

    readers = []
    if any(args.epan_dir.glob("packet-*.c")):
        readers.append(native_reader(args.epan_dir.resolve()))
    else:
        print(f"fuzz-wireshark: no packet-*.c under {args.epan_dir}: the Lua dissectors only")
    readers.append(lua_reader(args.lua if args.lua is not None else sorted(harness.LUA.glob("*.lua"))))
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    captures = args.only_inputs or inputs(out / "inputs")
    seed = args.seed if args.seed is not None else int(time.time())
    print(f"fuzz-wireshark: {', '.join(r.name for r in readers)}; {len(captures)} captures; editcap -E "
          f"{args.probability} --seed from {seed}; up to {args.seconds:g} s"
          + (f" or {args.mutations} mutations" if args.mutations else ""))
    for capture in captures:
        if not read_all(capture, readers, f"{capture.stem}-original", out):
            return 1
    started = time.monotonic()      # the time bound is the mutations', after the unmutated pass
    work = out / "work"
    work.mkdir(parents=True, exist_ok=True)
    done = 0
    rng = random.Random(seed)
    while time.monotonic() - started < args.seconds and not (args.mutations and done >= args.mutations):
        source = rng.choice(captures)
        mutated = work / f"mutated{source.suffix}"
        this_seed = seed + done
        if not mutate(source, mutated, args.probability, this_seed):
            print(f"fuzz-wireshark: editcap cannot mutate {source.name}", file=sys.stderr)
            return 2
        if not read_all(mutated, readers, f"{source.stem}-seed{this_seed}", out):
            return 1
        done += 1
    print(f"fuzz-wireshark: {done} mutations read without a crash, sanitizer report, dissector bug or Lua error "
          f"in {time.monotonic() - started:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
