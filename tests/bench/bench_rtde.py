"""make bench-rtde: RTDE (30004) data packages per second, by recipe.

One RTDE protocol 2 connection at 500 Hz with the recipe a driver asks for
(tests/tools/rtde_inputs.py: timestamp, actual_q, actual_qd, actual_current, actual_TCP_pose,
actual_TCP_speed, robot_mode, safety_mode, runtime_state; 264-byte packages), its values moving
as a robot's do. Each figure is CPU time,
the best of a few rounds, and a ratio against a baseline measured in the same run:

- Python: `urwire.rtde.Conversation` fed the robot's stream a megabyte at a time, every package
  decoded into its values by name, against the least any Python reader does (each package's
  header and values read with the recipe's precompiled `struct`, nothing else) and against the
  package of --base (default: the tree before recipes read by a precompiled reader); then with a
  canonical JSON line per package, against decoding alone and the package of --base.
- Python, one package hot: the C bench's 12-variable, 284-byte package (bench_rtde_hot.c)
  decoded by DataPackage.decode_body again and again and all 12 values read, by index
  (`in_order()`) and by name, against a hand-written reader of the same layout (one
  `struct.unpack_from`, the vectors sliced out) and against the package of --base; taking turns.
- C: `rtde_decode` with a caller-owned conversation, every value of every package read
  (tests/bench/bench_rtde.c), against memcpy of the same bytes read the same way; and against
  Python's rate.
- Both at PACKAGES and at LARGE packages (a robot-day at 500 Hz is 43 million): the cost per
  package at LARGE against PACKAGES shows whether it stays flat.
- Wireshark: tshark with generated/lua/rtde.lua on a capture of PACKAGES packages (one per TCP
  segment, as a robot sends them), against the same tshark with `--disable-protocol rtde` and
  with the rtde.lua of --base, taking turns: no tree (`-q -z io,stat,0`), one field (`-T fields -e
  rtde.actual_q`), the full tree (`-V`).

The inputs are built under build/bench-rtde (not committed). `--packages N --large M` set the
sizes; small ones give a quick look (the machine may be shared: run the full sizes alone).
"""
from __future__ import annotations

import argparse
import importlib.util
import resource
import shutil
import struct
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT), str(ROOT / "python"), str(ROOT / "generated" / "python")]
from tests.tools import capture, measure  # noqa: E402
from tests.tools.revision_package import unpack_package  # noqa: E402
from tests.tools.rtde_inputs import (HZ, PACKAGE_SIZE, RECIPE, client_bytes, packages, robot_head,  # noqa: E402
                                     values_struct)

OUT = ROOT / "build" / "bench-rtde"
PLUGIN = ROOT / "generated" / "lua" / "rtde.lua"
C_BENCH = ROOT / "build" / "bench_rtde"
CHUNK = 1 << 20
ROUNDS = 3
BASE = "4a2a41d"        # before recipes read their values by a precompiled reader and names by index

# The C hot bench's package (tests/bench/bench_rtde_hot.c): 12 variables, 284 bytes with its header.
HOT_NAMES = ["timestamp", "actual_q", "actual_qd", "actual_TCP_pose", "actual_TCP_force", "robot_mode", "safety_mode",
             "runtime_state", "actual_digital_input_bits", "speed_scaling", "output_int_register_0",
             "joint_temperatures"]
HOT_TYPES = ["DOUBLE", "VECTOR6D", "VECTOR6D", "VECTOR6D", "VECTOR6D", "INT32", "INT32", "UINT32", "UINT64", "DOUBLE",
             "INT32", "VECTOR6D"]
HOT_LAYOUT = struct.Struct(">HBB d6d6d6d6d iiIQdi 6d")
HOT_CALLS = 20_000


def write_robot(path: Path, count: int) -> Path:
    if not path.exists():
        with open(path.with_suffix(".tmp"), "wb") as fh:
            fh.write(robot_head())
            batch = []
            for pkg in packages(count):
                batch.append(pkg)
                if len(batch) == 4096:
                    fh.write(b"".join(batch))
                    batch.clear()
            fh.write(b"".join(batch))
        path.with_suffix(".tmp").rename(path)
    return path


def cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def in_turns(contenders: dict, rounds: int = ROUNDS) -> dict:
    """Each contender's (least CPU seconds, what it counted), the contenders taking turns round by
    round so that a busy stretch of the machine falls on all of them."""
    found = {name: (float("inf"), 0) for name in contenders}
    for _ in range(rounds):
        for name, work in contenders.items():
            start = cpu()
            counted = work()
            found[name] = (min(found[name][0], cpu() - start), counted)
    return found


def chunks(path: Path):
    with open(path, "rb") as fh:
        while data := fh.read(CHUNK):
            yield data


def package_of(revision: str):
    """The urwire package of a revision (hand-written and generated parts), imported as
    urwire_REV beside this tree's, with this tree's C extension where ext/ccore is unchanged."""
    root = OUT / "base" / revision
    if not (root / "urwire" / "generated" / "__init__.py").is_file():
        unpack_package(revision, root)
        if subprocess.run(["git", "-C", str(ROOT), "diff", "--quiet", revision, "--", "ext/ccore"]).returncode == 0:
            for built in (ROOT / "python" / "urwire").glob("_ccore*.so"):
                shutil.copy(built, root / "urwire")
    name = "urwire_" + revision
    found = importlib.util.spec_from_file_location(name, root / "urwire" / "__init__.py",
                                                   submodule_search_locations=[str(root / "urwire")])
    module = importlib.util.module_from_spec(found)
    sys.modules[name] = module
    found.loader.exec_module(module)
    importlib.import_module(name + ".rtde")
    return module


def urwire_decode(path: Path, json_lines: bool = False, package=None) -> int:
    """Every message of the robot's stream through a Conversation (of `package`, else this
    tree's); the data packages counted."""
    import urwire

    package = package or urwire
    to_json_line = package.to_json_line
    rtde, spec = package.rtde, package.generated.rtde
    conv = rtde.Conversation()
    conv.feed(client_bytes(), False)
    count = 0
    for data in chunks(path):
        for record in conv.feed(data, True):
            if type(record) is spec.DataPackage:
                count += 1
                if json_lines:
                    to_json_line(record)
    if count == 0:
        sys.exit("bench_rtde: no data package decoded")
    return count


def struct_floor(path: Path) -> int:
    """The baseline: each message's header, and a data package's values with the recipe's struct."""
    head, body = struct.Struct(">HB"), values_struct()
    count, held = 0, b""
    for data in chunks(path):
        buf, pos = held + data, 0
        while len(buf) - pos >= 3:
            size, code = head.unpack_from(buf, pos)
            if len(buf) - pos < size:
                break
            if code == 85:
                body.unpack_from(buf, pos + 4)
                count += 1
            pos += size
        held = buf[pos:]
    return count


def python_figures(path: Path, count: int, with_json: bool, base) -> float:
    """Prints Python's rates; returns its seconds per package."""
    contenders = {"ours": lambda: urwire_decode(path), "floor": lambda: struct_floor(path)}
    if base is not None:
        contenders["before"] = lambda: urwire_decode(path, package=base)
    if with_json:
        contenders["lines"] = lambda: urwire_decode(path, json_lines=True)
        if base is not None:
            contenders["lines before"] = lambda: urwire_decode(path, json_lines=True, package=base)
    found = in_turns(contenders)
    assert all(n == count for _, n in found.values()), (found, count)
    ours, floor = found["ours"][0], found["floor"][0]
    print(f"  Python Conversation             {count / ours:12,.0f} packages/s  {ours / floor:5.2f}x the time of "
          f"struct alone ({count / floor:,.0f}/s)")
    if base is not None:
        before = found["before"][0]
        print(f"  Python Conversation at {base.__name__[7:]:8s} {count / before:12,.0f} packages/s  "
              f"{before / ours:5.2f}x the time of this tree's")
    if with_json:
        lines = found["lines"][0]
        print(f"  Python decode + JSON line       {count / lines:12,.0f} packages/s  {lines / ours:5.2f}x the time "
              "of decoding")
        if base is not None:
            before = found["lines before"][0]
            print(f"  Python decode + JSON at {base.__name__[7:]:7s} {count / before:12,.0f} packages/s  "
                  f"{before / lines:5.2f}x the time of this tree's")
    return ours / count


def hot_package() -> bytes:
    """One package of the hot recipe, each value distinct."""
    return HOT_LAYOUT.pack(HOT_LAYOUT.size, 85, 1, 12.5, *map(float, range(24)), 7, 1, 2, 0x80000000000000ff, 1.0, -5,
                           *map(float, range(24, 30)))


def hot_readers(package) -> dict:
    """The contestants over one package of the hot recipe: each decodes it and reads all 12
    values, and returns what it read (the same for every one, or the bench fails)."""
    spec = package.generated.rtde
    recipe = package.rtde.Recipe(1, "outputs", HOT_NAMES, HOT_TYPES, spec.VALUE_TYPES)
    raw = hot_package()
    decode, end = spec.DataPackage.decode_body, len(raw)
    names = tuple(HOT_NAMES)

    def by_index():
        values = decode(raw, 3, end, recipe).values.in_order()
        return [values[i] for i in range(12)]

    def by_name():
        values = decode(raw, 3, end, recipe).values
        return [values[name] for name in names]

    return {"index": by_index, "name": by_name}


def hand_reader() -> dict:
    """The hand-written reader of the hot layout: a size check, one unpack_from, the vectors
    sliced out as lists."""
    package, size, unpack = hot_package(), HOT_LAYOUT.size, HOT_LAYOUT.unpack_from

    def hand():
        if len(package) < size:
            raise ValueError("short package")
        f = unpack(package)
        return [f[3], [*f[4:10]], [*f[10:16]], [*f[16:22]], [*f[22:28]], f[28], f[29], f[30], f[31], f[32], f[33],
                [*f[34:40]]]

    return {"hand": hand}


def hot_figures(base) -> None:
    import urwire

    contenders = {**hot_readers(urwire), **hand_reader()}
    if base is not None:
        contenders.update({f"{name} at {base.__name__[7:]}": fn for name, fn in hot_readers(base).items()})
    expected = contenders["hand"]()
    for name, fn in contenders.items():
        assert fn() == expected, (name, fn(), expected)
    times = dict.fromkeys(contenders, float("inf"))
    for _ in range(5):                                  # turns, so that a busy moment falls on all
        for name, fn in contenders.items():
            start = cpu()
            for _ in range(HOT_CALLS):
                fn()
            times[name] = min(times[name], (cpu() - start) / HOT_CALLS)
    print(f" Python, one {HOT_LAYOUT.size}-byte package hot ({len(HOT_NAMES)} variables, decode and read all), "
          f"best of 5 turns of {HOT_CALLS:,}")
    for name, seconds in times.items():
        against = f"{seconds / times['hand']:5.2f}x hand"
        before = times.get(f"{name} at {base.__name__[7:]}") if base is not None else None
        if before:
            against += f", {before / seconds:5.2f}x faster than at {base.__name__[7:]}"
        print(f"  {name:16s} {seconds * 1e9:8.0f} ns/package  {against}")


def c_figures(path: Path, count: int, python_per_package: float) -> float:
    """Prints C's rates; returns its seconds per package."""
    client = OUT / "client.bin"
    client.write_bytes(client_bytes())
    res = subprocess.run([str(C_BENCH), str(client), str(path), str(ROUNDS)], capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"bench_rtde failed: {res.stderr[:500]}")
    n, decode, copy = res.stdout.split()
    assert int(n) == count, (n, count)
    decode, copy = float(decode), float(copy)
    print(f"  C rtde_decode                   {count / decode:12,.0f} packages/s  {decode / copy:5.2f}x the time of "
          f"memcpy, {python_per_package * count / decode:5.1f}x Python's rate")
    return decode / count


def lua_of(revision: str) -> Path:
    """generated/lua/rtde.lua of a revision, under build/bench-rtde/base/REV/."""
    path = OUT / "base" / revision / "rtde.lua"
    if not path.is_file():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(subprocess.run(["git", "-C", str(ROOT), "show", f"{revision}:generated/lua/rtde.lua"],
                                        capture_output=True, check=True).stdout)
    return path


def tshark_figures(count: int, base: str) -> None:
    pieces = [client_bytes(), robot_head(), *packages(count)]
    segments = [capture.Segment(False, pieces[0]), capture.Segment(True, pieces[1]),
                *(capture.Segment(True, p) for p in pieces[2:])]
    pcap = capture.write(OUT / f"rtde_{count}.pcap", capture.session_frames(segments, port=30004), step=0.001)
    plugins = {"rtde": PLUGIN, **({"at " + base: lua_of(base)} if base else {})}

    def run(plugin: Path, args) -> float:
        res, _, seconds, _ = measure.run_cpu(["tshark", "-r", str(pcap), "-X", f"lua_script:{plugin}", *args],
                                             output=False)
        if res.returncode != 0 or "Lua: Error" in res.stderr:
            sys.exit(f"tshark failed: {res.stderr[:500]}")
        return seconds

    heads = "".join(f" {name:>12s}" for name in plugins)
    print(f"  tshark, {count:,} packages     {heads} {'disabled':>9s} {'ratio':>6s}"
          + (f" {'base/now':>8s}" if base else ""))
    for name, args in (("no tree (-q -z io,stat,0)", ["-q", "-z", "io,stat,0"]),
                       ("one field (-T fields)", ["-T", "fields", "-e", "rtde.actual_q"]),
                       ("full tree (-V)", ["-V"])):
        times = {key: float("inf") for key in [*plugins, "disabled"]}
        for _ in range(ROUNDS):                        # turns, so that a busy moment falls on all
            for key, plugin in plugins.items():
                times[key] = min(times[key], run(plugin, args))
            times["disabled"] = min(times["disabled"], run(PLUGIN, ["--disable-protocol", "rtde", *args]))
        cells = "".join(f" {times[key]:10.2f} s" for key in plugins)
        print(f"  {name:28s}{cells} {times['disabled']:7.2f} s {times['rtde'] / times['disabled']:6.2f}"
              + (f" {times['at ' + base] / times['rtde']:8.2f}" if base else ""))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--packages", type=int, default=30_000, help="the small size, and tshark's (default 30,000)")
    parser.add_argument("--large", type=int, default=1_000_000, help="the large size (default 1,000,000)")
    parser.add_argument("--base", default=BASE, help=f"the revision whose Python to compare (default {BASE}; "
                        "'' for none)")
    args = parser.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    base = package_of(args.base) if args.base else None
    print(f"RTDE: {len(RECIPE)}-variable recipe at {HZ:.0f} Hz ({PACKAGE_SIZE}-byte packages), best of {ROUNDS}, "
          "CPU time "
          f"({time.strftime('%Y-%m-%d')})")
    per_package = {}
    for count in (args.packages, args.large):
        path = write_robot(OUT / f"robot_{count}.bin", count)
        print(f" {count:,} packages ({path.stat().st_size / 1e6:,.0f} MB)")
        py = python_figures(path, count, with_json=count == args.packages, base=base)
        c = c_figures(path, count, py) if C_BENCH.exists() else None
        per_package[count] = (py, c)
    (py_small, c_small), (py_large, c_large) = per_package[args.packages], per_package[args.large]
    print(f" per package at {args.large:,} against {args.packages:,}: Python {py_large / py_small:.2f}x"
          + (f", C {c_large / c_small:.2f}x" if c_small else " (build/bench_rtde missing: make bench-rtde builds it)"))
    hot_figures(base)
    tshark_figures(args.packages, args.base)
    return 0


if __name__ == "__main__":
    sys.exit(main())
