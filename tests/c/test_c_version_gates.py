"""A field with a version range, in generated C: read, printed and encoded only for streams of
those versions. This renders a variant of the spec with one more gated field (as
tests/codegen/test_version_gates.py does for Python) and builds the CLI on it."""
from __future__ import annotations

import json
import struct
import subprocess

import pytest
import yaml

from codegen.kinds.packages.plan import plan
from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.kinds.packages import c as c_target
from tests.c import state_members
from tests.c.harness_c import CLI_LIBRARY, CLI_SOURCES, ROOT, compile_c


def variant_cli(tmp_path):
    data = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))
    fields = data["messages"]["robot_state"]["packages"]["additional_info"]["fields"]
    fields.append({"name": "gated_flag", "label": "Gated flag", "type": "uint16", "versions": {"from": "5.12", "through": "PolyScope X"}})
    for rel, text in c_target.render(plan(compile_text(yaml.safe_dump(data, sort_keys=False))), ["test build"]).items():
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text(text)
    exe, driver = tmp_path / "urwire-decode", tmp_path / "driver"
    flags = ["-O1", "-g", "-fsanitize=address,undefined", "-fno-sanitize-recover=all", f"-I{tmp_path / 'c'}"]
    compile_c("clang", flags, [*CLI_SOURCES, tmp_path / "c" / "urwire.c"], exe, ["-lm"])
    compile_c("clang", flags + [f"-I{state_members.write(tmp_path / 'c' / 'urwire.h', tmp_path / 'c')}"],
              [ROOT / "tests" / "c" / "driver.c", *CLI_LIBRARY, tmp_path / "c" / "urwire.c"], driver, ["-lm"])
    return exe, driver


@pytest.mark.deep  # builds a variant of the C library and the command (about 20 s): make test-deep
def test_a_gated_field_is_read_only_from_its_version(tmp_path):
    exe, driver = variant_cli(tmp_path)

    def message(body: bytes) -> bytes:
        pkg = struct.pack(">iB", 5 + len(body), 8) + body
        return struct.pack(">iB", 5 + len(pkg), 16) + pkg

    def decode(msg, hint):
        result = subprocess.run([str(exe), "--version-hint", hint, "-"], input=msg, capture_output=True)
        assert result.returncode == 0, result.stderr
        (record,) = [json.loads(line) for line in result.stdout.decode().splitlines()]
        return record["packages"][0]

    # A body of neither form's size (7 bytes: 4 up to 5.11, 6 from 5.12) is read in the
    # version's form, the rest flagged as extra.
    msg = message(bytes([1, 0, 1, 0]) + struct.pack(">H", 0xBEEF) + b"\x99")
    new, old = decode(msg, "5.12"), decode(msg, "5.9")
    assert new["gated_flag"] == 0xBEEF and new["extra"] == "99"
    assert "gated_flag" not in old and old["extra"] == "beef99"
    assert "ver->key >= URWIRE__V(5, 12, 0)" in (tmp_path / "c" / "urwire.c").read_text()
    # A body of exactly the 5.12 form's size is that form, whatever the version
    # (docs/contract.md#choosing-a-layout: the one form whose size equals the length).
    exact = message(bytes([1, 0, 1, 0]) + struct.pack(">H", 0xBEEF))
    assert decode(exact, "5.9")["gated_flag"] == 0xBEEF and "extra" not in decode(exact, "5.9")
    # Encoded back exactly under either version: the field, or the same bytes as extra.
    for data in (msg, exact):
        (tmp_path / "m.bin").write_bytes(data)
        for hint in ("5.12", "5.9"):
            result = subprocess.run([str(driver), "roundtrip", str(tmp_path / "m.bin"), hint], capture_output=True,
                                    text=True)
            assert result.returncode == 0 and result.stdout.startswith("messages 1 packages 1"), result.stdout


def test_a_layout_of_several_forms_has_a_decoder_per_form_that_tests_no_version():
    """The form is chosen first (runtime/forms.c), so the decoder of each form reads its fields
    straight: every sub-package layout with several forms (masterboard data's five...) has one
    decoder per form, none of which compares the version, and no decoder of the whole layout."""
    source = (ROOT / "generated" / "c" / "urwire.c").read_text()
    robot_state = plan(compile_text(DEFAULT_SPEC.read_text(encoding="utf-8"))).message("robot_state")
    several = [c.layout for c in robot_state.layouts if len(robot_state.forms_of(c.layout)) > 1]
    assert "masterboard_data" in [lay.name for lay in several]
    for lay in several:
        assert f"bool urwire__decode_{lay.name}(" not in source
        for k in range(len(robot_state.forms_of(lay))):
            start = source.index(f"static inline bool urwire__decode_{lay.name}_{k}(")
            body = source[start:source.index("\n}\n", start)]
            assert "ver->key" not in body, f"urwire__decode_{lay.name}_{k}"
            assert f"urwire__decode_{lay.name}_{k}(msg, at, end, ver, &out->{lay.name}, err)" in source
