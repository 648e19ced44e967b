"""`pip install .` gives the urwire package and command; the bindings need no third-party module."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


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
