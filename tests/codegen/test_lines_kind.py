"""The kind `lines` (spec/ur_dashboard.yaml): its spec errors name their YAML path and line, and
the plan tries longer command texts first."""
from __future__ import annotations

import pytest

from codegen.compile import SPEC_DIR, compile_text
from codegen.errors import SpecError
from codegen.kinds.lines.plan import plan
from codegen.kinds.lines.resolve import pattern_pieces

SPEC = (SPEC_DIR / "ur_dashboard.yaml").read_text(encoding="utf-8")


def problems(text: str) -> list:
    with pytest.raises(SpecError) as caught:
        compile_text(text, "probe.yaml")
    return caught.value.problems


def test_the_dashboard_spec_compiles_and_tries_longest_texts_first():
    planned = plan(compile_text(SPEC))
    texts = [c.command.text for c in planned.lookup]
    assert texts.index("load installation") < texts.index("load")
    assert texts.index("close safety popup") < texts.index("close popup")
    assert planned.version_command.command.name == "polyscope_version"


def test_pattern_pieces_split_at_placeholders():
    assert pattern_pieces("Loading program: <program>") == ("Loading program: ", "")
    assert pattern_pieces("could not understand: '<command>'") == ("could not understand: '", "'")
    assert pattern_pieces("Stopped") == ("Stopped",)


def test_a_duplicate_command_is_named_at_its_path():
    text = SPEC.replace("  - name: play\n    text: play\n", "  - name: load\n    text: play\n")
    (problem,) = problems(text)
    assert problem.path == "commands[1].name" and "duplicate command name load" in problem.message
    assert problem.line == SPEC.splitlines().index("  - name: play") + 1


def test_a_stray_angle_bracket_and_a_series_mismatch_are_both_reported():
    text = SPEC.replace('"Starting program"', '"Starting <program"').replace(
        'since: {cb: "1.4", e_series: "5.0"}\n    doc: Start', 'since: {cb: "5.1", e_series: "3.0"}\n    doc: Start')
    found = {p.path: p.message for p in problems(text)}
    assert "'<' and '>'" in found["commands[1].replies[0].pattern"]
    assert "not a CB-series version" in found["commands[1].since.cb"]
    assert "not an e-Series version" in found["commands[1].since.e_series"]


def test_the_version_reply_names_a_known_command():
    (problem,) = problems(SPEC.replace("command: polyscope_version", "command: polyscope"))
    assert problem.path == "framing.version_reply.command" and "unknown command" in problem.message


def test_the_schema_refuses_a_command_without_replies():
    text = SPEC.replace("""    replies:
      - {name: log_saved, pattern: "Log saved to disk"}
""", "")
    (problem,) = problems(text)
    assert problem.path.startswith("commands[") and "replies" in problem.message


def test_what_the_simulated_robot_answers_is_resolved_from_the_spec():
    commands = {c.name: c for c in compile_text(SPEC).commands}
    assert commands["play"].effect == "play" and commands["robotmode"].effect is None
    # A placeholder named as the argument takes the argument, unless the reply's fill says otherwise.
    assert [r.fill for r in commands["load"].replies] == ["{argument}"] * 3
    assert commands["set_operational_mode"].replies[0].fill == "'{argument}'"
    assert commands["program_state"].replies[1].when == (("program_state", "PLAYING"),)


def test_an_unknown_effect_or_robot_state_and_a_misplaced_fill_are_named_at_their_paths():
    text = (SPEC.replace("effect: play\n", "effect: dance\n")
            .replace('fill: "{robot_mode}"', 'fill: "{robot_mood}"')
            .replace('fill: "{program_running}"', 'fill: "{argument}"')
            .replace('{name: stopped, pattern: "Stopped"}', '{name: stopped, pattern: "Stopped", fill: "x"}')
            .replace("when: {program_state: PAUSED}", "when: {program_phase: PAUSED}")
            .replace('fill: "{serial_number}"', 'fill: "{serial_number"')
            .replace("    error: true\n    doc: The server", "    error: true\n    fill: x\n    doc: The server"))
    found = {p.path: p.message for p in problems(text)}
    assert "unknown effect 'dance'" in found["commands[1].effect"]
    robotmode = next(k for k, v in found.items() if "robot_mood" in v)
    assert robotmode.endswith("replies[0].fill") and "one of argument, program_state" in found[robotmode]
    assert any("takes no argument" in v for v in found.values())
    assert "the pattern has 0" in found["commands[2].replies[0].fill"]
    assert any(k.endswith("when.program_phase") for k in found)
    assert any("'{' and '}'" in v for v in found.values())
    assert "only a command's reply" in found["common_replies[0].fill"]
