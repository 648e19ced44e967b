"""python -m codegen --target epan --upstream: the copy of the epan dissectors for Wireshark's own
tree (docs/wireshark-upstream.md), which reads no command line; tests/native/test_upstream.py
builds and runs it."""
import re
import subprocess
import sys

import pytest

from codegen.epan_c import SHARED_STEM, development_branch, shared_helpers
from codegen.kinds.packages import epan
from tests.codegen.test_generated_is_current import ROOT

COMMAND_LINE_WORDS = ("/proc/self/cmdline", "tshark_command_line", "named_fields_only", "tshark_fields.c ----",
                      "ur_wanted.c ====")


def codegen(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "codegen", *args], cwd=ROOT, capture_output=True, text=True)


@pytest.mark.parametrize("args", [
    ("--upstream", "--target", "epan"),                                   # into generated/
    ("--upstream", "--target", "epan", "--out", "generated/upstream"),
    ("--upstream", "--out", "{tmp}"),                                     # every target
    ("--upstream", "--target", "epan", "--target", "c", "--out", "{tmp}"),
], ids=["generated", "under generated", "every target", "another target"])
def test_upstream_is_refused_beside_urwires_own_files(tmp_path, args):
    result = codegen(*(a.format(tmp=tmp_path) for a in args))
    assert result.returncode == 2 and "--upstream" in result.stderr
    assert not any(tmp_path.iterdir())


def test_the_upstream_copy_reads_no_command_line(tmp_path):
    assert codegen("--target", "epan", "--upstream", "--out", str(tmp_path)).returncode == 0
    files = sorted((tmp_path / "epan").glob("packet-*.c"))
    assert [p.name for p in files] == sorted(p.name for p in (ROOT / "generated" / "epan").glob("packet-*.c"))
    for path in files:
        text = path.read_text()
        assert not [w for w in COMMAND_LINE_WORDS if w in text], path.name
    assert "ur_wanted_upstream.c" in (tmp_path / "epan" / "packet-ur.c").read_text()
    assert "tshark_fields_upstream.c" in (tmp_path / "epan" / "packet-ur-common.c").read_text()


def test_each_copy_joins_its_runtime():
    assert "ur_wanted.c" in epan.runtime_code(False)
    upstream = epan.runtime_code(True)
    assert "ur_wanted.c" not in upstream
    assert upstream.index("ur_wanted_upstream.c") == epan.runtime_code(False).index("ur_wanted.c")
    epan.check_runtime(upstream)
    epan.check_runtime(epan.runtime_code(False))


def test_a_runtime_file_no_copy_joins_is_refused(tmp_path, monkeypatch):
    folder = tmp_path / "epan"
    folder.mkdir()
    for name in (*epan.RUNTIME_TYPES, *epan.runtime_code(True)):
        (folder / epan.runtime_file(name)).parent.mkdir(exist_ok=True)
        (folder / epan.runtime_file(name)).write_text("")
    monkeypatch.setattr(epan, "RUNTIME_FOLDER", tmp_path)
    epan.check_runtime(epan.runtime_code(True))           # Wireshark's tree: the upstream copy's files only
    with pytest.raises(ValueError, match="ur_wanted.c"):
        epan.check_runtime(epan.runtime_code(False))
    (folder / "packages" / "ur_stray.c").write_text("")
    with pytest.raises(ValueError, match="ur_stray.c"):
        epan.check_runtime(epan.runtime_code(True))


# Wireshark's development branch's style in the upstream copy only (codegen/epan_c.py)
# Protocol, field and subtree handles (the out-of-tree build against 4.0 gives subtree handles -1 as it
# registers them: dissector/native/subtrees_from_zero.h).
HANDLE_WITH_INIT = re.compile(r"^static (?:int|gint) [^;(]*\b(?:proto|hf|ett)_\w+(?:\[\w+\])? = (?:-1|\{)", re.M)


def test_the_upstream_copy_declares_its_handles_as_the_development_branch_does(tmp_path):
    assert codegen("--target", "epan", "--upstream", "--out", str(tmp_path)).returncode == 0
    for path in sorted((tmp_path / "epan").glob("packet-*.c")):
        if path.stem == SHARED_STEM:
            continue
        text = path.read_text()
        proto = path.name.removeprefix("packet-").removesuffix(".c").replace("-", "_")
        assert not HANDLE_WITH_INIT.findall(text), path.name
        assert re.search(rf"^static int proto_({proto}|lines|int32_records)?\w*;", text, re.M), path.name
        # urwire's own copy keeps the initialisers Wireshark 4.0's plugins are written with.
        assert HANDLE_WITH_INIT.search((ROOT / "generated" / "epan" / path.name).read_text()), path.name


def test_development_branch_drops_only_handle_initialisers():
    text = ("static int proto_x = -1;\nstatic int hf_a = -1, hf_b = -1;\nstatic gint ett_x = -1;   /* a tree */\n"
            "static int hf_x[X_COUNT] = {\n    -1, -1,\n    -1,\n};\nstatic int depth = -1;\n    int size = -1;\n"
            "static expert_field ei_x = EI_INIT;\n")
    assert development_branch(text) == (
        "static int proto_x;\nstatic int hf_a, hf_b;\nstatic gint ett_x;   /* a tree */\n"
        "static int hf_x[X_COUNT];\nstatic int depth = -1;\n    int size = -1;\nstatic expert_field ei_x = EI_INIT;\n")


def test_the_shared_helpers_are_defined_once_and_declared_for_every_dissector(tmp_path):
    """packet-ur-common.c defines the runtime several dissectors call (not static, named ur_*); each
    dissector that calls one includes packet-ur-common.h and joins none of it."""
    own, upstream = shared_helpers(), shared_helpers(upstream=True)
    assert sorted(own) == sorted(upstream) == [f"epan/{SHARED_STEM}.c", f"epan/{SHARED_STEM}.h"]
    source = own[f"epan/{SHARED_STEM}.c"]
    assert re.search(r"^ur_exchange_request_t \*\nur_exchange_request\(packet_info \*pinfo\)$", source, re.M)
    assert "/proc/self/cmdline" in source and "/proc/self/cmdline" not in upstream[f"epan/{SHARED_STEM}.c"]
    generated = ROOT / "generated" / "epan"
    for path in sorted(generated.glob("packet-*.c")):
        text = path.read_text()
        assert "---- runtime/epan/common/" not in text or path.stem == SHARED_STEM, path.name
        calls = re.search(r"\bur_(?:exchange|tshark_fields)_\w+\(", text)
        assert bool(calls) == (f'#include "{SHARED_STEM}.h"' in text) or path.stem == SHARED_STEM, path.name
