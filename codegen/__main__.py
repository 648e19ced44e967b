"""python -m codegen [--check]: write generated/ from the specs (spec/*.yaml, one per interface), or
check that it is current.

`python -m codegen --target epan --upstream --out DIR` writes the copy of the epan dissectors for
Wireshark's own tree (docs/wireshark-upstream.md): it reads no command line.

`--pin 5.11` and `--select ur:robot_state.joint_data,robot_state.tool_data` (or a selection file)
write a smaller build outside generated/ (docs/generator.md#subsets).

Also: `python -m codegen diff 3.15 5.11` prints what changed between two software versions (and
the C robot-state fast-path loop each takes; `--spec spec/ur_realtime.yaml` or any other spec for
that interface), and `python -m codegen reference [--check]` writes docs/protocol.md, the
protocol reference.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from . import ir, select
from .compile import DEFAULT_SPEC, compile_file, compile_loaded, kind_of, spec_files
from .emit import banner_lines
from .epan_c import shared_helpers
from .errors import SpecError
from .kinds import TARGETS, TargetOptions
from .kinds.packages.c import fast_path_change
from .kinds.packages.model import Protocol
from .kinds.packages.pin import pin
from .kinds.packages.plan import ProtocolPlan, plan
from .kinds.packages.reference import protocol_markdown
from .load import load_file, load_text

ROOT = Path(__file__).resolve().parent.parent


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["diff"]:
        return _diff(argv[1:])
    if argv[:1] == ["reference"]:
        return _reference(argv[1:])
    parser = argparse.ArgumentParser(prog="python -m codegen", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--spec", type=Path, action="append",
                        help="only this spec (default: every spec/*.yaml, one per interface)")
    parser.add_argument("--out", type=Path, default=ROOT / "generated")
    parser.add_argument("--target", action="append", choices=sorted(TARGETS),
                        help="only these targets (default: all)")
    parser.add_argument("--check", action="store_true",
                        help="write nothing; exit 1 if generated/ differs from what would be written")
    parser.add_argument("--pin", metavar="VERSION",
                        help="only what this software version sends, with no version branches (needs --out "
                             "outside generated/ and the primary spec), e.g. --pin 5.11 --target c --out build/pinned")
    parser.add_argument("--select", metavar="SELECTION", action="append",
                        help="only these parts of an interface, the rest framed and kept raw (needs --out outside "
                             "generated/): interface:name,name or a selection file (.yaml), e.g. --select "
                             "ur:robot_state.joint_data,robot_state.tool_data --target c --out build/subset "
                             "(docs/generator.md#subsets)")
    parser.add_argument("--upstream", action="store_true",
                        help="the epan dissectors as Wireshark's own tree carries them, reading no command line "
                             "(needs --target epan and --out outside generated/), e.g. --target epan --upstream "
                             "--out build/upstream-epan")
    args = parser.parse_args(argv)
    if args.pin and args.out.resolve() == (ROOT / "generated").resolve():
        parser.error("--pin writes a build for one version: give --out a folder outside generated/")
    if args.upstream and args.target != ["epan"]:
        parser.error("--upstream renders the epan dissectors only: give --target epan")
    if args.upstream and args.out.resolve().is_relative_to((ROOT / "generated").resolve()):
        parser.error("--upstream writes Wireshark's copy of the dissectors: give --out a folder outside generated/")
    if args.select and args.out.resolve() == (ROOT / "generated").resolve():
        parser.error("--select writes a build of some parts only: give --out a folder outside generated/")
    outputs: dict[str, str] = {}
    try:
        args.selection = select.parse(args.select) if args.select else None
        specs = args.spec or (select.specs_for(args.selection, spec_files()) if args.selection
                              else [DEFAULT_SPEC] if args.pin else spec_files())
        unselectable: list = []                 # every interface's selection problems, not the first's
        for spec in specs:
            try:
                rendered = _render_spec(spec, args)
            except select.SelectionError as exc:
                unselectable += exc.problems
                continue
            for rel, text in rendered.items():
                if rel in outputs:
                    print(f"{spec}: writes {rel}, which another spec writes too", file=sys.stderr)
                    return 2
                outputs[rel] = text
        if unselectable:
            raise select.SelectionError(select.OPTION, unselectable)
        if args.target is None or "epan" in args.target:    # what the epan dissectors of every kind share
            outputs.update(shared_helpers(upstream=args.upstream))
    except SpecError as exc:
        # A target that cannot render a node reports it like a spec error: path, line, what.
        print(exc, file=sys.stderr)
        return 2
    # Files of the target folders that no spec wrote are stale only when every spec was rendered.
    every_spec = args.spec is None and not args.pin and not args.select
    return _check(args.out, outputs, every_spec) if args.check else _write(args.out, outputs, every_spec)


def _render_spec(spec: Path, args) -> dict[str, str]:
    spec_rel = spec.resolve().relative_to(ROOT) if spec.resolve().is_relative_to(ROOT) else spec
    text = spec.read_text(encoding="utf-8")
    loaded = load_text(text, str(spec))
    kind = kind_of(loaded)
    model = compile_loaded(loaded)
    if args.pin:
        if not isinstance(model, Protocol):
            raise SpecError(str(spec), [loaded.problem("framing", "--pin applies to the primary interface's spec")])
        model = pin(model, ir.parse_version(args.pin))
    key = args.selection.key_of(select.names_of(spec, loaded.data)) if args.selection else None
    if key is not None:
        model = select.apply(kind.name, model, args.selection.picks[key], args.selection.keys[key])
    banner = banner_lines(str(spec_rel), text, upstream=args.upstream)
    if key is not None:
        banner += select.banner(args.selection.picks[key])
    return kind.render(model, banner, args.target, _target_options(args))


def _target_options(args) -> TargetOptions:
    return {"epan": {"upstream": True}} if args.upstream else {}


def _planned(spec: Path):
    try:
        return plan(compile_file(spec))
    except SpecError as exc:
        print(exc, file=sys.stderr)
        return None


def _diff(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="python -m codegen diff",
                                     description="What changes in an interface from one software version to another "
                                                 "(for the ROS driver's sockets, from one driver release to another).")
    parser.add_argument("old", help="software version, e.g. 3.15")
    parser.add_argument("new", help="software version, e.g. 5.11 or 5.25.1")
    parser.add_argument("--spec", type=Path, default=DEFAULT_SPEC)
    args = parser.parse_args(argv)
    try:
        old, new = ir.parse_version(args.old), ir.parse_version(args.new)
    except ValueError:
        parser.error("versions are written like 5.9 or 5.25.1")
    try:
        loaded = load_file(args.spec)
        kind = kind_of(loaded)
        planned = kind.plan(compile_loaded(loaded))
    except SpecError as exc:
        print(exc, file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"{args.spec}: cannot read the spec: {exc.strerror}", file=sys.stderr)
        return 2
    lines = kind.diff(planned, old, new)
    print(f"{args.old} -> {args.new}: " + (f"{len([x for x in lines if not x.startswith(' ')])} change(s)"
                                           if lines else "no change"))
    for line in lines:
        print(line)
    if isinstance(planned, ProtocolPlan):      # the primary interface: which C fast path each takes
        print(fast_path_change(planned, old, new))
    return 0


def _reference(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="python -m codegen reference", description="Write docs/protocol.md.")
    parser.add_argument("--spec", type=Path, default=DEFAULT_SPEC)
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "protocol.md")
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 if the file is out of date")
    args = parser.parse_args(argv)
    planned = _planned(args.spec)
    if planned is None:
        return 2
    spec_rel = args.spec.resolve().relative_to(ROOT) if args.spec.resolve().is_relative_to(ROOT) else args.spec
    text = protocol_markdown(planned, str(spec_rel))
    current = args.out.read_text(encoding="utf-8") if args.out.exists() else None
    if args.check:
        if current != text:
            print(f"out of date: {args.out.relative_to(ROOT) if args.out.is_relative_to(ROOT) else args.out} "
                  f"(run `make generate`)", file=sys.stderr)
            return 1
        return 0
    if current != text:
        args.out.write_text(text, encoding="utf-8")
    return 0


def _is_build_artifact(path: Path) -> bool:
    """What Python and pip leave beside the sources (bytecode, `pip install .` metadata)."""
    return any(part == "__pycache__" or part.endswith(".egg-info") for part in path.parts)


def _owned(out: Path, outputs: dict[str, str]) -> set[Path]:
    """Files under each target folder we render into; anything else there is stale."""
    tops = {rel.split("/")[0] for rel in outputs}
    return {p for top in tops if (out / top).is_dir() for p in (out / top).rglob("*")
            if p.is_file() and not _is_build_artifact(p.relative_to(out))}


def _write(out: Path, outputs: dict[str, str], remove_stale: bool = True) -> int:
    stale = _owned(out, outputs) - {out / rel for rel in outputs} if remove_stale else set()
    for path in stale:
        path.unlink()
    for rel, text in outputs.items():
        path = out / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")
    return 0


def _check(out: Path, outputs: dict[str, str], report_stale: bool = True) -> int:
    differ = [rel for rel, text in outputs.items()
              if not (out / rel).exists() or (out / rel).read_text(encoding="utf-8") != text]
    stale = sorted(str(p.relative_to(out)) for p in _owned(out, outputs) - {out / rel for rel in outputs}) \
        if report_stale else []
    for rel in differ:
        print(f"out of date: generated/{rel}", file=sys.stderr)
    for rel in stale:
        print(f"not generated by the spec: generated/{rel}", file=sys.stderr)
    return 1 if differ or stale else 0


if __name__ == "__main__":
    sys.exit(main())
