"""`pip install .` and `pip install -e .` give the urwire package and command, from python/urwire
and its generated subpackage; the bindings need no third-party module."""
from __future__ import annotations

import json
import os
import site
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "dissector" / "samples" / "primary_session.pcapng"


def test_bindings_import_nothing_from_outside_the_standard_library():
    code = (
        "import sys, urwire\n"
        "data = bytes.fromhex('0000001c140000000000000000fe030255520518000000000000002a')\n"
        "assert [urwire.to_json_line(r) for r in urwire.decode_stream(data)]\n"
        "third = {m.split('.')[0] for m in sys.modules} & {'dpkt', 'tqdm', 'yaml', 'jinja2', 'numpy'}\n"
        "assert not third, third\n"
    )
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
    subprocess.run([sys.executable, "-c", code], check=True, env=env)


@pytest.mark.deep          # a whole pip install, about a minute: `make test-deep`
def test_pip_install_gives_the_package_its_types_and_command(tmp_path):
    target = tmp_path / "site"
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps",
                    "--target", str(target), str(ROOT)], check=True, capture_output=True)
    assert (target / "urwire" / "py.typed").exists()
    assert (target / "urwire" / "generated" / "messages.py").exists()
    assert (target / "bin" / "urwire").exists()
    env = dict(os.environ, PYTHONPATH=str(target))
    out = subprocess.run([sys.executable, str(target / "bin" / "urwire"), "--version"], env=env,
                         capture_output=True, text=True, check=True)
    assert out.stdout.startswith("urwire ")


def test_every_attribute_carries_its_label_and_unit():
    """dataclasses.field(metadata=...) holds the spec's label and unit, for code that shows
    records to people; the canonical JSON keys stay the spec's names."""
    import dataclasses

    import urwire
    from urwire.generated import messages

    meta = {f.name: f.metadata for f in dataclasses.fields(messages.Joint)}
    assert meta["q_actual"] == {"label": "Actual joint position", "unit": "rad"}
    assert meta["t_motor"] == {"label": "Motor temperature", "unit": "°C"}
    assert meta["joint_mode"] == {"label": "Joint mode", "unit": None}
    assert messages.Joint.LABEL == "Joint" and messages.RobotModeData.LABEL == "Robot mode data"
    classes = [c for c in vars(messages).values() if isinstance(c, type) and dataclasses.is_dataclass(c)
               and hasattr(c, "JSON")]
    assert len(classes) > 20
    for cls in classes:
        for f in dataclasses.fields(cls):
            if f.name in {n for n, _, _ in cls.JSON}:
                assert f.metadata["label"] and "_" not in f.metadata["label"], (cls.__name__, f.name)
    data = bytes.fromhex("0000001c140000000000000000fe030255520518000000000000002a")
    (record,) = urwire.decode_stream(data)
    assert "project_name" in urwire.to_dict(record) and "Project name" not in urwire.to_json_line(record)


def source_copy(dest: Path) -> Path:
    """What packaging reads, copied out of the tree: pyproject.toml, README.md, the hand-written
    package and the generated subpackage (nothing else may be needed to install)."""
    dest.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, dest / name)
    shutil.copytree(ROOT / "python", dest / "python", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(ROOT / "generated" / "python", dest / "generated" / "python",
                    ignore=shutil.ignore_patterns("__pycache__"))
    return dest


# What `pip install --no-build-isolation` builds with: setuptools from 70.1 on, or from 68 with wheel.
CAN_BUILD = ("import sys, setuptools; from importlib.util import find_spec; "
             "v = tuple(int(x) for x in setuptools.__version__.split('.')[:2]); "
             "sys.exit(0 if v >= (70, 1) or (v >= (68, 0) and find_spec('wheel')) else 1)")


def fresh_venv(path: Path) -> Path:
    """A venv that sees the system's packages (dpkt, tqdm, pip), with the build requirements of
    pyproject.toml (requirements-dev.txt installs them; else they are installed into the venv);
    its python."""
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(path)], check=True)
    python = path / "bin" / "python"
    if sys.prefix != sys.base_prefix:
        # Run from a venv (make test-python-range), the packages are in that venv's site-packages,
        # which --system-site-packages does not reach: list them after the new venv's own.
        own = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
                             capture_output=True, text=True, check=True).stdout.strip()
        Path(own, "outer-venv.pth").write_text("\n".join(site.getsitepackages()) + "\n")
    if subprocess.run([str(python), "-c", CAN_BUILD]).returncode != 0:
        subprocess.run([str(python), "-m", "pip", "install", "-q", "setuptools>=68", "wheel"], check=True,
                       capture_output=True)
    return python


# The editable install is strict (a tree of links in the copy's build/): setuptools' default one
# imports through a finder it appends after the path finder, so a urwire installed as a plain
# package in the system's site-packages (scripts/setup.sh runs `pip install .`) would win.
@pytest.mark.parametrize("how", [[], ["--config-settings", "editable_mode=strict", "-e"]],
                         ids=["pip install .", "pip install -e ."])
def test_installed_package_decodes_a_sample_from_outside_the_tree(tmp_path, how):
    source = source_copy(tmp_path / "src")
    python = fresh_venv(tmp_path / "venv")
    pip = subprocess.run([str(python), "-m", "pip", "install", "-q", "--no-deps", "--no-build-isolation", *how,
                          str(source)], capture_output=True, text=True, cwd=tmp_path)
    assert pip.returncode == 0, pip.stdout[-2000:] + pip.stderr[-2000:]
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    where = subprocess.run([str(python), "-c", "import urwire, urwire.generated.messages as m, urwire.cli as c; "
                            "print(urwire.__file__); print(m.__file__); print(c.__file__)"],
                           cwd=elsewhere, env=env, capture_output=True, text=True, check=True).stdout.split()
    installed = (tmp_path / "venv") if not how else source
    for path in where:
        assert Path(path).resolve().is_relative_to(installed.resolve()), (how, where)
    out = subprocess.run([str(tmp_path / "venv" / "bin" / "urwire"), "decode", str(SAMPLE)], cwd=elsewhere,
                         env=env, capture_output=True, text=True, check=True).stdout.splitlines()
    records = [json.loads(line) for line in out]
    assert records[0]["type"] == "version" and records[0]["major_version"] == 5
    assert sum(r["type"] == "robot_state" for r in records) > 10


def test_in_the_tree_the_package_joins_the_generated_folder_and_no_other_install(tmp_path):
    """With python/ and generated/python/ on sys.path, urwire's path is exactly their two urwire
    folders: a urwire installed elsewhere on the path (a folder with its own __init__.py) adds
    no module to it."""
    other = tmp_path / "other" / "urwire"
    other.mkdir(parents=True)
    (other / "__init__.py").write_text("")
    (other / "stale.py").write_text("")
    path = [ROOT / "python", ROOT / "generated" / "python", tmp_path / "other"]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(map(str, path)))
    out = subprocess.run([sys.executable, "-c", "import importlib.util, urwire, urwire.generated; "
                          "print(urwire.__path__); print(importlib.util.find_spec('urwire.stale'))"],
                         cwd=tmp_path, env=env, capture_output=True, text=True, check=True).stdout.splitlines()
    assert out[0] == str([str(ROOT / "python" / "urwire"), str(ROOT / "generated" / "python" / "urwire")])
    assert out[1] == "None"
