"""build/urwire-decode as docs/contract.md#what-every-target-keeps says: FILE or -,
--version-hint, exit codes 0/1/2 with a one-line stderr message for usage and I/O errors."""
from __future__ import annotations

import subprocess

import pytest

from tests.c.harness_c import parse_lines, run_cli
from tests.vectors import all_cases

CASES = {c.name: c for c in all_cases()}


def test_file_and_stdin_give_the_same_records(fast, tmp_path):
    case = CASES["stream_several_messages"]
    path = tmp_path / "s.bin"
    path.write_bytes(case.data)
    by_file = subprocess.run([str(fast.cli), str(path)], capture_output=True)
    assert by_file.returncode == 0
    assert by_file.stdout == run_cli(fast, case.data).stdout
    assert len(parse_lines(by_file.stdout)) == len(case.expect)


def test_error_records_exit_1(fast):
    result = run_cli(fast, CASES["stream_fault_truncated_message"].data)
    assert result.returncode == 1
    assert parse_lines(result.stdout)[-1]["type"] == "error"


def test_version_hint_chooses_the_value_table(fast):
    data = CASES["global_variables_update_doc_example_5_0"].data
    under_5_9 = parse_lines(run_cli(fast, data).stdout)
    under_5_0 = parse_lines(run_cli(fast, data, "--version-hint", "5.0").stdout)
    assert under_5_9 != under_5_0
    assert under_5_0 == parse_lines(run_cli(fast, data, "--version-hint=5.0").stdout)


def test_help_states_the_default_version(fast):
    result = subprocess.run([str(fast.cli), "--help"], capture_output=True, text=True)
    assert result.returncode == 0
    assert "5.9" in result.stdout and "default" in result.stdout


@pytest.mark.parametrize("args", [[], ["/no/such/file"], ["--version-hint", "five", "-"], ["--version-hint"],
                                  ["--frobnicate", "-"], ["a", "b"], ["--version-hint", "5", "-"]])
def test_usage_and_io_errors_exit_2_with_one_line(fast, args):
    result = subprocess.run([str(fast.cli), *args], input="", capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stdout == ""
    assert len(result.stderr.splitlines()) == 1 and result.stderr.startswith("urwire-decode: ")


def test_a_directory_is_an_io_error(fast, tmp_path):
    result = subprocess.run([str(fast.cli), str(tmp_path)], capture_output=True, text=True)
    assert result.returncode == 2
    assert len(result.stderr.splitlines()) == 1


def test_the_bundled_capture_decodes_as_in_python(fast, tmp_path):
    """The robot->client stream of dissector/samples/primary_session.pcapng (what `make demo-c`
    shows): the C CLI prints what the Python decoder prints for the capture itself."""
    import urwire
    from tests.c.harness_c import ROOT

    pcap = ROOT / "dissector" / "samples" / "primary_session.pcapng"
    if not pcap.is_file():
        pytest.fail(f"{pcap} is missing (the Lua target bundles it)")
    raw = tmp_path / "primary.bin"
    subprocess.run(["python3", str(ROOT / "tests" / "c" / "seeds.py"), "--capture", str(pcap), str(raw)], check=True)
    result = subprocess.run([str(fast.cli), str(raw)], capture_output=True)
    expected = [urwire.to_dict(r) for r in urwire.decode_file(pcap)]
    assert len(expected) > 10
    assert parse_lines(result.stdout) == expected


def test_recurring_packages_are_written_as_python_writes_them(fast):
    """The command keeps the text of each sub-package type and writes it again while the type,
    version and body recur. Every generation's robot states come twice, then the same bytes
    under every other version's Version message; a malformed package, whose error names its
    offset in the message, comes at two offsets. Each line must be Python's."""
    import random
    import struct

    import urwire
    from tests.tools import valid

    def state(*packages: bytes) -> bytes:
        body = b"".join(packages)
        return struct.pack(">iB", 5 + len(body), 16) + body

    rng = random.Random(11)
    states = []
    for version in valid.versions():
        made = [m for m in (valid.message(rng, version) for _ in range(60)) if m[4] == 16]
        states += made[:3]
    short_cartesian = struct.pack(">iB", 15, 4) + bytes(range(10))
    data = state(short_cartesian) + state(struct.pack(">iB", 7, 20) + b"\x01\x02", short_cartesian)
    for version in valid.versions():
        data += valid.version_message(rng, version) + b"".join(m + m for m in states)
    result = run_cli(fast, data)
    expected = [urwire.to_json_line(r) for r in urwire.decode_stream(data)]
    assert len(expected) > 1000
    assert result.stdout.decode().splitlines() == expected
    assert expected[0] != expected[1].replace('{"type": "unknown", "package_type": 20, "raw": "0102"}, ', "")
