"""Pass 2: check the spec's shape against the JSON Schema of its part of the spec language.

Every file under codegen/schema is registered by its name, so a kind's schema can take the shared
definitions (fields, types, versions, enums) from the primary one: {"$ref": "spec.schema.json#/$defs/field"}.
"""
from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

import jsonschema
from referencing import Registry, Resource
from referencing.jsonschema import DRAFT202012

from .errors import Problem
from .load import LoadedSpec

SCHEMA_DIR = Path(__file__).parent / "schema"
SCHEMA_PATH = SCHEMA_DIR / "spec.schema.json"


@lru_cache(maxsize=1)
def _registry() -> Registry:
    resources = [(path.name, Resource.from_contents(json.loads(path.read_text(encoding="utf-8")),
                                                    default_specification=DRAFT202012))
                 for path in sorted(SCHEMA_DIR.glob("*.schema.json"))]
    return Registry().with_resources(resources)


@lru_cache(maxsize=None)
def _validator(schema_name: str) -> jsonschema.Draft202012Validator:
    schema = json.loads((SCHEMA_DIR / schema_name).read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(schema)
    # Validate through a reference to the registered file, so its relative $refs resolve by name.
    return jsonschema.Draft202012Validator({"$ref": schema_name}, registry=_registry())


def _deepest(error: jsonschema.ValidationError) -> jsonschema.ValidationError:
    # oneOf failures hide the useful message in their context; take the most specific one.
    best = error
    while best.context:
        best = max(best.context, key=lambda e: len(e.absolute_path))
    return best


def schema_problems(spec: LoadedSpec, schema_name: str = SCHEMA_PATH.name) -> list[Problem]:
    problems = []
    errors = _validator(schema_name).iter_errors(spec.data)
    for error in sorted(errors, key=lambda e: list(map(str, e.absolute_path))):
        detail = _deepest(error)
        problems.append(spec.problem(list(detail.absolute_path), detail.message))
    return problems
