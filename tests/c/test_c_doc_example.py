"""docs/c.md opens with a complete program: it compiles as it stands there, with gcc and clang under
the project's strict flags against generated/c alone, and on the stream `urwire streams` writes
from the bundled capture it prints what the Python decoder reads and what the doc shows."""
from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from tests.c.harness_c import GEN, ROOT, STRICT
from tests.c.seeds import messages

DOC = ROOT / "docs" / "c.md"
CAPTURE = ROOT / "dissector" / "samples" / "primary_session.pcapng"
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))


def blocks(language: str) -> list[str]:
    return re.findall(rf"^```{language}\n(.*?)^```", DOC.read_text(encoding="utf-8"), re.S | re.M)


@pytest.fixture(scope="module")
def stream(tmp_path_factory):
    """The file the doc's commands run the program on, written by the command the doc names."""
    [commands] = blocks("sh")[:1]
    streams = tmp_path_factory.mktemp("streams")
    result = subprocess.run([sys.executable, "-m", "urwire", "streams", str(CAPTURE), str(streams / "streams")],
                            capture_output=True, text=True, env=ENV, cwd=streams, timeout=300)
    assert result.returncode == 0, result.stderr
    [run] = [line for line in commands.splitlines() if line.startswith("./first ")]
    return streams / run.split()[1]


def expected(stream) -> list[str]:
    """What the program prints, from the Python decoder."""
    sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python")]
    import urwire

    data = stream.read_bytes()
    framed = messages(data)
    assert sum(map(len, framed)) == len(data), "the stream is whole: no fault to print"
    lines, offset, states = [], 0, 0
    for message in framed:
        [record] = list(urwire.decode_stream(message))
        if isinstance(record, urwire.VersionMessage):
            lines.append(f"controller {record.major_version}.{record.minor_version}.{record.bugfix_version}")
        elif isinstance(record, urwire.RobotStateMessage):
            states += 1
            q = record.package(urwire.JointData).joints[0].q_actual
            mode = record.package(urwire.RobotModeData).robot_mode.name
            lines.append(f"robot state at byte {offset}: {mode}, base joint at {q:.4f} rad")
        offset += len(message)
    return lines + [f"{states} robot states, 0 faults"]


def test_the_doc_opens_with_the_program():
    text = DOC.read_text(encoding="utf-8")
    assert text.index("```c\n") < text.index("\n## ", text.index("## A first program") + 1)
    assert "int main(" in blocks("c")[0]


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_the_doc_program_compiles_as_written_and_prints_what_python_reads(cc, tmp_path, stream):
    source = tmp_path / "first.c"
    source.write_text(blocks("c")[0])
    exe = tmp_path / "first"
    build = subprocess.run([cc, *STRICT, "-O0", f"-I{GEN}", str(source), str(GEN / "urwire.c"), "-o", str(exe)],
                           capture_output=True, text=True)
    assert build.returncode == 0 and build.stderr == "", build.stderr
    result = subprocess.run([str(exe), str(stream)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    printed = result.stdout.splitlines()
    assert printed == expected(stream)
    # The output the doc shows: its first lines, then "...", then its last.
    shown = blocks("text")[0].splitlines()
    cut = shown.index("...")
    assert printed[:cut] == shown[:cut] and printed[len(printed) - (len(shown) - cut - 1):] == shown[cut + 1:]
