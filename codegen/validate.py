"""Pass 2: check the spec's shape against the JSON Schema of the spec language."""
from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

import jsonschema

from .errors import Problem
from .load import LoadedSpec

SCHEMA_PATH = Path(__file__).parent / "schema" / "spec.schema.json"


@lru_cache(maxsize=1)
def _validator() -> jsonschema.Draft202012Validator:
    schema = json.loads(SCHEMA_PATH.read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def _deepest(error: jsonschema.ValidationError) -> jsonschema.ValidationError:
    # oneOf failures hide the useful message in their context; take the most specific one.
    best = error
    while best.context:
        best = max(best.context, key=lambda e: len(e.absolute_path))
    return best


def schema_problems(spec: LoadedSpec) -> list[Problem]:
    problems = []
    for error in sorted(_validator().iter_errors(spec.data), key=lambda e: list(map(str, e.absolute_path))):
        detail = _deepest(error)
        problems.append(spec.problem(list(detail.absolute_path), detail.message))
    return problems
