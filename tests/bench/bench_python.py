"""make bench-python: the Python bindings' speed and memory, every comparison measured in this run.

    python3 tests/bench/bench_python.py [--base REV] [--generations-base REV] [MB ...]   (default: 10 100)

1. Decode of real robot states in pure Python, per message: against python-urx
   (urx.ursecmon.ParserUtils, the `urx` package on PyPI), and against the package that
   --generations-base generated (before every controller generation entered the spec).
   python-urx decodes less than urwire: it stops at the sub-packages it knows, types no enums
   and keeps no bytes for re-encoding.
2. A canonical JSON line per robot state, against the package of --base (before the per-class
   writers): the same state again (at rest: a robot repeats most values from one state to the
   next), states whose moving packages change (in motion), and with nothing kept (every float
   text and every sub-package text worked out anew before each line).
3. Files of MB megabytes of real robot states, raw and .pcap (tests/tools/robot_inputs.py), each
   read in its own process: decode_file, and `python -m urwire decode` writing JSON Lines to a
   pipe; MB per second of CPU time and peak resident memory. The command of --base runs on the
   smallest files too, and decode_stream over a whole buffer runs in both packages.
4. A capture whose TCP segments come in reverse order, against the same capture in order.
5. The C backend (urwire._ccore, `make python-ext`), at rest and in motion: a robot state's
   records (decode_message: framed in C, each sub-package a copy of what its bytes gave last,
   else read by Python's decoder of its form) against python-urx's decode and pure Python's,
   each state dropped as it comes (its copies are then taken back by the next read), and in
   motion with the last three states held (every copy made and freed: a caller that keeps them);
   decode_stream in a loop over states in motion, the garbage collector on, against python-urx's
   loop over the same states;
   and its canonical JSON line framed, decoded and written by the C parser, against python-urx's
   decode and pure Python's decode plus to_json_line; and `urwire decode` of the raw files under
   both backends (part 3's command column runs under the default backend, the C one where it is
   built). Parts 1 and 2 decode in pure Python whatever the backend.

Machines here are shared and noisy: each in-process figure is a range over ROUNDS rounds (each
the best of REPEAT x NUMBER calls, the contenders taking turns), and the ratios are what count.
The packages of older revisions are taken from git into build/bench-python/.
"""
from __future__ import annotations

import argparse
import collections
import contextlib
import dataclasses
import importlib.util
import itertools
import logging
import os
import random
import statistics
import struct
import subprocess
import sys
import tempfile
import time
import timeit
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python"), str(ROOT)]

import urwire  # noqa: E402
from urwire import decoding  # noqa: E402
from tests.tools import measure, robot_inputs  # noqa: E402

CONFORMANCE = ROOT / "tests" / "conformance" / "Universal_Robots_Client_Library"
SAMPLES = ["robot_state_real_robot_5.11_pr137", "robot_state_ursim5.8_ur5e_first"]
BASE = "56d4759"               # main before the per-class JSON writers and the lazy decode_stream
GENERATIONS_BASE = "27a9d98"   # the package before every controller generation entered the spec
ROUNDS, REPEAT, NUMBER = 5, 5, 100
CAPTURE_MESSAGES = 4000
MIB = 1 << 20

COUNT_FILE = "import sys, urwire; print(sum(1 for _ in urwire.decode_file(sys.argv[1])))"
COUNT_STREAM = ("import sys, urwire; data = open(sys.argv[1], 'rb').read(); "
                "print(sum(1 for _ in urwire.decode_stream(data)))")


def sample(name: str) -> bytes:
    return bytes.fromhex((CONFORMANCE / f"{name}.hex").read_text().strip())


def package_of(revision: str) -> Path | None:
    """The generated Python package of a git revision, under build/bench-python/REV/."""
    root = ROOT / "build" / "bench-python" / revision
    if not (root / "urwire" / "__init__.py").is_file():
        root.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", revision, "generated/python/urwire"],
                                 capture_output=True)
        if archive.returncode != 0:
            print(f"   (no package of {revision}: {archive.stderr.decode().strip()})")
            return None
        subprocess.run(["tar", "-x", "--strip-components=2", "-C", str(root)], input=archive.stdout, check=True)
    return root


def load(root: Path, name: str):
    """The urwire package under `root`, imported as `name` beside the current one."""
    spec = importlib.util.spec_from_file_location(name, root / "urwire" / "__init__.py",
                                                  submodule_search_locations=[str(root / "urwire")])
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def rounds(contenders: dict) -> dict:
    """CPU seconds per call of each contender in each round: the best of REPEAT runs of NUMBER
    calls, the contenders taking turns run by run so that a busy moment of the machine falls on
    all of them."""
    timers = {name: timeit.Timer(fn, timer=time.process_time) for name, fn in contenders.items()}
    seconds: dict = {name: [] for name in contenders}
    for _ in range(ROUNDS):
        best = dict.fromkeys(contenders, float("inf"))
        for _ in range(REPEAT):
            for name, timer in timers.items():
                best[name] = min(best[name], timer.timeit(NUMBER) / NUMBER)
        for name in contenders:
            seconds[name].append(best[name])
    return seconds


def spread(values: list) -> str:
    return f"{min(values):.2f}-{max(values):.2f}x"


def us(values: list) -> str:
    return f"{statistics.median(values) * 1e6:.1f}"


@contextlib.contextmanager
def pure_python():
    """decode_message reads robot states in pure Python while inside, whatever the backend."""
    saved = decoding._C_STATES
    decoding._C_STATES = None
    try:
        yield
    finally:
        decoding._C_STATES = saved


def python_decode(data: bytes):
    """Pure Python's decode_message of a robot state, with the C backend chosen or not."""
    return decoding.decode_in_python(data, None, None)


def decode_per_message(generations: Path | None) -> None:
    logging.disable(logging.CRITICAL)  # urx logs every package it skips
    from urx.ursecmon import ParserUtils

    old = load(generations, "urwire_generations_base") if generations else None
    print(f"== Decode per message: us (the median of {ROUNDS} rounds) and ratios (their range over the rounds)")
    print(f"   {'message':<36}{'bytes':>6}{'urx':>8}{'urwire':>8}{'urwire faster':>15}"
          + (f"{GENERATIONS_BASE:>9}{'its time now':>15}" if old else ""))
    for name in SAMPLES:
        data = sample(name)
        assert not urwire.canonical.has_error(urwire.decode_message(data)), name
        contenders = {"urx": lambda: ParserUtils().parse(data), "now": lambda: python_decode(data)}
        if old:
            contenders["then"] = lambda: old.decode_message(data)
        t = rounds(contenders)
        line = (f"   {name:<36}{len(data):>6}{us(t['urx']):>8}{us(t['now']):>8}"
                f"{spread([u / n for u, n in zip(t['urx'], t['now'])]):>15}")
        if old:
            line += f"{us(t['then']):>9}{spread([n / o for n, o in zip(t['now'], t['then'])]):>15}"
        print(line)
    stream = b"".join(sample(n) for n in SAMPLES) * 500
    with pure_python():
        framed = min(timeit.repeat(lambda: sum(1 for _ in urwire.decode_stream(stream)), number=1, repeat=3))
    print(f"   framer + decode over a {len(stream) / 1e6:.1f} MB stream: {len(stream) / framed / 1e6:.1f} MB/s, "
          f"{1000 / framed:,.0f} messages/s")


# What moves on a robot in motion, from one state to the next: every float of these packages.
# Limits, kinematics, calibration and configuration stay as they are.
MOVING = ("JointData", "CartesianInfo", "MasterboardData", "ToolData", "ForceModeData")
MOTION_STATES = 1000
F32 = struct.Struct(">f")


def moved(obj, rng: random.Random):
    """obj with each finite float of its members (and of its items) nudged by up to 0.1%."""
    changes = {}
    for name, kind, _ in obj.JSON:
        value = getattr(obj, name)
        if kind == "items":
            changes[name] = [moved(item, rng) for item in value]
        elif kind in ("f32", "f64", "list:f32", "list:f64") and value is not None:  # int|f32: left as is
            nudge = (lambda x: F32.unpack(F32.pack(x))[0]) if "f32" in kind else float
            new = [nudge(x + (abs(x) + 1) * rng.uniform(-1e-3, 1e-3)) if type(x) is float and x - x == 0 else x
                   for x in (value if kind.startswith("list") else [value])]
            changes[name] = new if kind.startswith("list") else new[0]
    return dataclasses.replace(obj, **changes)


def in_motion(data: bytes) -> list[bytes]:
    """MOTION_STATES copies of a robot state, each with the MOVING packages moved a little."""
    rng = random.Random(1)
    state = urwire.decode_message(data)
    out = []
    for _ in range(MOTION_STATES):
        state.packages = [moved(p, rng) if type(p).__name__ in MOVING else p for p in state.packages]
        out.append(state.encode())
    return out


def json_per_message(base: Path | None) -> None:
    """A robot at rest (the same state again), in motion, and with no text kept."""
    if base is None:
        return
    old = load(base, "urwire_base")
    def anew(record):
        urwire.canonical.forget_texts()
        return urwire.to_json_line(record)

    with pure_python():
        json_lines_against(old, anew)


def json_lines_against(old, anew) -> None:
    print(f"== A JSON line per robot state against {BASE}, the same text: us and ratios as above")
    print(f"   {'message':<36}{'robot':<10}{BASE:>9}{'now':>7}{'faster':>13}{'decode':>8}")
    for name in SAMPLES:
        data = sample(name)
        moving = in_motion(data)
        now, then = [urwire.decode_message(m) for m in moving], [old.decode_message(m) for m in moving]
        assert [urwire.to_json_line(r) for r in now] == [old.to_json_line(r) for r in then], name
        now_next, then_next = itertools.cycle(now).__next__, itertools.cycle(then).__next__
        record, first = urwire.decode_message(data), old.decode_message(data)
        t = rounds({"then at rest": lambda: old.to_json_line(first), "at rest": lambda: urwire.to_json_line(record),
                    "then in motion": lambda: old.to_json_line(then_next()),
                    "in motion": lambda: urwire.to_json_line(now_next()),
                    "nothing kept": lambda: anew(record), "decode": lambda: urwire.decode_message(data)})
        for case, before in (("at rest", "then at rest"), ("in motion", "then in motion"),
                             ("nothing kept", "then at rest")):
            print(f"   {name if case == 'at rest' else '':<36}{case:<16}{us(t[before]):>9}{us(t[case]):>7}"
                  f"{spread([o / n for o, n in zip(t[before], t[case])]):>13}"
                  f"{us(t['decode']) if case == 'at rest' else '':>8}")


def run(package: Path | str, args: list[str], expected: int, count_lines: bool,
        extra_env: dict | None = None) -> measure.Usage:
    env = dict(os.environ, PYTHONPATH=str(package), **(extra_env or {}))
    usage = measure.watch([sys.executable, *args], env)
    records = usage.lines if count_lines else int(usage.last or 0)
    assert usage.returncode == 0 and records == expected, (args, usage.returncode, records, expected)
    return usage


def files(sizes: list[int], base: Path | None) -> None:
    states = robot_inputs.real_states()
    now = os.pathsep.join(str(ROOT / part) for part in ("python", "generated/python"))
    print(f"== Files of real robot states ({len(states)} states repeated), each read in its own process:"
          " MB/s of CPU time, peak memory")
    print(f"   {'input':<16}{'decode_file':>22}{'command, JSON Lines':>26}"
          + (f"{'command of ' + BASE:>28}{'JSON speed-up':>15}" if base else ""))
    for megabytes in sizes:
        count = robot_inputs.message_count(megabytes, states)
        for form, path in (("raw", robot_inputs.raw_stream(megabytes, states)),
                           ("pcap", robot_inputs.capture(megabytes, states=states))):
            mb = path.stat().st_size / 1e6
            read = run(now, ["-c", COUNT_FILE, str(path)], count, False)
            cli = run(now, ["-m", "urwire", "decode", "--no-progress", str(path)], count, True)
            line = (f"   {f'{megabytes} MB {form}':<16}{mb / read.cpu:>9.1f} MB/s {read.peak / MIB:>5.0f} MiB"
                    f"{mb / cli.cpu:>13.1f} MB/s {cli.peak / MIB:>5.0f} MiB")
            if base and megabytes == min(sizes):
                old = run(base, ["-m", "urwire", "decode", "--no-progress", str(path)], count, True)
                line += f"{mb / old.cpu:>15.1f} MB/s {old.peak / MIB:>5.0f} MiB{old.cpu / cli.cpu:>14.2f}x"
            print(line)
    smallest = robot_inputs.raw_stream(min(sizes), states)
    count = robot_inputs.message_count(min(sizes), states)
    buffers = [("now", now)] + ([(BASE, base)] if base else [])
    shown = []
    for name, package in buffers:
        usage = run(package, ["-c", COUNT_STREAM, str(smallest)], count, False)
        shown.append(f"{name} {(usage.peak - smallest.stat().st_size) / MIB:.0f} MiB, "
                     f"{smallest.stat().st_size / 1e6 / usage.cpu:.1f} MB/s")
    print(f"   decode_stream over a {min(sizes)} MB buffer, memory beyond the buffer: {'; '.join(shown)}")


def reversed_segments() -> None:
    """One message per TCP segment, CAPTURE_MESSAGES of them, in order and then reversed."""
    from tests.tools import capture

    messages = [sample(n) for n in SAMPLES]
    # A window as large as TCP scales one (2**14 times 65,535 bytes): else segments held further
    # than the client's window would read as past a gap whose acknowledgements were lost too.
    frames = capture.robot_session([messages[i % len(messages)] for i in range(CAPTURE_MESSAGES)], window_shift=14)
    handshake, data, closing = frames[:3], frames[3:-3], frames[-3:]
    with tempfile.TemporaryDirectory() as tmp:
        in_order = capture.write(Path(tmp) / "in_order.pcap", frames)
        backwards = capture.write(Path(tmp) / "reversed.pcap", handshake + data[::-1] + closing)
        seconds = {}
        for path in (in_order, backwards):
            assert sum(1 for _ in urwire.decode_file(path)) == CAPTURE_MESSAGES, path.name
            seconds[path] = min(timeit.repeat(lambda: sum(1 for _ in urwire.decode_file(path)), number=1, repeat=3))
    print(f"== Capture of {CAPTURE_MESSAGES:,} messages: in order {seconds[in_order]:.2f} s, segments reversed "
          f"{seconds[backwards]:.2f} s ({seconds[backwards] / seconds[in_order]:.2f}x the in-order time; goal: about 1x)")


def c_backend_per_message() -> None:
    """Per robot state: python-urx's decode, pure Python's decode and JSON line, and the C
    backend's records (decode_message) and JSON line (a Python call per state: the framer fed
    one message)."""
    from urwire import backends

    logging.disable(logging.CRITICAL)
    from urx.ursecmon import ParserUtils

    if backends.backend() != "c":
        print("== C backend: not built or not chosen (make python-ext; URWIRE_BACKEND unset)")
        return
    print("== C backend per robot state: us (median of the rounds) and ratios (their range)")
    print(f"   {'message':<36}{'robot':<11}{'urx':>7}{'python':>8}{'C rec.':>8}"
          f"{'C rec. vs urx':>16}{'vs python':>13}{'py line':>9}{'C line':>8}{'C line vs urx':>16}"
          f"{'vs python':>13}")
    for name in SAMPLES:
        data = sample(name)
        moving = in_motion(data)
        for robot, states, held in (("at rest", [data], 0), ("in motion", moving, 0), ("3 held", moving, 3)):
            lines = backends._CCORE.PrimaryJsonLines(None)
            nexts = {who: itertools.cycle(states).__next__ for who in ("python", "c", "py line", "c line")}
            keep = collections.deque(maxlen=held).append
            assert lines.feed(data) == (urwire.to_json_line(python_decode(data)) + "\n").encode(), name
            assert all(urwire.decode_message(m) == python_decode(m) for m in states[:50]), name
            t = rounds({"urx": lambda: ParserUtils().parse(data),
                        "python": lambda: python_decode(nexts["python"]()),
                        "c": lambda: keep(urwire.decode_message(nexts["c"]())),
                        "py line": lambda: urwire.to_json_line(python_decode(nexts["py line"]())),
                        "c line": lambda: lines.feed(nexts["c line"]())})
            print(f"   {name if robot == 'at rest' else '':<36}{robot:<11}{us(t['urx']):>7}{us(t['python']):>8}"
                  f"{us(t['c']):>8}{spread([u / c for u, c in zip(t['urx'], t['c'])]):>16}"
                  f"{spread([p / c for p, c in zip(t['python'], t['c'])]):>13}"
                  f"{us(t['py line']):>9}{us(t['c line']):>8}"
                  f"{spread([u / c for u, c in zip(t['urx'], t['c line'])]):>16}"
                  f"{spread([p / c for p, c in zip(t['py line'], t['c line'])]):>13}")


def c_backend_stream() -> None:
    """A program's loop: decode_stream over a feed of MOTION_STATES real states in motion, each
    record dropped as the loop goes on, against python-urx parsing the same states in a loop; and
    list(decode_stream(...)), which holds every record. CPU seconds per state, the best of
    ROUNDS x REPEAT runs taking turns, with the garbage collector on as in a program (timeit
    turns it off for the per-state figures above)."""
    from urwire import backends
    from urx.ursecmon import ParserUtils

    if backends.backend() != "c":
        return
    moving = in_motion(sample(SAMPLES[0]))
    stream = b"".join(moving)

    def loop():
        for _ in urwire.decode_stream(stream):
            pass

    def urx():
        for state in moving:
            ParserUtils().parse(state)

    contenders = {"decode_stream": loop, "urx": urx, "list": lambda: list(urwire.decode_stream(stream))}
    best = dict.fromkeys(contenders, float("inf"))
    for _ in range(ROUNDS * REPEAT):
        for name, run_once in contenders.items():
            start = time.process_time()
            run_once()
            best[name] = min(best[name], (time.process_time() - start) / len(moving))
    print(f"== C backend in a loop, {SAMPLES[0]} in motion, {len(moving):,} states, the collector on: "
          f"decode_stream {best['decode_stream'] * 1e6:.1f} us a state against urx's {best['urx'] * 1e6:.1f} "
          f"({best['urx'] / best['decode_stream']:.1f}x); list(decode_stream) {best['list'] * 1e6:.1f} us "
          f"({best['urx'] / best['list']:.1f}x)")


def c_backend_files(sizes: list[int]) -> None:
    """`urwire decode` of a raw file of real robot states under each backend, in its own process."""
    states = robot_inputs.real_states()
    now = os.pathsep.join(str(ROOT / part) for part in ("python", "generated/python"))
    print("== urwire decode of raw robot states under each backend: MB/s of CPU time, peak memory")
    for megabytes in sizes:
        count = robot_inputs.message_count(megabytes, states)
        path = robot_inputs.raw_stream(megabytes, states)
        mb = path.stat().st_size / 1e6
        usage = {backend: run(now, ["-m", "urwire", "decode", "--no-progress", str(path)], count, True,
                              {"URWIRE_BACKEND": backend}) for backend in ("python", "c")}
        print(f"   {f'{megabytes} MB raw':<16}" + "".join(
            f"{backend:>8} {mb / u.cpu:>7.1f} MB/s {u.peak / MIB:>4.0f} MiB" for backend, u in usage.items())
            + f"   C {usage['python'].cpu / usage['c'].cpu:.1f}x faster")


def main(argv: list[str]) -> int:
    global BASE, GENERATIONS_BASE
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default=BASE)
    parser.add_argument("--generations-base", default=GENERATIONS_BASE)
    parser.add_argument("sizes", nargs="*", type=int, default=[10, 100])
    parser.add_argument("--only-c", action="store_true", help="part 5 only (the C backend)")
    args = parser.parse_args(argv)
    if args.only_c:
        c_backend_per_message()
        c_backend_stream()
        c_backend_files(sorted(args.sizes))
        return 0
    BASE, GENERATIONS_BASE = args.base, args.generations_base
    base, generations = package_of(BASE), package_of(GENERATIONS_BASE)
    decode_per_message(generations)
    json_per_message(base)
    files(sorted(args.sizes), base)
    reversed_segments()
    c_backend_per_message()
    c_backend_stream()
    c_backend_files(sorted(args.sizes))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
