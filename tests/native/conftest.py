"""The native plugin built with ASan and UBSan is slow to build and slow to run: every test that
runs it is a long sweep (marked `deep`), which `make test-deep` runs in CI and `make test` leaves
out. The same captures run through the plain build in `make test`."""
import re
from pathlib import Path

import pytest

HERE = Path(__file__).parent

SANITIZED = re.compile(r"asan|sanitiz|short_fixed_run", re.IGNORECASE)
ABOUT_SANITIZERS = ("test_what_counts_as_a_failure",)   # reads report texts; runs no plugin


def pytest_collection_modifyitems(items):
    # the hook sees every test of the session: only this folder's are meant
    for item in items:
        if Path(item.fspath).parent == HERE and SANITIZED.search(item.name) and not item.name.startswith(ABOUT_SANITIZERS):
            item.add_marker(pytest.mark.deep)
