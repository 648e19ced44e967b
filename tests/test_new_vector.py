"""scripts/new_vector.py (make new-vector): a new version's robot-state vectors start as copies of
the newest of its series with the Version message's numbers changed, and stay refused by the
golden loader until a person deletes their `TODO: check` lines."""
from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import urwire
from scripts.new_vector import ScaffoldError, scaffold
from tests.vectors import GOLDEN_DIR, UNCHECKED, VectorError, _load_yaml, parse_hex

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture
def golden(tmp_path) -> Path:
    for path in GOLDEN_DIR.glob("generation_*.yaml"):
        shutil.copy(path, tmp_path)
    return tmp_path


def checked(path: Path) -> dict:
    """What a maintainer does last: drop the marks, then the loader takes the file."""
    text = path.read_text(encoding="utf-8")
    head, description = text.split("\ndescription:", 1)
    assert all(line.startswith("# ") for line in head.splitlines())
    text = "description:" + description.replace(f"{UNCHECKED}: ", "", 1)
    path.write_text(text, encoding="utf-8")
    return _load_yaml(path)


def version_of(stream: bytes) -> tuple[int, int, int]:
    record = urwire.to_dict(next(iter(urwire.decode_stream(stream))))
    assert record["type"] == "version"
    return record["major_version"], record["minor_version"], record.get("bugfix_version", 0)


def test_the_newest_of_the_series_with_the_new_versions_numbers_only(golden):
    [written] = scaffold("5.27", golden)
    assert written.name == "generation_eseries_5_27_robot_state.yaml"
    source = golden / "generation_eseries_5_25_1_robot_state.yaml"
    with pytest.raises(VectorError, match="TODO: check"):
        _load_yaml(written)
    doc, old = checked(written), _load_yaml(source)
    new_bytes, old_bytes = parse_hex(doc["hex"], written), parse_hex(old["hex"], source)
    assert version_of(new_bytes) == (5, 27, 0) and version_of(old_bytes) == (5, 25, 1)
    # Same length, and only the minor (byte 26) and bugfix (bytes 27-30) numbers differ.
    assert len(new_bytes) == len(old_bytes)
    assert [i for i, (a, b) in enumerate(zip(new_bytes, old_bytes)) if a != b] == [26, 30]
    assert doc["expect"][0] | {"minor_version": 25, "bugfix_version": 1} == old["expect"][0]
    assert doc["expect"][1:] == old["expect"][1:]
    assert doc["also_without_version_message"] is True


def test_every_variant_of_the_newest_version_and_a_bugfix_number(golden):
    written = scaffold("3.12.2", golden)
    assert sorted(p.name for p in written) == ["generation_cb3_3_12_2_robot_state.yaml",
                                                "generation_cb3_3_12_2_robot_state_euromap67.yaml"]
    for path in written:
        assert version_of(parse_hex(checked(path)["hex"], path)) == (3, 12, 2)


def test_a_named_source(golden):
    [written] = scaffold("5.27", golden, source=golden / "generation_eseries_5_11_robot_state.yaml")
    assert "generation_eseries_5_11_robot_state.yaml" in written.read_text(encoding="utf-8")


@pytest.mark.parametrize("version, why", [
    ("3.16", "in no series"),                              # between CB3 and the e-Series
    ("5.2", "no generation_.* vector of e-Series older than 5.2: name one with --from"),
    ("1.8.1", "no '# bugfix_version = ' line"),            # the svn-form Version message of 1.8
])
def test_refused_with_the_reason(golden, version, why):
    before = sorted(golden.iterdir())
    with pytest.raises(ScaffoldError, match=why):
        scaffold(version, golden)
    assert sorted(golden.iterdir()) == before


def test_nothing_is_overwritten(golden):
    [written] = scaffold("5.27", golden)
    written.write_text("mine", encoding="utf-8")
    with pytest.raises(ScaffoldError, match="already there"):
        scaffold("5.27", golden)
    assert written.read_text(encoding="utf-8") == "mine"


def test_the_command_says_what_it_wrote_and_refuses_a_bad_version(golden):
    run = [sys.executable, str(ROOT / "scripts" / "new_vector.py"), "--golden", str(golden)]
    done = subprocess.run(run + ["10.8"], capture_output=True, text=True, check=True)
    assert "generation_polyscope_x_10_8_robot_state.yaml: to check by hand" in done.stdout
    bad = subprocess.run(run + ["5.x"], capture_output=True, text=True)
    assert bad.returncode == 2 and "major.minor" in bad.stderr
