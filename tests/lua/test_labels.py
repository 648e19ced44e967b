"""What a Wireshark user reads: every tree item is labelled in words, physical values carry their
unit, descriptions come from the spec, and the filter names and enum names stay the spec's."""
from __future__ import annotations

import re
import subprocess

from tests.lua.harness import PLUGIN, ROOT, run_tshark, write_sessions
from tests.vectors import golden_cases

SAMPLES = [ROOT / "dissector" / "samples" / name for name in ("primary_session.pcapng", "secondary_session.pcap")]
SNAKE = re.compile(r"\b[a-z][a-z0-9]*_[a-z0-9_]+\b")
BITS = re.compile(r"^[.01 ]+ = ")


def ur_labels(text: str) -> list[str]:
    """The label of every line of the UR trees in `tshark -V` output: the text before ': ', or
    the whole line of a subtree ("Joint 0"), without a bit field's picture."""
    labels, inside = [], False
    for line in text.splitlines():
        if not line.startswith(" "):
            inside = line.startswith("Universal Robots")
            continue
        if inside:
            item = BITS.sub("", line.strip()).strip("[]")
            labels.append(item.split(": ", 1)[0])
    return labels


def test_no_tree_item_is_labelled_with_a_snake_case_name():
    for sample, distinct in zip(SAMPLES, (190, 130)):
        labels = ur_labels(run_tshark(sample, "-V"))
        assert len(set(labels)) > distinct, sample   # robot states, robot messages, program states
        snake = sorted({label for label in labels if SNAKE.search(label)})
        assert not snake, f"{sample.name}: {snake[:20]}"


def test_physical_values_carry_their_unit():
    text = run_tshark(SAMPLES[0], "-O", "ur", "-Y", "ur.joint_data")
    for label, unit in (("Actual joint position", "rad"), ("Actual joint velocity", "rad/s"),
                        ("Actual joint current", "A"), ("Actual joint voltage", "V"),
                        ("Motor temperature", "°C"), ("TCP position X", "m"), ("Force Z", "N"),
                        ("Tool output voltage", "V")):
        values = re.findall(rf"^\s+{re.escape(label)}: (\S+) (\S+)$", text, re.M)
        assert values, label
        assert {u for _, u in values} == {unit}, (label, set(values))
        float(values[0][0])
    assert re.search(r"^\s+Robot mode: RUNNING \(7\)$", text, re.M), "enum value strings stay as they are"


def test_filter_names_and_field_values_stay_the_spec_names():
    fields = run_tshark(SAMPLES[0], "-Y", "ur.joint_data.q_actual > 1.5", "-T", "fields",
                        "-e", "ur.joint_data.q_actual", "-e", "ur.robot_mode_data.robot_mode")
    first = fields.splitlines()[0].split("\t")
    assert all(float(v) == float(v) for v in first[0].split(",")), "plain numbers, no unit"
    assert first[1] in ("7", "5")


def test_descriptions_come_from_the_spec():
    out = subprocess.run(["tshark", "-G", "fields", "-X", f"lua_script:{PLUGIN}"], capture_output=True,
                         text=True, check=True).stdout
    rows = {cols[2]: cols for cols in (line.split("\t") for line in out.splitlines())
            if len(cols) > 7 and cols[2].startswith("ur.")}
    q = rows["ur.joint_data.q_actual"]
    assert q[1] == "Actual joint position" and q[7] == "Measured angle of the joint. In rad."
    assert rows["ur.robot_mode_data.speed_scaling"][7] == "Speed scaling. Sent by software 3.0 and later."
    assert rows["ur.masterboard_data.digital_input_bits"][7].startswith("Bits 0-7 standard")
    assert rows["ur.masterboard_data.digital_input_bits.tool_1"][1] == "Tool 1"
    assert not [name for name, cols in rows.items() if SNAKE.search(cols[1])]


def test_undocumented_parts_are_named_and_marked():
    # Sub-package 14 of the bundled 5.11 capture: named, marked, its fields filterable with units.
    text = run_tshark(SAMPLES[0], "-O", "ur", "-Y", "ur.payload_info.mass == 1", "-c", "8")
    assert re.search(r"^\s+Payload info \(undocumented, inferred\)$", text, re.M)
    assert re.search(r"^\s+Payload mass: 1 kg$", text, re.M)
    assert re.search(r"^\s+Payload inertia: 0\.001539 kg·m²$", text, re.M)
    assert "Unknown package" not in text


def test_undocumented_messages_are_named_in_the_info_column(tmp_path):
    # The stream a real CB3 3.10 opens with: Version, robot message 12, message type 24; then
    # types 5, 22 and 23 (the golden vectors' bytes, each whole message in a segment of its own).
    cases = {c.name: c for c in golden_cases()}
    data = cases["safety_compliance_tolerances_cb3_3_10"].data + cases["undocumented_message_types"].data
    pcap = write_sessions(tmp_path / "undocumented.pcap", [[data]])
    info = run_tshark(pcap, "-Y", "ur", "-T", "fields", "-e", "_ws.col.Info").strip()
    assert info == ("Version: URControl 3.10.0.0; Robot message 12 (undocumented); "
                    "Safety compliance tolerances (undocumented, inferred); Modbus info (undocumented); "
                    "HMC (undocumented); Safety setup broadcast (undocumented); Type 255 (DISCONNECT); Text: still in sync")
    fields = run_tshark(pcap, "-Y", "ur", "-T", "fields", "-E", "aggregator=;",
                        "-e", "ur.safety_compliance_tolerances.tolerances", "-e", "ur.modbus_info.raw").strip()
    tolerances, modbus = fields.split("\t")
    assert [float(v) for v in tolerances.split(";")][:4] == [0.15, 25.0, 0.0, 3.0]
    assert modbus.replace(":", "") == "00000000"
