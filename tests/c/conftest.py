"""Fixtures of the C tests: one build per compiler and sanitizer variant (see harness_c.py)."""
from __future__ import annotations

import pytest

from tests.c.harness_c import VARIANTS, Build, get_build


@pytest.fixture(scope="session", params=list(VARIANTS))
def build(request) -> Build:
    return get_build(request.param)


@pytest.fixture(scope="session")
def asan() -> Build:
    return get_build("asan-clang")


@pytest.fixture(scope="session")
def fast() -> Build:
    return get_build("gcc")


