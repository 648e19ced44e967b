"""The upstream patch (docs/wireshark-upstream.md): `make upstream-patch` lays out exactly the files
a Wireshark patch would carry and builds an out-of-tree plugin from exactly its dissector files;
the patch's own tools/urwire2wireshark.py regenerates them; `make check-upstream` runs Wireshark's
source checks from a checkout (WIRESHARK_SOURCE; Debian packages none of them).
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.native import harness

ROOT = harness.ROOT
FIXTURE_EPAN = Path(__file__).resolve().parent / "fixtures" / "epan"
GENERATED = sorted(harness.EPAN.glob("packet-*.c"))
WIRESHARK_SOURCE = os.environ.get("WIRESHARK_SOURCE")


def make(*args: str) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k != "MAKEFLAGS"}
    return subprocess.run(["make", "--no-print-directory", "-C", str(ROOT), *args], capture_output=True, text=True,
                          env=env, timeout=900)


def files_under(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file())


def expected_tools() -> list[str]:
    generator = [f"tools/urwire/codegen/{p.relative_to(ROOT / 'codegen')}" for p in (ROOT / "codegen").rglob("*")
                 if p.is_file() and "__pycache__" not in p.parts]
    specs = [f"tools/urwire/spec/{p.name}" for p in (ROOT / "spec").glob("*.yaml")]
    runtime = [f"tools/urwire/runtime/epan/{p.relative_to(ROOT / 'runtime' / 'epan')}"
               for p in (ROOT / "runtime" / "epan").rglob("*") if p.is_file() and "__pycache__" not in p.parts]
    return [*generator, *specs, *runtime, "tools/urwire2wireshark.py"]


def test_upstream_patch_carries_exactly_its_files_and_builds_from_them(tmp_path):
    out = tmp_path / "upstream"
    result = make("upstream-patch", f"URWIRE_EPAN_DIR={FIXTURE_EPAN}", f"UPSTREAM={out}")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    dissectors = [f"epan/dissectors/{p.name}" for p in FIXTURE_EPAN.glob("packet-*.c")]
    assert files_under(out) == sorted([*dissectors, *expected_tools()])
    for name in dissectors:
        assert (out / name).read_bytes() == (FIXTURE_EPAN / Path(name).name).read_bytes()
    # the plugin is built from exactly the patch's epan/dissectors
    cache = (tmp_path / "upstream-plugin" / "CMakeCache.txt").read_text()
    assert f"URWIRE_EPAN_DIR:PATH={out / 'epan' / 'dissectors'}" in cache
    library = tmp_path / "upstream-plugin" / "plugins" / "4.0" / "epan" / "urwire.so"
    symbols = subprocess.run(["nm", "-D", "--defined-only", str(library)], capture_output=True, text=True,
                             check=True).stdout.split()
    assert "plugin_register" in symbols
    assert f"native-dissector: {tmp_path / 'upstream-plugin'}" in result.stdout


def test_upstream_patch_of_the_generated_files(tmp_path):
    if not GENERATED:
        pytest.skip("no generated/epan/packet-*.c yet (make generate)")
    out = tmp_path / "upstream"
    result = make("upstream-patch", f"UPSTREAM={out}")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert sorted(p.name for p in (out / "epan" / "dissectors").iterdir()) == [p.name for p in GENERATED]


def has_epan_target() -> bool:
    sys.path.insert(0, str(ROOT))
    from codegen.targets import TARGETS
    return "epan" in TARGETS


def test_the_patch_regenerates_its_own_dissectors(tmp_path):
    """tools/urwire2wireshark.py --check, in the laid-out tree, finds the dissectors current; after
    an edit of one it finds it stale, and without --check it writes it back."""
    if not (GENERATED and has_epan_target()):
        pytest.skip("the generator has no epan target yet, or generated/epan no files")
    out = tmp_path / "upstream"
    assert make("upstream-patch", f"UPSTREAM={out}").returncode == 0
    tool = out / "tools" / "urwire2wireshark.py"
    check = subprocess.run([sys.executable, str(tool), "--check"], capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
    edited = out / "epan" / "dissectors" / GENERATED[0].name
    edited.write_text(edited.read_text() + "/* edited */\n")
    assert subprocess.run([sys.executable, str(tool), "--check"], capture_output=True).returncode == 1
    assert subprocess.run([sys.executable, str(tool)], capture_output=True).returncode == 0
    assert edited.read_bytes() == GENERATED[0].read_bytes()


def test_check_upstream_wants_a_checkout():
    result = make("check-upstream", "WIRESHARK_SOURCE=")
    assert result.returncode != 0 and "WIRESHARK_SOURCE" in result.stderr


@pytest.mark.skipif(not WIRESHARK_SOURCE, reason="WIRESHARK_SOURCE is not set: Wireshark's checks (checkAPIs.pl, "
                    "checkhf.pl, check_typed_item_calls.py) come from a Wireshark checkout, not from Debian")
def test_wiresharks_checks_pass_on_the_generated_dissectors():
    epan = harness.EPAN if GENERATED else FIXTURE_EPAN
    result = make("check-upstream", f"WIRESHARK_SOURCE={WIRESHARK_SOURCE}", f"URWIRE_EPAN_DIR={epan}")
    assert result.returncode == 0, result.stdout[-6000:] + result.stderr[-3000:]


@pytest.mark.skipif(not WIRESHARK_SOURCE, reason="WIRESHARK_SOURCE is not set")
def test_check_upstream_reports_an_unused_field(tmp_path):
    source = (FIXTURE_EPAN / "packet-urwire-fixture.c").read_text()
    (tmp_path / "packet-urwire-fixture.c").write_text(source.replace(
        "static int hf_urwire_fixture_value = -1;\n",
        "static int hf_urwire_fixture_value = -1;\nstatic int hf_urwire_fixture_unused = -1;\n"))
    result = make("check-upstream", f"WIRESHARK_SOURCE={WIRESHARK_SOURCE}", f"URWIRE_EPAN_DIR={tmp_path}")
    assert result.returncode != 0
    assert "hf_urwire_fixture_unused" in result.stdout
