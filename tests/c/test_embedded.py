"""The budgets of docs/c.md (`make bench-embedded`): the table is what scripts/bench_embedded.py
renders from its measurement, the measurement is of today's generated C and firmwares, and the
firmwares of examples/embedded do what they say (run here on the build machine's board). The
measurement itself, on the cross compilers, is in `make test-deep`."""
from __future__ import annotations

import json
import shutil
import struct
import subprocess
import sys

import pytest

from tests.c.harness_c import GEN, ROOT, STRICT
from tests.c.seeds import capture_stream, messages

sys.path.insert(0, str(ROOT / "scripts"))
import bench_embedded  # noqa: E402
import embedded_table  # noqa: E402

EXAMPLES = ROOT / "examples" / "embedded"


def measurements() -> dict:
    return json.loads(bench_embedded.MEASUREMENTS.read_text())


def test_the_doc_table_is_the_one_the_script_renders_from_its_measurement():
    table = embedded_table.table_of(embedded_table.DOC.read_text(encoding="utf-8"))
    assert table, "docs/c.md has no bench-embedded markers"
    assert table == embedded_table.render(measurements()), "run `make embedded-table`"


def test_the_measurement_is_of_todays_generated_c_and_firmwares():
    recorded = measurements()["inputs"]
    stale = sorted(set(recorded.items()) ^ set(bench_embedded.digests().items()))
    assert not stale, f"{sorted({name for name, _ in stale})} changed since: run `make bench-embedded`"


def bounded_or_refused(stack) -> bool:
    """A stack figure is a number of bytes (0 for a leaf that keeps all in registers), or the
    reason there is none (a cycle in the graph)."""
    return stack >= 0 if isinstance(stack, int) else stack.startswith("no bound: ")


def test_every_target_level_interface_and_firmware_is_measured():
    m = measurements()
    targets = [t.name for t in bench_embedded.TARGETS]
    interfaces = sorted(p.stem for p in GEN.glob("*.c"))
    assert list(m["parsers"]) == targets
    for target in targets:
        for level in bench_embedded.LEVELS:
            parsers = m["parsers"][target][level]
            assert sorted(parsers) == interfaces
            for name, figures in parsers.items():
                assert figures["flash"] > 0 and figures["ram"] >= 0
                assert figures["stack"], f"{name}: no public entry point measured"
                assert all(map(bounded_or_refused, figures["stack"].values()))
            for firmware in bench_embedded.FIRMWARES:
                figures = m["firmwares"][firmware.key][target][level]
                assert "skipped" in figures or figures["flash"] > figures["ram"] > 0
                assert "skipped" in figures or bounded_or_refused(figures["stack"])
    # The firmwares that need nothing more than the repository are built, everywhere.
    assert not any("skipped" in levels[level] for key in ("robot_states", "rtde_values")
                   for levels in m["firmwares"][key].values() for level in levels)


def test_every_goal_has_its_figure_and_mark():
    table = embedded_table.render(measurements())
    for _, _, limit, what in embedded_table.GOALS:
        [row] = [line for line in table.splitlines() if line.startswith(f"| {what} |")]
        assert row.endswith(("| pass |", "| over |", "| - |")), row
        assert f"| {limit:,} |" in row


def test_the_stack_bound_refuses_recursion(tmp_path):
    ci = tmp_path / "r.ci"
    ci.write_text('graph: { title: "r.c"\n'
                  'node: { title: "r.c:a" label: "a\\nr.c:1:1\\n16 bytes (static)" }\n'
                  'node: { title: "r.c:b" label: "b\\nr.c:2:1\\n32 bytes (static)" }\n'
                  'node: { title: "r.c:c" label: "c\\nr.c:3:1\\n8 bytes (static)" }\n'
                  'edge: { sourcename: "r.c:a" targetname: "r.c:b" }\n'
                  'edge: { sourcename: "r.c:a" targetname: "r.c:c" }\n'
                  'edge: { sourcename: "r.c:b" targetname: "memcpy" }\n'
                  'edge: { sourcename: "r.c:c" targetname: "r.c:a" }\n}\n')
    graph = bench_embedded.CallGraph()
    graph.add_ci(ci)
    assert graph.deepest("b") == (32, ["b"])
    with pytest.raises(bench_embedded.Recursion, match="a -> c -> a"):
        graph.deepest("a")
    ci.write_text(ci.read_text().replace('targetname: "r.c:a"', 'targetname: "r.c:b"'))
    graph = bench_embedded.CallGraph()
    graph.add_ci(ci)
    assert graph.deepest("a") == (16 + 8 + 32, ["a", "c", "b"])
    assert graph.unknown == {"memcpy"}


# What a C library's start code (newlib's crt0 on ARM, picolibc's on RISC-V) links, and a
# firmware started by examples/embedded/startup.c does not.
LIBC_START = {"_mainCRTStartup", "_cstart", "__libc_init_array", "exit", "atexit", "__call_exitprocs", "_set_tls"}


def symbols(target, elf) -> dict[str, int]:
    return {line.split()[2]: int(line.split()[0], 16)
            for line in bench_embedded.run(target.tool("nm"), str(elf)).splitlines() if len(line.split()) == 3}


def first_words(target, elf, n: int) -> list[int]:
    """The first n 32-bit words of flash (address 0), as the CPU reads them at reset."""
    out = elf.with_suffix(".bin")
    bench_embedded.run(target.tool("objcopy"), "-O", "binary", "-j", ".text", str(elf), str(out))
    data = out.read_bytes()[:4 * n]
    return list(struct.unpack(f"<{n}I", data))


@pytest.mark.parametrize("name", ["Cortex-M4F", "RV32IMC"])
def test_the_firmwares_start_from_their_own_reset_not_the_c_librarys(tmp_path, name):
    """bench-embedded's firmwares are linked as a device's: startup.c's vector table (ARM) or
    entry (RISC-V) at address 0, firmware.ld's stack, and none of the C library's start code."""
    [target] = [t for t in bench_embedded.TARGETS if t.name == name]
    if shutil.which(target.tool("gcc")) is None:
        pytest.skip(f"{target.tool('gcc')} not installed (scripts/setup.sh installs it)")
    [firmware] = [f for f in bench_embedded.FIRMWARES if f.key == "rtde_values"]
    figures = bench_embedded.measure_firmware(target, "-Os", firmware, {"generated": GEN}, tmp_path)
    assert "skipped" not in figures, figures
    elf = tmp_path / f"{firmware.key}.elf"
    names = symbols(target, elf)
    assert not LIBC_START & set(names), sorted(LIBC_START & set(names))
    if name == "RV32IMC":
        assert names["_start"] == 0
        return
    stack_pointer, reset = first_words(target, elf, 2)
    assert stack_pointer == names["__stack_top"] and stack_pointer % 8 == 0
    assert reset == names["Reset_Handler"] | 1  # a Thumb address


def host_firmware(tmp_path, key: str) -> str:
    [firmware] = [f for f in bench_embedded.FIRMWARES if f.key == key]
    exe = tmp_path / key
    sources = [EXAMPLES / s for s in firmware.sources] + [EXAMPLES / "board_host.c", GEN / firmware.library]
    build = subprocess.run(["gcc", *STRICT, "-O0", *firmware.defines, f"-I{GEN}", f"-I{EXAMPLES}", *map(str, sources),
                            "-o", str(exe)], capture_output=True, text=True)
    assert build.returncode == 0 and build.stderr == "", build.stderr
    return str(exe)


def test_the_robot_state_firmware_reads_every_robot_state_of_a_capture(tmp_path):
    sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python")]
    import urwire

    data = capture_stream(ROOT / "dissector" / "samples" / "primary_session.pcapng")
    run = subprocess.run([host_firmware(tmp_path, "robot_states")], input=data,
                         capture_output=True, timeout=60)
    assert run.returncode == 0
    values = [line.split() for line in run.stdout.decode().splitlines()]
    states = [r for m in messages(data) for r in urwire.decode_stream(m) if isinstance(r, urwire.RobotStateMessage)]
    assert [float(v) for name, v in values if name == "q_actual0"] == [
        s.package(urwire.JointData).joints[0].q_actual for s in states]
    assert [int(float(v)) for name, v in values if name == "malformed"] == [0] * len(states)
    assert values[:2] == [["major_version", "5"], ["minor_version", "11"]]


def test_the_rtde_firmware_reads_values_by_index_and_by_name(tmp_path):
    def message(code: int, body: bytes) -> bytes:
        return struct.pack(">HB", 3 + len(body), code) + body

    # What a robot answers the firmware's requests with (protocol 2, recipe 1 of its three
    # outputs, start), then two data packages of that recipe.
    robot = (message(ord("V"), b"\x01") + message(ord("O"), b"\x01DOUBLE,VECTOR6D,INT32") + message(ord("S"), b"\x01")
             + b"".join(message(ord("U"), b"\x01" + struct.pack(">d6di", 12.5 + i, 0.5 - i, -1.5, 1.5, -0.5, 0.25,
                                                                 3.0, 7)) for i in range(2)))
    run = subprocess.run([host_firmware(tmp_path, "rtde_values")], input=robot, capture_output=True,
                         timeout=60)
    assert run.returncode == 0
    assert run.stdout.decode().split() == ["double", "12.5", "actual_q0", "0.5", "robot_mode", "7",
                                           "double", "13.5", "actual_q0", "-0.5", "robot_mode", "7"]
    assert run.stderr.decode().splitlines() == ["sent 5 bytes, type 86", "sent 40 bytes, type 79",
                                                "sent 3 bytes, type 83"]


@pytest.mark.deep
def test_a_fresh_measurement_gives_the_committed_figures(tmp_path):
    pinned = tmp_path / "pinned"
    subprocess.run([sys.executable, "-m", "codegen", "--pin", "5.11", "--target", "c", "--out", str(pinned)],
                   cwd=ROOT, check=True)
    fresh = bench_embedded.measure(pinned / "c", measurements()["subset_selection"], 2)
    committed = measurements()
    assert fresh["toolchains"] == committed["toolchains"], "another compiler: figures differ by nature"
    assert fresh["parsers"] == committed["parsers"]
    assert fresh["firmwares"] == committed["firmwares"], "run `make bench-embedded`"
