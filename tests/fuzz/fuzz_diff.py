#!/usr/bin/env python3
"""Differential fuzzing of the cell's interfaces: the same mutated sessions through `urwire decode`
and `urwire-decode`, which must print the same lines, byte for byte, and exit alike.

Each input is a session of one interface (tests/fuzz/diff_sessions.py): the robot's stream, the
client's (for the interfaces that decode both directions) and a version hint, written to two
files, which both commands read:

    urwire decode --protocol X ROBOT --to-robot CLIENT [--version-hint V]
    urwire-decode --protocol X ROBOT --to-robot CLIENT [--version-hint V]

Python runs in this process (the command's own `urwire.cli.main`, its output caught);
the C command runs in one long-lived process (tests/c/decode_driver.c: the command's main linked
in, ASan and UBSan on), so that an input costs no process. Sessions start from the interface's
golden vectors and kept corpus (tests/fuzz/corpus/diff_<interface>/) and are mutated with a
seeded mutator; a mutant whose records show something new (a record type, key set, error text,
flag or short value) joins the pool that later mutants are drawn from.

On a difference, an exception in Python, or the C process dying, the session is written to
build/fuzz/crashes/diff_<interface>/ (with a .txt of the difference) and the run fails; with
--keep-going it goes on and counts them.

    make fuzz-diff FUZZ_SECONDS=120                       every interface
    python3 tests/fuzz/fuzz_diff.py --peer build/fuzz/decode_driver --seconds 60 rtde
    python3 tests/fuzz/fuzz_diff.py --show FILE --interface rtde       both outputs, where they part
    python3 tests/fuzz/fuzz_diff.py --minimize FILE --interface rtde   a smaller session that fails
"""
from __future__ import annotations

import argparse
import contextlib
import hashlib
import io
import json
import os
import random
import re
import select
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Optional

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT), str(ROOT / "python"), str(ROOT / "generated" / "python")]
from tests.fuzz import diff_sessions  # noqa: E402
from tests.fuzz.diff_sessions import INTERFACES, Mutator, Session, dump, load, seeds  # noqa: E402

CRASHES = ROOT / "build" / "fuzz" / "crashes"
# What a record carries as given text, or names and places: no feature of its own.
FREE_TEXT = {"conversation", "raw", "interface", "direction", "command", "reply", "text", "title", "message",
             "source", "program", "file"}
MAX_POOL = 4000            # sessions mutants are drawn from
PEER_TIMEOUT = 30          # seconds for one session in C: a hang is a finding too
Answer = tuple[bytes, int]  # what a command prints, and its exit status
END = re.compile(rb"(?:^|\n)=(\d+)\n")   # the driver's line after each answer: "=" and the exit status


def command_args(interface: str, session: Session, robot: Path, client: Path) -> list[str]:
    """The arguments after `urwire decode` / `urwire-decode` for a session in these files."""
    args = [str(robot), "--protocol", interface]
    if session.to_robot:
        args += ["--to-robot", str(client)]
    if session.hint:
        args += ["--version-hint", session.hint]
    return args


def python_answer(args: list[str]) -> Answer:
    """`urwire decode ARGS` run in this process: its standard output and exit status."""
    from urwire import cli

    out = io.BytesIO()
    text = io.TextIOWrapper(out, encoding="utf-8", newline="\n", write_through=True)
    with contextlib.redirect_stdout(text), contextlib.redirect_stderr(io.StringIO()):
        try:
            status = cli.main(["decode", *args])
        except SystemExit as exc:
            status = exc.code if isinstance(exc.code, int) else 2
    text.flush()
    return out.getvalue(), status


class CPeer:
    """tests/c/decode_driver.c: urwire-decode's main run again for each request, in one process.
    What it writes to stderr (a sanitizer's report) goes to a file, shown when it dies."""

    def __init__(self, driver: Path):
        self.stderr = tempfile.TemporaryFile()
        env = {**os.environ, "ASAN_OPTIONS": "detect_leaks=0:abort_on_error=0",
               "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1"}
        self.driver = driver
        self.proc = subprocess.Popen([str(driver)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=self.stderr, env=env)
        self.pending = b""

    def answer(self, args: list[str]) -> Answer:
        request = len(args).to_bytes(4, "big") + b"".join(
            len(a.encode()).to_bytes(4, "big") + a.encode() for a in args)
        self.proc.stdin.write(request)
        self.proc.stdin.flush()
        fd, deadline, data = self.proc.stdout.fileno(), time.monotonic() + PEER_TIMEOUT, self.pending
        while True:
            end = END.search(data)
            if end:
                self.pending = data[end.end():]
                return data[:end.start() + (data[end.start():end.start() + 1] == b"\n")], int(end.group(1))
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([fd], [], [], left)[0]:
                raise PeerDied(f"urwire-decode took over {PEER_TIMEOUT} s")
            chunk = os.read(fd, 1 << 16)
            if not chunk:
                raise PeerDied(f"urwire-decode died (exit {self.proc.wait()}): {self.errors()}")
            data += chunk

    def errors(self) -> str:
        self.stderr.seek(0)
        return self.stderr.read().decode("utf-8", "replace")[-4000:]

    def restart(self) -> "CPeer":
        self.close()
        return CPeer(self.driver)

    def close(self) -> None:
        with contextlib.suppress(OSError):
            self.proc.stdin.close()
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.wait()
        self.stderr.close()


class PeerDied(Exception):
    pass


class Workspace:
    """Two files a session is written to, read by both commands under the same names."""

    def __init__(self):
        base = "/dev/shm" if os.path.isdir("/dev/shm") and os.access("/dev/shm", os.W_OK) else None
        self.dir = tempfile.TemporaryDirectory(prefix="urwire-diff-", dir=base)
        self.robot, self.client = Path(self.dir.name) / "robot.bin", Path(self.dir.name) / "client.bin"

    def args(self, interface: str, session: Session) -> list[str]:
        self.robot.write_bytes(session.stream(True))
        self.client.write_bytes(session.stream(False))
        return command_args(interface, session, self.robot, self.client)


def lines(output: bytes) -> list[bytes]:
    """The lines of an output, the last one unended if it is."""
    return output[:-1].split(b"\n") if output.endswith(b"\n") else output.split(b"\n") if output else []


def difference(python: Answer, c: Answer) -> Optional[str]:
    """None when the two answers are the same, else where they first part."""
    if python == c:
        return None
    p, q = lines(python[0]), lines(c[0])
    for i, (a, b) in enumerate(zip(p, q)):
        if a != b:
            return f"line {i + 1}:\n  python: {a[:600]!r}\n  c:      {b[:600]!r}"
    if len(p) != len(q):
        longer, name = (p, "python") if len(p) > len(q) else (q, "c")
        return f"{len(p)} lines from python, {len(q)} from c; {name} goes on with {longer[min(len(p), len(q))][:600]!r}"
    return f"exit status: python {python[1]}, c {c[1]}"


def check(interface: str, session: Session, peer: CPeer, space: Workspace) -> tuple[Optional[str], bytes]:
    """(what is wrong, or None; Python's output) for one session."""
    args = space.args(interface, session)
    try:
        python = python_answer(args)
    except Exception as exc:     # noqa: BLE001 - any exception of the command is a finding
        return f"python raised {type(exc).__name__}: {exc}", b""
    if read_as_capture(session):
        return None, python[0]
    c = peer.answer(args)
    return difference(python, c), python[0]


def read_as_capture(session: Session) -> bool:
    """Whether `urwire decode` reads the robot's file as a capture: alone, opening with a whole
    capture file header (a mutant's magic followed by a version's bytes). urwire-decode reads raw
    streams only, so the two are not compared there (docs/canonical-json.md)."""
    from urwire.capture import HEAD_BYTES, is_capture

    return not session.to_robot and is_capture(session.stream(True)[:HEAD_BYTES])


def features(output: bytes) -> set:
    """What a session's records show, coarsely: each record's type, direction and keys, each error
    text and each short text value that is not free text, with its numbers taken out, and each flag; a mutant that shows a new one joins
    the pool."""
    out = set()
    for line in output.splitlines():
        try:
            record = json.loads(line)
        except ValueError:
            continue
        if not isinstance(record, dict):
            continue
        kind = (record.get("direction"), record.get("type"))
        out.add(("keys", kind, tuple(sorted(record))))
        for key, value in record.items():
            if isinstance(value, bool) or value is None:
                out.add((key, kind, value))
            elif isinstance(value, str) and key not in FREE_TEXT:
                text = re.sub(r"\d+", "N", value)
                if key in ("error", "warning") or len(text) <= 24:
                    out.add((key, kind, text[:120]))
    return out


def keep_failure(interface: str, session: Session, why: str, args: list[str], folder: Path) -> Path:
    raw = dump(session)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / hashlib.sha1(raw).hexdigest()
    path.write_bytes(raw)
    shown = " ".join(a.replace(str(Path(args[0]).parent), "DIR") for a in args)
    path.with_suffix(".txt").write_text(f"{interface}: {why}\n\nurwire decode {shown}\n"
                                        f"show it: python3 tests/fuzz/fuzz_diff.py --show {path} "
                                        f"--interface {interface}\n")
    return path


def fuzz(interface: str, seconds: float, runs: int, rng: random.Random, peer: CPeer, space: Workspace,
         crashes: Path, keep_going: bool, new_corpus: Optional[Path]) -> tuple[int, int, CPeer]:
    """(inputs run, failures) of one interface; the peer, restarted if it died."""
    pool = seeds(interface)
    mutate = Mutator(interface, rng)
    seen: set = set()
    done = failures = 0
    started = time.monotonic()
    queue = list(pool)           # the seeds themselves first
    seeded = len(queue)
    while (queue or time.monotonic() - started < seconds) and not (runs and done >= runs):
        session = queue.pop(0) if queue else mutate(rng.choice(pool), pool)
        try:
            why, output = check(interface, session, peer, space)
        except PeerDied as died:
            why, output = str(died), b""
            peer = peer.restart()
        done += 1
        if why:
            failures += 1
            kept = keep_failure(interface, session, why, space.args(interface, session), crashes / f"diff_{interface}")
            print(f"fuzz-diff: {interface}: {why.splitlines()[0]} (kept {kept})", file=sys.stderr)
            if not keep_going:
                break
            continue
        new = features(output) - seen
        if new:
            seen |= new
            if done > seeded and len(pool) < MAX_POOL:
                pool.append(session)
                if new_corpus is not None:
                    new_corpus.mkdir(parents=True, exist_ok=True)
                    raw = dump(session)
                    (new_corpus / hashlib.sha1(raw).hexdigest()).write_bytes(raw)
    return done, failures, peer


def show(path: Path, interface: str, peer: CPeer, space: Workspace) -> int:
    """Print what each command makes of one kept session, and where they part."""
    session = load(interface, path.read_bytes())
    args = space.args(interface, session)
    python, c = python_answer(args), peer.answer(args)
    print(f"urwire decode {' '.join(args)}")
    for name, (out, status) in (("python", python), ("c", c)):
        print(f"== {name} (exit {status})\n{out.decode('utf-8', 'replace')}")
    print(difference(python, c) or "the same")
    return 0 if python == c else 1


def minimize(path: Path, interface: str, peer: CPeer, space: Workspace) -> Path:
    """A smaller session that still makes the commands part: whole messages dropped, then each
    message's tail cut, while the difference stays; written beside the session as <name>.min."""
    session = load(interface, path.read_bytes())

    def fails(candidate: Session) -> bool:
        return check(interface, candidate, peer, space)[0] is not None

    if not fails(session):
        raise SystemExit(f"fuzz-diff: {path} does not fail")
    changed = True
    while changed:
        changed = False
        for i in reversed(range(len(session.pieces))):
            smaller = Session(session.pieces[:i] + session.pieces[i + 1:], session.hint, session.to_robot)
            if fails(smaller):
                session, changed = smaller, True
        for i in range(len(session.pieces)):
            robot, data = session.pieces[i]
            for cut in (len(data) // 2, len(data) - 1):
                shorter = Session(session.pieces[:i] + ((robot, data[:cut]),) + session.pieces[i + 1:],
                                  session.hint, session.to_robot)
                if 0 <= cut < len(data) and fails(shorter):
                    session, changed = shorter, True
                    break
    out = path.with_name(path.name + ".min")
    out.write_bytes(dump(session))
    return out


def main(argv: Optional[list[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("interfaces", nargs="*", metavar="INTERFACE",
                        help=f"the interfaces to fuzz (default: every one but the primary: {' '.join(INTERFACES)})")
    parser.add_argument("--peer", type=Path, default=ROOT / "build" / "fuzz" / "decode_driver",
                        help="tests/c/decode_driver.c built (make build/fuzz/decode_driver)")
    parser.add_argument("--seconds", type=float, default=60,
                        help="the whole run's time, shared evenly by the interfaces (60)")
    parser.add_argument("--runs", type=int, default=0, help="stop each interface after this many inputs")
    parser.add_argument("--seed", type=int, default=None, help="the mutator's seed (default: from the clock)")
    parser.add_argument("--crashes", type=Path, default=CRASHES, help="where failing sessions go (diff_<interface>/)")
    parser.add_argument("--keep-going", action="store_true", help="count failures instead of stopping at the first")
    parser.add_argument("--new-corpus", type=Path, default=None,
                        help="write each mutant that showed something new here, under <interface>/")
    parser.add_argument("--show", type=Path, default=None, help="show one kept session (with --interface)")
    parser.add_argument("--minimize", type=Path, default=None,
                        help="shrink one failing session (with --interface) to FILE.min, and show it")
    parser.add_argument("--interface", choices=INTERFACES, default=None, help="the interface of --show, --minimize")
    args = parser.parse_args(argv)
    interfaces = args.interfaces or list(INTERFACES)
    for name in set(interfaces) - set(INTERFACES):
        parser.error(f"not an interface this fuzzer reads: {name}")

    peer, space = CPeer(args.peer), Workspace()
    try:
        if args.minimize:
            args.show = minimize(args.minimize, args.interface or interfaces[0], peer, space)
        if args.show:
            return show(args.show, args.interface or interfaces[0], peer, space)
        seed = args.seed if args.seed is not None else int(time.time())
        print(f"fuzz-diff: {', '.join(interfaces)}; seed {seed}; {args.seconds:g} s in all"
              + (f", at most {args.runs} inputs each" if args.runs else ""))
        failed = 0
        for interface in interfaces:
            rng = random.Random(f"{seed} {interface}")
            started = time.monotonic()
            done, failures, peer = fuzz(interface, args.seconds / len(interfaces), args.runs, rng, peer, space,
                                        args.crashes, args.keep_going,
                                        args.new_corpus / interface if args.new_corpus else None)
            print(f"fuzz-diff: {interface}: {done} sessions, {failures} differences, "
                  f"{time.monotonic() - started:.0f} s")
            failed += failures
            if failures and not args.keep_going:
                break
        return 1 if failed else 0
    finally:
        peer.close()
        space.dir.cleanup()


if __name__ == "__main__":
    sys.exit(main())
