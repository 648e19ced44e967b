"""make fuzz-wireshark: Wireshark's own fuzzing, as its tools/fuzz-test.sh does it, per interface:
`editcap -E <probability>` mutates a capture, and `tshark -nVxr` reads the result, with the
debugging environment of its tools/test-common.sh (the strict wmem allocator, abort on a dissector
bug or too many tree items). Here tshark reads each mutation twice: with the native plugin built
under ASan and UBSan (tests/native/harness.py, variant asan; libasan preloaded, as tshark itself is
not instrumented) and, separately, with every Lua dissector of generated/lua.

The inputs of an interface: a capture holding each of its golden vectors as a TCP session
(tests/tools/golden_sessions.py), the same cut into 1-7 byte segments, and its conversations in
each of dissector/samples/* (taken out by port). Each is read unmutated first; then mutations of
inputs picked at random (seeded), half of them sparing the frames' first 54 bytes (Ethernet, IPv4
and TCP headers: editcap -o) so that the payload takes every change, until the interface's share
of --seconds (counted from the end of its unmutated pass) or --mutations runs out.

Counted per interface and printed as a table: malformed packets (frames with `_ws.malformed`: an
exception, or an expert info of the Malformed group, which is how the dissectors name a fault),
exceptions among them ("[Malformed Packet"), and the failures: a crash, a non-zero exit, a
sanitizer report, a dissector bug, a Lua error, and an exception on an unmutated capture (a golden
vector or a sample: real input must not make a dissector read past what it checked). Mutated input
is malformed by design, so its malformed packets are counted, not failures. The frames whose
protocol lines (each protocol's summary in -V) differ between the native plugin and Lua are
counted too: a failure on an unmutated capture, and on a mutated one a finding, its capture kept
under build/fuzz-wireshark/differences/. Each failing capture and what tshark said are kept under
build/fuzz-wireshark/failures/; the run fails if any.

`--replay` reads the kept corpora instead (tests/fuzz/corpus/wireshark_<interface>/: mutated
captures, each once), as `make test` does (tests/native/test_fuzz_wireshark.py).

    make fuzz-wireshark FUZZ_SECONDS=120                 every interface, in four groups
    python3 tests/fuzz/fuzz_wireshark.py --seconds 60 rtde
"""
from __future__ import annotations

import argparse
import os
import random
import re
import shutil
import subprocess
import sys
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT), str(ROOT / "python"), str(ROOT / "generated" / "python")]
from tests.native import harness  # noqa: E402
from tests.tools import golden_sessions  # noqa: E402

OUT = ROOT / "build" / "fuzz-wireshark"
SAMPLES = ROOT / "dissector" / "samples"
CORPUS = ROOT / "tests" / "fuzz" / "corpus"
INTERFACES = ("ur", "ur_realtime", "rtde", "ur_dashboard", "ur_reverse", "ur_script_sender", "ur_trajectory",
              "ur_script_command")
HEADERS = 54                            # Ethernet, IPv4 and TCP headers without options: editcap -o
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
FRAME = re.compile(r"Frame \d+: ")     # the line that opens a frame in tshark -V
HEX_LINE = re.compile(r"[0-9a-f]{4,}  ")                 # tshark -x: a line of a hex dump
DUMP_TITLE = re.compile(r"[A-Za-z][A-Za-z0-9 ]* \(\d+ bytes\):$")   # and the title of one data source
MAX_DIFFERENCES_KEPT = 20
LUA_ERRORS = ("Lua: Error", "Lua Error", "_ws.lua.error")


@dataclass(frozen=True)
class Reader:
    """One way of reading a capture: `run(bytes)` gives tshark's finished process."""
    name: str
    run: object


def asan_preload() -> str:
    return subprocess.run(["gcc", "-print-file-name=libasan.so"], capture_output=True, text=True,
                          check=True).stdout.strip()


def native_reader(epan_dir: Path, variant: str = "asan") -> Reader:
    """The native plugin's build `variant` (tests/native/harness.py): asan preloads libasan."""
    built = harness.build_plugin(variant, epan_dir)
    env = {**WIRESHARK_DEBUG, **SANITIZERS, "LD_PRELOAD": asan_preload()} if variant == "asan" else WIRESHARK_DEBUG
    name = "ASan+UBSan" if variant == "asan" else variant
    return Reader(f"native ({name}, {built.library.name})",
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


# The failure classes of `problem`, by the start of its text, as the summary counts them.
KINDS = {"killed by signal": "crashes", "sanitizer report": "sanitizer reports", "Lua error": "Lua errors",
         "dissector bug": "dissector bugs", "exit status": "other exits", "exception": "exceptions unmutated",
         "dissectors differ": "dissectors differ unmutated"}


def malformed_frames(result: subprocess.CompletedProcess) -> tuple[int, int]:
    """(frames with `_ws.malformed`, frames with an exception) in tshark -V's text: an exception
    shows "[Malformed Packet"; an expert info of the Malformed group "(<severity>/Malformed)"."""
    malformed = exceptions = 0
    flagged = thrown = False
    for line in result.stdout.decode(errors="replace").splitlines() + ["Frame 0: end"]:
        if FRAME.match(line):           # not -x's "Frame (60 bytes):" above a hex dump
            malformed, exceptions = malformed + flagged, exceptions + thrown
            flagged = thrown = False
        elif "[Malformed Packet" in line:
            flagged = thrown = True
        elif "/Malformed)" in line:
            flagged = True
    return malformed, exceptions


@dataclass
class Tally:
    """What one interface's run met."""
    inputs: int = 0
    mutations: int = 0
    malformed: Counter = field(default_factory=Counter)     # by reader
    exceptions: Counter = field(default_factory=Counter)    # by reader
    failures: Counter = field(default_factory=Counter)      # by KINDS value
    differing: int = 0          # frames whose top lines differ between the native plugin and Lua


def interface_ports(interface: str) -> tuple[int, ...]:
    from urwire.interfaces import INTERFACES as CELL

    return CELL[interface].ports


def pcapng_packets(path: Path) -> int:
    """Enhanced packet blocks in a little-endian pcapng (what tshark -w writes)."""
    data, at, count = path.read_bytes(), 0, 0
    while at + 8 <= len(data):
        kind, length = int.from_bytes(data[at:at + 4], "little"), int.from_bytes(data[at + 4:at + 8], "little")
        count += kind in (3, 6)
        at += max(length, 12)
    return count


def inputs(folder: Path, interface: str) -> list[Path]:
    """The interface's golden sessions, whole and in 1-7 byte segments, and its conversations in
    each sample capture that has some."""
    folder.mkdir(parents=True, exist_ok=True)
    made = [golden_sessions.write(folder / f"{interface}-golden_vectors.pcap", interface=interface),
            golden_sessions.write(folder / f"{interface}-golden_vectors_1_7_byte_segments.pcap", cut=True,
                                  interface=interface)]
    ports = " || ".join(f"tcp.port == {port}" for port in interface_ports(interface))
    env = {**os.environ, "HOME": str(harness._empty_home())}
    for sample in sorted(p for p in SAMPLES.iterdir() if p.suffix in (".pcap", ".pcapng")):
        part = folder / f"{interface}-{sample.stem}.pcapng"
        subprocess.run(["tshark", "-r", str(sample), "-Y", ports, "-w", str(part)],
                       capture_output=True, check=True, env=env)
        if pcapng_packets(part):
            made.append(part)
        else:
            part.unlink()
    return made


def mutate(source: Path, target: Path, probability: float, seed: int, skip: int = 0) -> bool:
    """editcap -E, as fuzz-test.sh runs it (-o: leave each frame's first `skip` bytes); False when
    editcap cannot write the format."""
    result = subprocess.run(["editcap", "-E", str(probability), "-o", str(skip), "--seed", str(seed), str(source),
                             str(target)], capture_output=True)
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


def tree_roots(result: subprocess.CompletedProcess) -> dict[str, list[str]]:
    """Each frame's top lines in tshark -V: one per protocol, with the summary its dissector gave
    (not -x's hex dumps nor their "Frame (60 bytes):" titles)."""
    frames: dict[str, list[str]] = {}
    lines: list[str] = []
    for line in result.stdout.decode(errors="replace").splitlines():
        if FRAME.match(line):
            lines = frames[line.split(":", 1)[0]] = []
        elif line and not line[0].isspace() and not HEX_LINE.match(line) and not DUMP_TITLE.match(line):
            lines.append(line)
    return frames


def differing_frames(native: subprocess.CompletedProcess, lua: subprocess.CompletedProcess) -> list[str]:
    """The frames whose protocols or summaries differ between two readers, with both texts."""
    a, b = tree_roots(native), tree_roots(lua)
    out = []
    for frame in sorted(set(a) | set(b), key=lambda f: int(f.split()[1])):
        one, other = a.get(frame, []), b.get(frame, [])
        if one != other:
            same = next((i for i, (x, y) in enumerate(zip(one, other)) if x != y), min(len(one), len(other)))
            out.append(f"{frame}, from its protocol {same + 1} on:\n  {' | '.join(one[same:]) or '(nothing)'}\n"
                       f"  {' | '.join(other[same:]) or '(nothing)'}")
    return out


def keep_difference(capture: Path, readers: list[Reader], frames: list[str], label: str, out: Path) -> None:
    folder = out / "differences"
    folder.mkdir(parents=True, exist_ok=True)
    if len(list(folder.glob("*.txt"))) < MAX_DIFFERENCES_KEPT:
        shutil.copy(capture, folder / f"{label}{capture.suffix}")
        (folder / f"{label}.txt").write_text(f"{len(frames)} frames differ between {readers[0].name} and "
                                            f"{readers[1].name}:\n" + "\n".join(frames[:50]) + "\n")


def read_all(capture: Path, readers: list[Reader], label: str, out: Path, tally: Tally, mutated: bool) -> bool:
    """Every reader on one capture, counted into the tally; False on a failure (the capture kept).
    With two readers, the frames where their trees' top lines differ are counted too; on a capture
    that is not mutated that is a failure, on a mutated one the capture is kept under differences/."""
    data, fine, results = capture.read_bytes(), True, []
    for reader in readers:
        result = reader.run(data)
        results.append(result)
        malformed, exceptions = malformed_frames(result)
        tally.malformed[reader.name] += malformed
        tally.exceptions[reader.name] += exceptions
        why = problem(result)
        if why is None and exceptions and not mutated:
            why = f"exception on an unmutated capture ({exceptions} frames show [Malformed Packet)"
        if why:
            tally.failures[next(v for k, v in KINDS.items() if why.startswith(k))] += 1
            kept = keep(capture, reader, result, why, label, out)
            print(f"fuzz-wireshark: FAILED: {reader.name} on {label}: {why}; kept {kept} "
                  f"(and {kept.with_suffix('.txt').name})", file=sys.stderr)
            fine = False
    frames = differing_frames(*results[:2]) if len(results) == 2 and fine else []
    tally.differing += len(frames)
    if frames and not mutated:
        why = f"dissectors differ on an unmutated capture: {len(frames)} frames, first {frames[0]}"
        tally.failures["dissectors differ unmutated"] += 1
        kept = keep(capture, readers[1], results[1], why, label, out)
        print(f"fuzz-wireshark: FAILED: {why}; kept {kept}", file=sys.stderr)
        fine = False
    elif frames:
        keep_difference(capture, readers, frames, label, out)
    return fine


def fuzz_interface(name: str, captures: list[Path], readers: list[Reader], args, seed: int, seconds: float,
                   out: Path, mutated: bool = False) -> Tally:
    """The unmutated pass over the captures (mutated ones when replaying), then mutations for `seconds`."""
    tally = Tally(inputs=len(captures))
    for capture in captures:
        read_all(capture, readers, f"{capture.stem}-{'kept' if mutated else 'original'}", out, tally, mutated)
    started = time.monotonic()      # the time bound is the mutations', after the unmutated pass
    work = out / "work"
    work.mkdir(parents=True, exist_ok=True)
    rng = random.Random(f"{seed} {name}")
    while (captures and time.monotonic() - started < seconds
           and not (args.mutations and tally.mutations >= args.mutations)):
        source = rng.choice(captures)
        this_seed, skip = seed + tally.mutations, rng.choice((0, HEADERS))
        mutated_capture = work / f"{name}-mutated{source.suffix}"
        if not mutate(source, mutated_capture, args.probability, this_seed, skip):
            raise SystemExit(f"fuzz-wireshark: editcap cannot mutate {source.name}")
        label = f"{source.stem}-seed{this_seed}" + (f"-o{skip}" if skip else "")
        read_all(mutated_capture, readers, label, out, tally, True)
        if args.save_mutations:
            (args.save_mutations / name).mkdir(parents=True, exist_ok=True)
            shutil.copy(mutated_capture, args.save_mutations / name / f"{label}{source.suffix}")
        tally.mutations += 1
    return tally


def summary(tallies: dict[str, Tally], readers: list[Reader]) -> str:
    """The table of every interface's counts: malformed packets and exceptions by reader, then the
    failures by kind."""
    short = ["native" if r.name.startswith("native") else "Lua" for r in readers]
    kinds = list(dict.fromkeys(KINDS.values()))
    head = (["interface", "inputs", "mutations"] + [f"malformed {s}" for s in short]
            + [f"exceptions {s}" for s in short] + ["frames differ"] + kinds)
    rows = [[name, t.inputs, t.mutations] + [t.malformed[r.name] for r in readers]
            + [t.exceptions[r.name] for r in readers] + [t.differing] + [t.failures[k] for k in kinds]
            for name, t in tallies.items()]
    widths = [max(len(str(x)) for x in column) for column in zip(head, *rows)]
    return "\n".join("  ".join(str(x).rjust(w) if i else str(x).ljust(w) for i, (x, w) in enumerate(zip(row, widths)))
                     for row in [head, *rows])


def kept_captures(interface: str) -> list[Path]:
    folder = CORPUS / f"wireshark_{interface}"
    return sorted(p for p in folder.iterdir() if p.suffix in (".pcap", ".pcapng")) if folder.is_dir() else []


def main(argv: Optional[list[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("interfaces", nargs="*", metavar="INTERFACE",
                        help=f"the interfaces to fuzz (default: every one: {' '.join(INTERFACES)})")
    parser.add_argument("--seconds", type=float, default=60,
                        help="the mutations' time, shared evenly by the interfaces, each counted after its "
                             "unmutated pass (60)")
    parser.add_argument("--mutations", type=int, default=0, help="stop each interface after this many (0: no limit)")
    parser.add_argument("--seed", type=int, default=None, help="editcap's first seed (default: from the clock)")
    parser.add_argument("--probability", type=float, default=PROBABILITY, help=f"editcap -E ({PROBABILITY})")
    parser.add_argument("--epan-dir", type=Path, default=harness.EPAN,
                        help="the packet-*.c of the native plugin (default generated/epan)")
    parser.add_argument("--native", choices=("asan", "gcc"), default="asan",
                        help="the native plugin's build: asan (ASan+UBSan, the default) or gcc (plain)")
    parser.add_argument("--lua", type=Path, nargs="*", default=None,
                        help="the Lua dissectors (default every generated/lua/*.lua)")
    parser.add_argument("--out", type=Path, default=OUT, help="where inputs, work and failures go")
    parser.add_argument("--only-inputs", type=Path, nargs="*", default=None,
                        help="these captures instead of the interfaces' (counted as one row, 'given')")
    parser.add_argument("--replay", action="store_true",
                        help="read each interface's kept corpus (tests/fuzz/corpus/wireshark_<interface>/) once, "
                             "as mutated captures, and nothing else")
    parser.add_argument("--save-mutations", type=Path, default=None,
                        help="keep every mutated capture here, under <interface>/ (to choose a kept corpus)")
    args = parser.parse_args(argv)
    interfaces = args.interfaces or list(INTERFACES)
    for name in set(interfaces) - set(INTERFACES):
        parser.error(f"not an interface of the cell: {name}")

    readers = []
    if any(args.epan_dir.glob("packet-*.c")):
        readers.append(native_reader(args.epan_dir.resolve(), args.native))
    else:
        print(f"fuzz-wireshark: no packet-*.c under {args.epan_dir}: the Lua dissectors only")
    readers.append(lua_reader(args.lua if args.lua is not None else sorted(harness.LUA.glob("*.lua"))))
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    seed = args.seed if args.seed is not None else int(time.time())
    if args.only_inputs is not None:
        groups = {"given": args.only_inputs}
    elif args.replay:
        groups = {name: kept_captures(name) for name in interfaces}
    else:
        groups = {name: inputs(out / "inputs", name) for name in interfaces}
    seconds = 0 if args.replay else args.seconds / len(groups)
    print(f"fuzz-wireshark: {', '.join(r.name for r in readers)}; {', '.join(groups)}; "
          + ("their kept corpora" if args.replay else
             f"editcap -E {args.probability} --seed from {seed}; {seconds:g} s each"
             + (f" or {args.mutations} mutations" if args.mutations else "")))
    tallies = {name: fuzz_interface(name, captures, readers, args, seed, seconds, out, mutated=args.replay)
               for name, captures in groups.items()}
    print(summary(tallies, readers))
    failed = sum(sum(t.failures.values()) for t in tallies.values())
    done = sum(t.mutations for t in tallies.values())
    if failed:
        print(f"fuzz-wireshark: {failed} failures; the captures are kept under {out / 'failures'}", file=sys.stderr)
        return 1
    read = sum(t.inputs for t in tallies.values())
    print(f"fuzz-wireshark: {read} captures and {done} mutations read without a crash, sanitizer report, "
          f"dissector bug or Lua error")
    return 0


if __name__ == "__main__":
    sys.exit(main())
