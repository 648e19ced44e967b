"""urwire._ccore built with ASan and UBSan from the sources setup.py builds it from
(ext/ccore/sources.txt), and the environment a Python process needs to load it: the tests run
their peers (tests/python/*_asan_peer.py) over it in a process of their own."""
from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
INCLUDES = ["ext/ccore", "generated/c", "runtime/c/json", "runtime/c/capture"]   # as setup.py


def sources() -> list[str]:
    return (ROOT / "ext" / "ccore" / "sources.txt").read_text().split()


def build(folder: Path) -> Path:
    library = folder / ("_ccore" + sysconfig.get_config_var("EXT_SUFFIX"))
    subprocess.run(["gcc", "-shared", "-fPIC", "-g", "-O1", "-std=c99", "-D_GNU_SOURCE", "-Wall", "-Werror",
                    "-fsanitize=address,undefined", "-fno-sanitize-recover=all",
                    *[f"-I{d}" for d in INCLUDES], "-I" + sysconfig.get_paths()["include"], *sources(), "-lm",
                    "-o", str(library)], cwd=ROOT, check=True, timeout=300)
    return library


def load(library: str):
    """The module of a sanitized build, in a peer's process (in place of the in-tree one)."""
    spec = importlib.util.spec_from_file_location("urwire._ccore", library)
    ccore = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ccore)
    return ccore


def run_peer(peer: str, folder: Path) -> subprocess.CompletedProcess:
    """tests/python/<peer> run over a sanitized build made in folder, its runtimes preloaded."""
    library = build(folder)
    runtimes = [subprocess.run(["gcc", f"-print-file-name={name}"], capture_output=True, text=True,
                               check=True).stdout.strip() for name in ("libasan.so", "libubsan.so")]
    env = dict(os.environ, LD_PRELOAD=":".join(runtimes), ASAN_OPTIONS="detect_leaks=0")
    return subprocess.run([sys.executable, str(ROOT / "tests" / "python" / peer), str(library)],
                          env=env, capture_output=True, text=True, timeout=600)


def extension():
    """The in-tree urwire._ccore, for a test that needs it (missing() when it is not built)."""
    try:
        from urwire import _ccore
    except ImportError:
        missing("the C extension urwire._ccore is not built (make python-ext)")
    return _ccore


def missing(why: str) -> None:
    """A test that needs the built extension, without it: a failure where it must be built (make
    test builds it first), a skip where the run says it is not (URWIRE_TESTS_WITHOUT_CCORE=1:
    scripts/test-python-range.sh, whose venvs run the pure-Python package on other Pythons)."""
    import pytest

    if os.environ.get("URWIRE_TESTS_WITHOUT_CCORE") == "1":
        pytest.skip(why)
    pytest.fail(why)
