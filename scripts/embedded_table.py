"""docs/c.md's budget table, rendered from the measurements of scripts/bench_embedded.py: the
issue's goals with a pass/over mark, then every figure. Written between two marker comments; the
rest of the document is left as it is."""
from __future__ import annotations

import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "c.md"
BEGIN = ("<!-- bench-embedded: begin. Written by `make bench-embedded` (scripts/bench_embedded.py) from "
         "examples/embedded/measurements.json: do not edit by hand. -->")
END = "<!-- bench-embedded: end -->"
GOAL_TARGET, GOAL_LEVEL = "Cortex-M4F", "-Os"

FIRMWARE_TITLES = {
    "robot_states": "(1) frames the primary stream, reads every robot-state sub-package, every software version",
    "robot_states_pinned": "(2) the same, pinned to one version (`make pinned-c`)",
    "rtde_values": "(3) RTDE: data packages of a recipe, values by index and by name",
    "joint_and_tool_subset": "(4) joint data and tool data alone, from a subset build",
    "robot_states_default": "(1) without the size options",
    "robot_states_pinned_default": "(2) without the size options",
}
# The compile-time options the primary stream's firmwares are built with (docs/c.md, "Options for a
# firmware"): no field names in errors, no robot-state fast path.
FIRMWARE_OPTIONS = ("-DURWIRE_NO_NAMES", "-DURWIRE_NO_FAST_PATHS")
# (firmware, figure, goal in bytes, what the goal says)
GOALS = [
    ("robot_states", "flash", 32 * 1024, "firmware (1) flash"),
    ("robot_states_pinned", "flash", 16 * 1024, "firmware (2) flash"),
    ("robot_states", "ram", 8 * 1024, "firmware (1) RAM, with a framer buffer of 4 KiB"),
    ("robot_states", "stack", 512, "firmware (1) stack"),
    ("rtde_values", "flash", 16 * 1024, "firmware (3) RTDE flash, its variable table included"),
    ("joint_and_tool_subset", "flash", 6 * 1024, "firmware (4) subset flash"),
]


def number(n: int) -> str:
    return f"{n:,}"


def bytes_or_refusal(figure: int | str) -> str:
    """A figure, or "no bound" where the stack has none (the measurement says why)."""
    return number(figure) if isinstance(figure, int) else "no bound"


def worst(stacks: dict[str, int | str]) -> str:
    """The entry point with the deepest stack; one with no bound first."""
    return max(stacks, key=lambda entry: (isinstance(stacks[entry], str), stacks[entry] if isinstance(
        stacks[entry], int) else 0, entry)) if stacks else ""


def cell(figures: dict) -> str:
    if "skipped" in figures:
        return "not built"
    stack = figures["stack"]
    if isinstance(stack, dict):
        stack = stack[worst(stack)] if stack else 0
    return f"{number(figures['flash'])} / {number(figures['ram'])} / {bytes_or_refusal(stack)}"


def _goals(m: dict) -> list[str]:
    rows = ["| goal (Cortex-M4F, `-Os`) | at most | today | |", "|---|---|---|---|"]
    for key, figure, limit, what in GOALS:
        found = m["firmwares"][key][GOAL_TARGET][GOAL_LEVEL]
        if "skipped" in found:
            rows.append(f"| {what} | {number(limit)} | not built: {found['skipped']} | - |")
            continue
        value = found[figure]
        mark = "pass" if isinstance(value, int) and value <= limit else "over"
        rows.append(f"| {what} | {number(limit)} | {bytes_or_refusal(value)} | {mark} |")
    return rows


def _firmwares(m: dict, targets: list[str]) -> list[str]:
    rows = ["| firmware | level | " + " | ".join(targets) + " |", "|---|---|" + "---|" * len(targets)]
    for key, title in FIRMWARE_TITLES.items():
        for level, by_target in sorted(_levels(m["firmwares"][key]).items()):
            rows.append(f"| {title} | `{level}` | " + " | ".join(cell(by_target[t]) for t in targets) + " |")
    return rows


def _levels(by_target: dict) -> dict[str, dict]:
    out: dict[str, dict] = {}
    for target, levels in by_target.items():
        for level, figures in levels.items():
            out.setdefault(level, {})[target] = figures
    return out


def _parsers(m: dict, targets: list[str], level: str) -> list[str]:
    rows = ["| interface | " + " | ".join(targets) + " | deepest entry point |",
            "|---|" + "---|" * (len(targets) + 1)]
    for name in sorted(m["parsers"][targets[0]][level]):
        figures = {t: m["parsers"][t][level][name] for t in targets}
        deepest = worst(figures[GOAL_TARGET]["stack"]) or "-"
        rows.append(f"| `{name}.c` | " + " | ".join(cell(figures[t]) for t in targets) + f" | `{deepest}` |")
    return rows


def _entry_points(m: dict, targets: list[str], level: str) -> list[str]:
    rows = ["| interface | entry point | " + " | ".join(targets) + " |", "|---|---|" + "---|" * len(targets)]
    for name in sorted(m["parsers"][targets[0]][level]):
        for entry in sorted(m["parsers"][targets[0]][level][name]["stack"]):
            rows.append(f"| `{name}` | `{entry}` | " + " | ".join(
                bytes_or_refusal(m["parsers"][t][level][name]["stack"][entry]) for t in targets) + " |")
    return rows


def _outside(m: dict) -> str:
    names = sorted({n for by_target in m["parsers"].values() for levels in by_target.values()
                    for figures in levels.values() for n in figures["outside"]}
                   | {n for by_target in m["firmwares"].values() for levels in by_target.values()
                      for figures in levels.values() for n in figures.get("outside", [])})
    return ", ".join(f"`{n}`" for n in names if n != "__indirect_call")


def render(m: dict) -> str:
    targets = list(m["parsers"])
    tools = "; ".join(f"`{name}` {version}" for name, version in sorted(m["toolchains"].items()))
    skipped = sorted({f["skipped"] for by_target in m["firmwares"].values() for levels in by_target.values()
                      for f in levels.values() if "skipped" in f})
    lines = [
        BEGIN,
        "",
        f"Measured by `make bench-embedded` with {tools}. Bytes. **Flash**: code, constants and the "
        "initial values of data; **RAM**: data and bss (the stack reservation of `firmware.ld` left "
        "out); **stack**: the deepest chain of calls, each function's frame from `-fstack-usage` "
        "summed along gcc's call graph (`-fcallgraph-info=su`), where an indirect call counts as the "
        "deepest function its caller points at, itself or through its tables "
        "(`scripts/embedded_stack.py`); a cycle (recursion) has no bound, and the script refuses a "
        "figure for it. Functions outside the graph count 0: "
        f"{_outside(m)} (the C library's and the compiler's helpers, small leaves), and a visitor's "
        "callbacks, which are yours.",
        "",
        *_goals(m),
        "",
        "The firmwares of `examples/embedded/`, each a complete `main()` over bytes in a buffer, linked "
        "with `-Wl,--gc-sections`, their startup code included (`startup.c`, in place of the C library's) "
        "and the C library's functions they call (newlib-nano on ARM, picolibc on RISC-V), the primary "
        "stream's built with `" + " ".join(FIRMWARE_OPTIONS) + "` (see Options for a firmware; the last two "
        "rows are (1) and (2) without them); flash / RAM / stack of `main`:",
        "",
        *_firmwares(m, targets),
    ]
    if skipped:
        lines += ["", "Not built: " + "; ".join(skipped) + "."]
    refused = sorted({why for by_target in m["parsers"].values() for levels in by_target.values()
                      for figures in levels.values() for why in figures["stack"].values() if isinstance(why, str)})
    if refused:
        lines += ["", "No bound (the script refuses a stack figure where the call graph has a cycle): "
                  + "; ".join(f"`{why.removeprefix('no bound: ')}`" for why in refused) + "."]
    for level in sorted(_levels(m["parsers"]), key=lambda lv: lv != "-Os"):
        lines += ["", f"Each interface's parser alone (`generated/c/<interface>.c`, `{level}`, "
                      "`-ffunction-sections -fdata-sections`): flash / RAM / the deepest public entry "
                      f"point's stack (named for {GOAL_TARGET}):", "", *_parsers(m, targets, level)]
    lines += ["", "<details><summary>Stack of every public entry point (<code>-Os</code>)</summary>", "",
              *_entry_points(m, targets, "-Os"), "", "</details>", "", END]
    return "\n".join(_wrapped(line) for line in lines) + "\n"


def _wrapped(line: str) -> str:
    """Prose wrapped as the rest of the document is; tables and markers as they are."""
    if line.startswith(("|", "<")):
        return line
    return textwrap.fill(line, WIDTH, break_long_words=False, break_on_hyphens=False)


WIDTH = 100


def replace_table(doc: str, table: str) -> str:
    """The document with the text between the markers (the markers included) replaced."""
    start, end = doc.find(BEGIN), doc.find(END)
    if start < 0 or end < start:
        raise ValueError("docs/c.md has no bench-embedded markers")
    return doc[:start] + table + doc[end + len(END) + 1:]


def table_of(doc: str) -> str:
    start, end = doc.find(BEGIN), doc.find(END)
    return doc[start:end + len(END) + 1] if 0 <= start < end else ""
