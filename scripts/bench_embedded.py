"""`make bench-embedded`: what the C parser costs on microcontrollers, measured into
examples/embedded/measurements.json and rendered into docs/c.md's budget table.

    python3 scripts/bench_embedded.py measure [--pinned DIR] [--subset-selection TEXT]
    python3 scripts/bench_embedded.py render       # docs/c.md's table from the measurements

For each target (Cortex-M0+, Cortex-M4F and Cortex-M7 with arm-none-eabi-gcc and newlib-nano,
RV32IMC with riscv64-unknown-elf-gcc and picolibc) and level (-Os, -O2):

- every interface's parser, generated/c/<interface>.c compiled alone with -ffunction-sections
  -fdata-sections: flash (the sections a device keeps in flash: code, constants and the initial
  values of data) and static RAM (data and bss), and the worst-case stack of each public entry
  point (embedded_stack.py, over the call graph gcc writes with -fcallgraph-info=su);
- the firmwares of examples/embedded, linked whole with -Wl,--gc-sections against the C
  library, with the device's own startup code (examples/embedded/startup.c: vector table and
  reset, no C library start code: -nostartfiles) and memory map (firmware.ld): flash, RAM (the
  linker script's .stack reservation left out) and the stack of main.

The warnings are the project's (C_STRICT), without -Werror: a warning does not change a size, and
the cross builds that fail on one are make cross-c's. The measurement records the SHA-256 of
every file it read from generated/c and examples/embedded, so that a test sees when the table is
older than the code (tests/c/test_embedded.py).
"""
from __future__ import annotations

import argparse
import concurrent.futures
import hashlib
import json
import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

from embedded_stack import CallGraph, Recursion, Unbounded  # noqa: E402
from embedded_table import DOC, FIRMWARE_OPTIONS, replace_table, render  # noqa: E402

GENERATED = ROOT / "generated" / "c"
EXAMPLES = ROOT / "examples" / "embedded"
MEASUREMENTS = EXAMPLES / "measurements.json"
STRICT = ["-std=c99", "-Wall", "-Wextra", "-pedantic", "-Wconversion", "-Wshadow"]
SECTIONS = ["-ffunction-sections", "-fdata-sections", "-fstack-usage", "-fcallgraph-info=su"]
LEVELS = ["-Os", "-O2"]
RESERVED = {".stack"}                # firmware.ld's reservation, not the program's RAM


@dataclass(frozen=True)
class Target:
    name: str
    prefix: str                      # the toolchain's: arm-none-eabi-
    flags: tuple[str, ...]           # compiling and linking
    libc: tuple[str, ...]            # the C library's specs

    def tool(self, name: str) -> str:
        return self.prefix + name


# newlib-nano's functions; no system calls (nosys): nothing the firmwares link makes one.
ARM_LIBC = ("--specs=nano.specs",)
TARGETS = [
    Target("Cortex-M0+", "arm-none-eabi-", ("-mthumb", "-mcpu=cortex-m0plus", "-mfloat-abi=soft"), ARM_LIBC),
    Target("Cortex-M4F", "arm-none-eabi-", ("-mthumb", "-mcpu=cortex-m4", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard"),
           ARM_LIBC),
    Target("Cortex-M7", "arm-none-eabi-", ("-mthumb", "-mcpu=cortex-m7", "-mfpu=fpv5-d16", "-mfloat-abi=hard"),
           ARM_LIBC),
    # picolibc has no rv32imc library: gcc links its rv32im one, the firmware's own code is rv32imc.
    Target("RV32IMC", "riscv64-unknown-elf-", ("-march=rv32imc", "-mabi=ilp32"), ("--specs=picolibc.specs",)),
]
# How every firmware is linked: the device's start (startup.c, a source of every firmware) in
# place of the C library's, and the memory map it starts from.
FIRMWARE_LINK = ("-nostartfiles", "-T", str(EXAMPLES / "firmware.ld"), "-Wl,--gc-sections")

# What the RTDE firmware's connection keeps: its one recipe (and the robot's reply's), its names.
RTDE_FIRMWARE_LIMITS = ("-DRTDE_MAX_RECIPES=2", "-DRTDE_MAX_VARIABLES=8", "-DRTDE_MAX_NAMES=64")


@dataclass(frozen=True)
class Firmware:
    key: str
    sources: tuple[str, ...]         # in examples/embedded, beside the board's
    library: str                     # the interface's .c, in `include`
    include: str                     # "generated", "pinned" or "subset": where its parser is
    defines: tuple[str, ...] = ()


FIRMWARES = [
    Firmware("robot_states", ("robot_states.c", "primary_stream.c"), "urwire.c", "generated", FIRMWARE_OPTIONS),
    Firmware("robot_states_pinned", ("robot_states.c", "primary_stream.c"), "urwire.c", "pinned", FIRMWARE_OPTIONS),
    Firmware("rtde_values", ("rtde_values.c",), "rtde.c", "generated", RTDE_FIRMWARE_LIMITS),
    Firmware("joint_and_tool_subset", ("joint_and_tool.c", "primary_stream.c"), "urwire.c", "subset",
             FIRMWARE_OPTIONS),
    # (1) and (2) as the tests build them, without the options: what the options save
    Firmware("robot_states_default", ("robot_states.c", "primary_stream.c"), "urwire.c", "generated"),
    Firmware("robot_states_pinned_default", ("robot_states.c", "primary_stream.c"), "urwire.c", "pinned"),
]


def run(*cmd: str) -> str:
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}\n{done.stderr.strip()}")
    return done.stdout


def version_of(compiler: str) -> str:
    return run(compiler, "-dumpfullversion").strip() + " (" + run(compiler, "--version").splitlines()[0] + ")"


def footprint(target: Target, path: Path) -> dict:
    """Flash and static RAM of an object or an ELF, from its section headers: flash holds every
    allocated section with contents (the initial values of data too), RAM every writable one."""
    flash = ram = 0
    for line in run(target.tool("readelf"), "-SW", str(path)).splitlines():
        if "]" not in line or line.lstrip().startswith("[Nr]"):
            continue
        fields = line.split("]", 1)[1].split()
        if len(fields) < 7:
            continue
        name, kind, size, flags = fields[0], fields[1], int(fields[4], 16), fields[6]
        if "A" not in flags or name in RESERVED:
            continue
        if kind != "NOBITS":
            flash += size
        if "W" in flags:
            ram += size
    return {"flash": flash, "ram": ram}


def compile_c(target: Target, level: str, source: Path, out: Path, includes: list[Path],
              defines: tuple[str, ...] = ()) -> Path:
    out.parent.mkdir(parents=True, exist_ok=True)
    run(target.tool("gcc"), *target.flags, *target.libc, *STRICT, level, *SECTIONS, *defines,
        *(f"-I{d}" for d in includes), "-c", str(source), "-o", str(out))
    return out


def graph_of(target: Target, objects: list[Path]) -> CallGraph:
    graph = CallGraph()
    for obj in objects:
        graph.add_ci(obj.with_suffix(".ci"))
        graph.add_relocations(target.tool("readelf"), obj)
    return graph


def public_functions(target: Target, obj: Path) -> list[str]:
    return sorted(line.split()[2] for line in run(target.tool("nm"), "-g", "--defined-only", str(obj)).splitlines()
                  if line.split()[1] == "T")


def stack_of(graph: CallGraph, root: str) -> tuple[int | str, list[str]]:
    """The stack root needs at most and the path that needs it, or, where no bound exists
    (recursion, a frame of dynamic size), why: the figure is refused, named in the table, and
    the command fails."""
    try:
        return graph.deepest(root)
    except (Recursion, Unbounded) as exc:
        return f"no bound: {type(exc).__name__.lower()} {exc}", []


def refusals(m: dict) -> list[str]:
    """Every entry point (and firmware's main) whose stack has no bound, once each."""
    found = set()
    for by_target in m["parsers"].values():
        for levels in by_target.values():
            for name, figures in levels.items():
                found |= {f"{entry} ({name}.c): {why}" for entry, why in figures["stack"].items()
                          if isinstance(why, str)}
    for key, by_target in m["firmwares"].items():
        found |= {f"main of {key}: {f['stack']}" for levels in by_target.values() for f in levels.values()
                  if isinstance(f.get("stack"), str)}
    return sorted(found)


def measure_parser(target: Target, level: str, source: Path, work: Path) -> dict:
    obj = compile_c(target, level, source, work / f"{source.stem}.o", [GENERATED])
    graph = graph_of(target, [obj])
    stacks = {name: stack_of(graph, name)[0] for name in public_functions(target, obj)}
    return {**footprint(target, obj), "stack": stacks, "outside": sorted(graph.unknown)}


def measure_firmware(target: Target, level: str, firmware: Firmware, parsers: dict[str, Path], work: Path) -> dict:
    include = parsers.get(firmware.include)
    if include is None:
        return {"skipped": SKIPPED[firmware.include]}
    sources = [*(EXAMPLES / s for s in firmware.sources), EXAMPLES / "board_target.c", EXAMPLES / "startup.c",
               include / firmware.library]
    try:
        objects = [compile_c(target, level, src, work / f"{firmware.key}-{src.stem}.o", [include, EXAMPLES],
                             firmware.defines) for src in sources]
    except RuntimeError as exc:
        return {"skipped": "does not build: " + first_error(str(exc))}
    elf = work / f"{firmware.key}.elf"
    try:
        run(target.tool("gcc"), *target.flags, *target.libc, level, *FIRMWARE_LINK, *map(str, objects), "-o", str(elf))
    except RuntimeError as exc:
        return {"skipped": "does not link: " + first_error(str(exc))}
    graph = graph_of(target, objects)
    stack, path = stack_of(graph, "main")
    return {**footprint(target, elf), "stack": stack, "stack_path": path, "outside": sorted(graph.unknown)}


def first_error(text: str) -> str:
    errors = [line for line in text.splitlines() if "error" in line]
    return (errors[0] if errors else text.splitlines()[-1]).replace(str(ROOT) + "/", "")


SKIPPED = {"pinned": "no pinned build given (make bench-embedded builds one: make pinned-c)",
           "subset": "no subset build: `python -m codegen` takes no selection of messages and sub-packages yet "
                     "(issue 38, point 4)"}


def subset_build(selection: str, out: Path) -> Path | None:
    """The parser of `selection` alone, when the generator takes a selection (--select)."""
    if "--select" not in run(sys.executable, "-m", "codegen", "--help"):
        return None
    try:
        run(sys.executable, "-m", "codegen", "--select", selection, "--target", "c", "--out", str(out))
    except RuntimeError as exc:
        SKIPPED["subset"] = "the subset build failed: " + first_error(str(exc))
        return None
    return out / "c"


def digests() -> dict[str, str]:
    """The SHA-256 of every file the measurement reads from generated/c and examples/embedded."""
    files = sorted([*GENERATED.glob("*.[ch]"), *EXAMPLES.glob("*.[ch]"), *EXAMPLES.glob("*.ld")])
    return {str(p.relative_to(ROOT)): hashlib.sha256(p.read_bytes()).hexdigest() for p in files}


def measure(pinned: Path | None, selection: str, jobs: int) -> dict:
    parsers = {"generated": GENERATED}
    if pinned is not None:
        parsers["pinned"] = pinned
    with tempfile.TemporaryDirectory(prefix="bench-embedded-") as tmp:
        work = Path(tmp)
        subset = subset_build(selection, work / "subset")
        if subset is not None:
            parsers["subset"] = subset
        tasks = {}
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            for target in TARGETS:
                for level in LEVELS:
                    place = work / target.name.replace("+", "p") / level.lstrip("-")
                    for source in sorted(GENERATED.glob("*.c")):
                        tasks[("parsers", target.name, level, source.stem)] = pool.submit(
                            measure_parser, target, level, source, place / "parsers")
                    for firmware in FIRMWARES:
                        tasks[("firmwares", firmware.key, target.name, level)] = pool.submit(
                            measure_firmware, target, level, firmware, parsers, place / "firmwares")
        result: dict = {"toolchains": {t.prefix + "gcc": version_of(t.tool("gcc")) for t in TARGETS},
                        "pinned": str(pinned.relative_to(ROOT)) if pinned and pinned.is_relative_to(ROOT) else None,
                        "subset_selection": selection, "inputs": digests(), "parsers": {}, "firmwares": {}}
        for (kind, a, b, c), task in tasks.items():
            result[kind].setdefault(a, {}).setdefault(b, {})[c] = task.result()
    return result


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="bench_embedded.py", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    m = sub.add_parser("measure", help="measure, write examples/embedded/measurements.json and the doc's table")
    m.add_argument("--pinned", type=Path, help="the folder of a pinned build's urwire.{h,c} (make pinned-c)")
    m.add_argument("--subset-selection", default="ur:robot_state.joint_data,robot_state.tool_data",
                   help="what the subset firmware's parser holds, as `python -m codegen --select` takes it")
    m.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1))
    sub.add_parser("render", help="write docs/c.md's table from examples/embedded/measurements.json")
    args = parser.parse_args(argv)
    if args.command == "measure":
        pinned = args.pinned.resolve() if args.pinned else None
        MEASUREMENTS.write_text(json.dumps(measure(pinned, args.subset_selection, args.jobs), indent=1,
                                           sort_keys=True) + "\n")
    m = json.loads(MEASUREMENTS.read_text())
    DOC.write_text(replace_table(DOC.read_text(), render(m)))
    for refused in refusals(m):
        print(f"bench-embedded: no stack bound for {refused}", file=sys.stderr)
    return 1 if refusals(m) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
