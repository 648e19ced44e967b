"""A field with a version range, in generated C: read, printed and encoded only for streams of
those versions. The real spec has none yet, so this renders a variant of it with one gated
field (as tests/codegen/test_version_gates.py does for Python) and builds the CLI on it."""
from __future__ import annotations

import json
import struct
import subprocess

import yaml

from codegen.plan import plan
from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.targets import c as c_target
from tests.c.harness_c import CLI, ROOT, compile_c


def variant_cli(tmp_path):
    data = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))
    fields = data["messages"]["robot_state"]["packages"]["additional_info"]["fields"]
    fields.append({"name": "gated_flag", "type": "uint16", "versions": {"from": "5.12"}})
    for rel, text in c_target.render(plan(compile_text(yaml.safe_dump(data, sort_keys=False))), ["test build"]).items():
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text(text)
    exe, driver = tmp_path / "urwire-decode", tmp_path / "driver"
    flags = ["-O1", "-g", "-fsanitize=address,undefined", "-fno-sanitize-recover=all", f"-I{tmp_path / 'c'}"]
    compile_c("clang", flags, [CLI / "main.c", CLI / "json.c", tmp_path / "c" / "urwire.c"], exe, ["-lm"])
    compile_c("clang", flags, [ROOT / "tests" / "c" / "driver.c", CLI / "json.c", tmp_path / "c" / "urwire.c"],
              driver, ["-lm"])
    return exe, driver


def test_a_gated_field_is_read_only_from_its_version(tmp_path):
    exe, driver = variant_cli(tmp_path)
    body = bytes([1, 0, 1, 0]) + struct.pack(">H", 0xBEEF)
    pkg = struct.pack(">iB", 5 + len(body), 8) + body
    msg = struct.pack(">iB", 5 + len(pkg), 16) + pkg

    def decode(hint):
        result = subprocess.run([str(exe), "--version-hint", hint, "-"], input=msg, capture_output=True)
        assert result.returncode == 0, result.stderr
        (record,) = [json.loads(line) for line in result.stdout.decode().splitlines()]
        return record["packages"][0]

    new, old = decode("5.12"), decode("5.9")
    assert new["gated_flag"] == 0xBEEF and "extra" not in new
    assert "gated_flag" not in old and old["extra"] == "beef"
    assert "urwire__version_cmp(version, 5, 12) >= 0" in (tmp_path / "c" / "urwire.c").read_text()
    # Encoded back exactly under either version: the field, or the same bytes as extra.
    (tmp_path / "m.bin").write_bytes(msg)
    for hint in ("5.12", "5.9"):
        result = subprocess.run([str(driver), "roundtrip", str(tmp_path / "m.bin"), hint], capture_output=True, text=True)
        assert result.returncode == 0 and result.stdout.startswith("messages 1 packages 1"), result.stdout
