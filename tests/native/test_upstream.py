"""The upstream patch (docs/wireshark-upstream.md): `make upstream-patch` lays out exactly the files
a Wireshark patch would carry and builds an out-of-tree plugin from exactly its dissector files;
the patch's own tools/urwire2wireshark.py regenerates them; its dissectors are the generator's
upstream copy, which reads no command line and shows what urwire's plugin shows; `make
check-upstream` runs Wireshark's source checks from a checkout (WIRESHARK_SOURCE; Debian packages
none of them).
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.native import harness

ROOT = harness.ROOT
FIXTURE_EPAN = Path(__file__).resolve().parent / "fixtures" / "epan"
GENERATED = sorted(harness.EPAN.glob("packet-*.c"))
WIRESHARK_SOURCE = os.environ.get("WIRESHARK_SOURCE")
SAMPLES = ROOT / "dissector" / "samples"
# The runtime only urwire's own plugin joins: it reads tshark's command line.
COMMAND_LINE_RUNTIME = {"tshark_fields.c", "ur_wanted.c"}
COMMAND_LINE_WORDS = ("/proc/self/cmdline", "tshark_command_line", "named_fields_only")
# The dissectors whose upstream copy differs from urwire's (the others read no command line at all).
COMMAND_LINE_READERS = {"packet-ur.c", "packet-rtde.c"}


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
               for p in (ROOT / "runtime" / "epan").rglob("*")
               if p.is_file() and "__pycache__" not in p.parts and p.name not in COMMAND_LINE_RUNTIME]
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


@pytest.fixture(scope="module")
def patch() -> Path:
    """`make upstream-patch` of the generated dissectors, once, under build/native-tests/upstream
    (its plugin in upstream-plugin beside it, where the user nobody may read it)."""
    if not (GENERATED and has_epan_target()):
        pytest.skip("the generator has no epan target yet, or generated/epan no files")
    out = harness.BUILDS / "upstream"
    result = make("upstream-patch", f"UPSTREAM={out}")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return out


def test_upstream_patch_of_the_generated_files(patch):
    """The patch's dissectors are the upstream copy: those that read tshark's command line in
    urwire's plugin differ, the others are the generated files; they join exactly the runtime the
    patch carries."""
    dissectors = sorted((patch / "epan" / "dissectors").iterdir())
    assert [p.name for p in dissectors] == [p.name for p in GENERATED]
    for path in dissectors:
        same = path.read_bytes() == (harness.EPAN / path.name).read_bytes()
        assert same == (path.name not in COMMAND_LINE_READERS), path.name
    joined = {name for path in dissectors
              for name in re.findall(r"^/\* [-=]{4} runtime/epan/(\S+) [-=]{4} \*/$", path.read_text(), re.M)}
    assert joined == {p.name for p in (patch / "tools" / "urwire" / "runtime" / "epan").iterdir()}


def test_the_patch_reads_no_command_line(patch):
    """Nothing of the patch reads tshark's command line or registers the preference that follows it,
    but the generator, which renders urwire's own plugin too."""
    for path in patch.rglob("*"):
        if path.is_file() and "codegen" not in path.relative_to(patch).parts:
            text = path.read_text()
            assert not [w for w in COMMAND_LINE_WORDS if w in text], path


@pytest.fixture(scope="module")
def upstream_plugin(patch) -> harness.Plugin:
    """The plugin `make upstream-patch` built from exactly the patch's dissectors."""
    built = patch.parent / "upstream-plugin"
    cache = (built / "CMakeCache.txt").read_text()
    assert f"URWIRE_EPAN_DIR:PATH={patch / 'epan' / 'dissectors'}" in cache
    return harness.installed_plugin("upstream", built)


def shown_by_both(upstream_plugin: harness.Plugin, capture: Path, *args: str) -> tuple[str, str]:
    """tshark's output with the upstream plugin, and with urwire's own (built from generated/epan)."""
    return (harness.checked(harness.run_plugin(upstream_plugin, capture, *args)),
            harness.checked(harness.run_native(capture, *args)))


@pytest.mark.parametrize("sample", ["cell_session.pcapng", "primary_session.pcapng"])
@pytest.mark.parametrize("args", [("-T", "json"), ("-V",)], ids=["json", "tree"])
def test_the_upstream_plugin_shows_what_urwires_shows(upstream_plugin, sample, args):
    upstream, own = shown_by_both(upstream_plugin, SAMPLES / sample, *args)
    assert "ur" in upstream and upstream == own


@pytest.mark.parametrize("sample", ["cell_session.pcapng", "primary_session.pcapng"])
def test_the_upstream_plugin_prints_the_fields_urwires_prints(upstream_plugin, sample):
    """tshark -T fields: urwire's plugin builds only the package named and appends no RTDE unit;
    the upstream one builds the whole tree, and prints the same values."""
    args = ("-T", "fields", "-e", "ur.joint_data.q_actual", "-e", "rtde.actual_q", "-e", "rtde.timestamp")
    upstream, own = shown_by_both(upstream_plugin, SAMPLES / sample, *args)
    assert upstream.strip() and upstream == own


def test_the_upstream_plugin_has_no_named_fields_preference(upstream_plugin):
    prefs = harness.checked(harness.tshark_with(upstream_plugin, ["-G", "currentprefs"]))
    assert "ur.max_length" in prefs and "named_fields_only" not in prefs


def has_epan_target() -> bool:
    sys.path.insert(0, str(ROOT))
    from codegen.targets import TARGETS
    return "epan" in TARGETS


@pytest.mark.parametrize("name", ["packet-ur.c", "packet-ur-dashboard.c"])
def test_the_patch_regenerates_its_own_dissectors(tmp_path, name):
    """tools/urwire2wireshark.py --check, in the laid-out tree, finds the dissectors current; after
    an edit of one (an upstream copy that differs from urwire's, or one that does not) it finds it
    stale, and without --check it writes it back."""
    if not (GENERATED and has_epan_target()):
        pytest.skip("the generator has no epan target yet, or generated/epan no files")
    out = tmp_path / "upstream"
    assert subprocess.run([sys.executable, str(ROOT / "scripts" / "upstream-patch.py"), str(out)],
                          capture_output=True).returncode == 0
    tool = out / "tools" / "urwire2wireshark.py"
    check = subprocess.run([sys.executable, str(tool), "--check"], capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
    edited = out / "epan" / "dissectors" / name
    laid_out = edited.read_bytes()
    edited.write_text(edited.read_text() + "/* edited */\n")
    stale = subprocess.run([sys.executable, str(tool), "--check"], capture_output=True, text=True)
    assert stale.returncode == 1 and name in stale.stderr
    assert subprocess.run([sys.executable, str(tool)], capture_output=True).returncode == 0
    assert edited.read_bytes() == laid_out


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
