"""`urwire-decode --protocol NAME FILE --to-robot FILE2`: the C command reads a connection's two
streams (the client's first) and prints exactly what `urwire decode` prints of the same two files,
with the same exit status: every RTDE golden exchange (a data package is read with the recipe the
client's stream set up), every golden conversation of the dashboard and the driver's sockets, and
hostile bytes in either file; under gcc and ASan/UBSan. A protocol that reads one direction refuses
--to-robot."""
from __future__ import annotations

import contextlib
import io
import random
import subprocess

import pytest

from tests.c.harness_c import CLI, INCLUDES, OUT, RUNTIME_SOURCES, STRICT, get_build
from tests.interface_vectors import conversation_cases
from tests.rtde_vectors import rtde_cases
from urwire.cli import main as python_main
from urwire.interfaces import INTERFACES

BOTH_DIRECTIONS = sorted(name for name, i in INTERFACES.items() if i.both_directions)
ONE_DIRECTION = sorted(name for name, i in INTERFACES.items() if not i.both_directions)
VARIANTS = ("gcc", "asan-gcc")


def golden_cases() -> list[tuple[str, str, bytes, bytes, str | None]]:
    """(interface, case, robot's bytes, client's bytes, version hint) of every two-way vector."""
    cases = [("rtde", c.name, c.robot_bytes, c.client_bytes, None) for c in rtde_cases()]
    for name in BOTH_DIRECTIONS:
        if name == "rtde":
            continue
        for c in conversation_cases(name):
            robot = b"".join(s.data for s in c.segments if s.from_robot)
            client = b"".join(s.data for s in c.segments if not s.from_robot)
            cases.append((name, c.name, robot, client, c.version))
    return cases


CASES = golden_cases()


def python_output(args: list[str]) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        status = python_main(["decode", "--no-progress", *args])
    return status, out.getvalue()


def c_output(variant: str, args: list[str]) -> tuple[int, str]:
    res = subprocess.run([str(get_build(variant).cli), *args], capture_output=True, timeout=60)
    assert res.returncode == 2 or res.stderr == b"", res.stderr.decode(errors="replace")
    return res.returncode, res.stdout.decode("utf-8")


def both_files(tmp_path, robot: bytes, client: bytes) -> tuple[str, str]:
    robot_file, client_file = tmp_path / "from_robot.bin", tmp_path / "to_robot.bin"
    robot_file.write_bytes(robot)
    client_file.write_bytes(client)
    return str(robot_file), str(client_file)


def test_every_two_way_interface_has_golden_conversations():
    assert {name for name, *_ in CASES} == set(BOTH_DIRECTIONS)
    # Both directions matter: RTDE data packages whose recipes only the client's stream sets up.
    assert any(name == "rtde" and client and b'"actual_q"' not in robot for name, _, robot, client, _ in CASES)


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("name,case,robot,client,hint", CASES, ids=[f"{c[0]}/{c[1]}" for c in CASES])
def test_two_files_print_what_python_prints(tmp_path, variant, name, case, robot, client, hint):
    robot_file, client_file = both_files(tmp_path, robot, client)
    args = ["--protocol", name, *(["--version-hint", hint] if hint else []), robot_file, "--to-robot", client_file]
    python = python_output(args)
    assert c_output(variant, args) == python
    assert f'"direction": "from_robot", "conversation": "{robot_file}"' in python[1] or not robot


def test_rtde_data_packages_take_the_recipe_of_the_clients_stream(tmp_path):
    """With the client's stream, the data packages that arrive during a setup are read with their
    recipes; from the robot's stream alone the same packages are kept whole with an error."""
    case = next(c for c in rtde_cases() if c.name == "data_during_setup")
    robot_file, client_file = both_files(tmp_path, case.robot_bytes, case.client_bytes)
    both = c_output("asan-gcc", ["--protocol", "rtde", robot_file, "--to-robot", client_file])
    alone = c_output("asan-gcc", ["--protocol", "rtde", robot_file])
    assert alone[1].count("did not set up") == 2
    assert both[0] == 0 and "error" not in both[1]
    packages = [line for line in both[1].splitlines() if '"type": "data_package"' in line]
    assert len(packages) == 2
    assert '"recipe_id": 1, "actual_q": [1.0, 2.0, 3.0, 0.5, 0.25, 0.0]' in packages[0]
    assert '"recipe_id": 2, "timestamp": 12.5' in packages[1]
    assert all(line.startswith('{"interface": "rtde", "direction": "from_robot"') for line in packages)


def hostile(rng: random.Random, golden: bytes) -> bytes:
    """Random bytes, or a golden stream cut, flipped or with bytes spliced in."""
    kind = rng.randrange(4)
    if kind == 0 or not golden:
        return rng.randbytes(rng.randrange(0, 300))
    data = bytearray(golden)
    if kind == 1:
        return bytes(data[:rng.randrange(len(data) + 1)])
    if kind == 2:
        for _ in range(rng.randrange(1, 8)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        return bytes(data)
    at = rng.randrange(len(data) + 1)
    return bytes(data[:at] + rng.randbytes(rng.randrange(1, 40)) + data[at:])


@pytest.mark.parametrize("name", BOTH_DIRECTIONS)
def test_hostile_bytes_in_either_file_print_what_python_prints(tmp_path, name):
    rng = random.Random(f"to-robot {name}")
    goldens = [(robot, client, hint) for n, _, robot, client, hint in CASES if n == name]
    for trial in range(30):
        robot, client, hint = rng.choice(goldens)
        if trial % 3 != 1:
            client = hostile(rng, client)
        if trial % 3 != 0:
            robot = hostile(rng, robot)
        robot_file, client_file = both_files(tmp_path, robot, client)
        args = ["--protocol", name, *(["--version-hint", hint] if hint else []), robot_file, "--to-robot", client_file]
        assert c_output("asan-gcc", args) == python_output(args), (trial, robot.hex(), client.hex())


@pytest.mark.parametrize("name", ONE_DIRECTION)
def test_a_protocol_that_reads_one_direction_refuses_to_robot(tmp_path, name):
    robot_file, client_file = both_files(tmp_path, b"", b"")
    res = subprocess.run([str(get_build("gcc").cli), "--protocol", name, robot_file, "--to-robot", client_file],
                         capture_output=True, text=True, timeout=60)
    assert res.returncode == 2 and res.stdout == ""
    assert f"--to-robot: {name} reads the robot's stream only" in res.stderr
    assert sorted(res.stderr.partition("read both directions:")[2].split()) == BOTH_DIRECTIONS


def test_an_unreadable_client_file_is_an_io_error(tmp_path):
    robot_file, _ = both_files(tmp_path, b"", b"")
    missing = str(tmp_path / "missing.bin")
    res = subprocess.run([str(get_build("gcc").cli), "--protocol", "rtde", robot_file, "--to-robot", missing],
                         capture_output=True, text=True, timeout=60)
    assert (res.returncode, res.stdout) == (2, "")
    assert missing in res.stderr and "No such file" in res.stderr
    assert python_output(["--protocol", "rtde", robot_file, "--to-robot", missing])[0] == 2


def test_file_names_are_json_texts_as_python_writes_them(tmp_path):
    """The envelope's conversation is the file's name as given, quoted and non-ASCII included."""
    case = next(c for c in rtde_cases() if c.name == "protocol1_session")
    folder = tmp_path / 'a "quoted" dir \\ é'
    folder.mkdir()
    robot_file, client_file = both_files(folder, case.robot_bytes, case.client_bytes)
    args = ["--protocol", "rtde", robot_file, "--to-robot", client_file]
    python = python_output(args)
    assert '\\"quoted\\"' in python[1] and "é" in python[1]
    assert c_output("asan-gcc", args) == python


def test_the_commands_decoding_references_no_malloc(tmp_path):
    """What the command links beside main.c (the streams, the envelopes, the JSON writers) reads
    both files through static state: no malloc, calloc, realloc or free in its objects. The capture
    reader (runtime/c/capture, and the command's capture_json.c over it) is apart: it holds a
    framer per conversation and out-of-order segments, on the heap, bounded as capture.h says."""
    folder = OUT / "to_robot_nm"
    folder.mkdir(parents=True, exist_ok=True)
    for source in [*sorted(CLI.glob("*.c")), *RUNTIME_SOURCES]:
        if source.parent.name == "capture" or source.stem == "capture_json":
            continue
        obj = folder / f"{source.stem}.o"
        subprocess.run(["gcc", *STRICT, "-O2", *(f"-I{d}" for d in INCLUDES), "-c", str(source), "-o", str(obj)],
                       check=True)
        undefined = subprocess.run(["nm", "-u", str(obj)], capture_output=True, text=True, check=True).stdout.split()
        assert not {"malloc", "calloc", "realloc", "free", "strdup"} & set(undefined), source.name
