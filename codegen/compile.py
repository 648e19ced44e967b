"""The front end in one call: load -> validate -> resolve."""
from __future__ import annotations

from pathlib import Path

from . import ir
from .errors import SpecError
from .load import LoadedSpec, load_file, load_text
from .resolve import resolve
from .validate import schema_problems

DEFAULT_SPEC = Path(__file__).resolve().parent.parent / "spec" / "ur_primary.yaml"


def compile_loaded(spec: LoadedSpec) -> ir.Protocol:
    problems = schema_problems(spec)
    if problems:
        raise SpecError(spec.source, problems)
    return resolve(spec)


def compile_text(text: str, source: str = "<spec>") -> ir.Protocol:
    return compile_loaded(load_text(text, source))


def compile_file(path: Path = DEFAULT_SPEC) -> ir.Protocol:
    return compile_loaded(load_file(path))
