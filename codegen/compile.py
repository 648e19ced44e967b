"""The front end in one call: load -> validate -> resolve, by the spec's interface kind."""
from __future__ import annotations

from pathlib import Path

from .errors import Problem, SpecError
from .kinds import KINDS, Kind, kind_name
from .load import LoadedSpec, load_file, load_text
from .validate import schema_problems

SPEC_DIR = Path(__file__).resolve().parent.parent / "spec"
DEFAULT_SPEC = SPEC_DIR / "ur_primary.yaml"


def spec_files() -> list[Path]:
    """Every spec of the project, one per interface."""
    return sorted(SPEC_DIR.glob("*.yaml"))


def kind_of(spec: LoadedSpec) -> Kind:
    name = kind_name(spec.data)
    if name not in KINDS:
        raise SpecError(spec.source, [spec.problem("framing.kind", f"unknown interface kind {name!r}; "
                                                   f"known: {', '.join(sorted(KINDS))}")])
    return KINDS[name]


def compile_loaded(spec: LoadedSpec):
    """The spec's IR, its kind's model (kinds/<kind>/model.py)."""
    kind = kind_of(spec)
    problems: list[Problem] = schema_problems(spec, kind.schema)
    if problems:
        raise SpecError(spec.source, problems)
    return kind.resolve(spec)


def compile_text(text: str, source: str = "<spec>"):
    return compile_loaded(load_text(text, source))


def compile_file(path: Path = DEFAULT_SPEC):
    return compile_loaded(load_file(path))
