"""Request/response tracking in the generator: the spec's RTDE `exchanges` resolved (requests to
the robot, replies from it, each message in one pair at most, refused at its YAML path otherwise),
the links' field names kept free of variables, and the decoders untouched by it."""
from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from codegen import exchanges
from codegen.compile import SPEC_DIR, compile_text
from codegen.errors import SpecError
from codegen.kinds.typed_messages.dissector import exchanges_of
from codegen.kinds.typed_messages.plan import plan

ROOT = Path(__file__).resolve().parents[2]
TEXT = (SPEC_DIR / "rtde.yaml").read_text(encoding="utf-8")


def edited(edit) -> str:
    data = yaml.safe_load(TEXT)
    edit(data)
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def problems(text: str) -> list[str]:
    with pytest.raises(SpecError) as caught:
        compile_text(text, "bad.yaml")
    return [str(p) for p in caught.value.problems]


def test_every_rtde_request_has_its_reply_and_data_packages_none():
    x = exchanges_of(plan(compile_text(TEXT, "rtde.yaml")))
    pairs = {}
    for name, i in x.requests.items():
        pairs.setdefault(i, [set(), set()])[0].add(name)
    for name, i in x.replies.items():
        pairs[i][1].add(name)
    assert sorted((sorted(a), sorted(b)) for a, b in pairs.values()) == [
        (["get_urcontrol_version"], ["get_urcontrol_version_reply"]),
        (["pause"], ["pause_reply"]),
        (["request_protocol_version"], ["request_protocol_version_reply"]),
        (["setup_inputs"], ["setup_inputs_reply"]),
        (["setup_outputs", "setup_outputs_v1"], ["setup_outputs_reply", "setup_outputs_reply_v1"]),
        (["start"], ["start_reply"]),
    ]
    for name in ("data_package", "input_data_package", "text_message", "send_text_message"):
        assert x.role(name) == (-1, False), name
    assert x.max_pending == 8


@pytest.mark.parametrize("name", exchanges.NAMES)
def test_a_variable_named_like_a_link_is_refused(name):
    def edit(data):
        data["variables"][0]["name"] = name
        data["variables"][0].pop("indices", None)
    found = problems(edited(edit))
    assert any(p.startswith("variables[0]") and f"rtde.{name} is the dissector's own field" in p for p in found), found


@pytest.mark.parametrize("pair, key, name, says", [
    (0, "requests", "no_such_message", "unknown message 'no_such_message'"),
    (0, "requests", "start_reply", "'start_reply' is not a message to the robot"),
    (0, "replies", "start", "'start' is not a message from the robot"),
    (5, "replies", "start_reply", "'start_reply' is in another pair already"),
])
def test_a_bad_pair_is_refused_at_its_path(pair, key, name, says):
    def edit(data):
        data["exchanges"]["pairs"][pair][key][0] = name
    found = problems(edited(edit))
    assert any(p.startswith(f"exchanges.pairs[{pair}].{key}[0]") and says in p for p in found), found


def test_the_decoders_carry_no_link():
    """Only the dissectors link replies with requests: the C and Python decoders read no pair."""
    for path in [*(ROOT / "generated" / "c").glob("*"), *(ROOT / "generated" / "python").rglob("*.py")]:
        text = path.read_text(encoding="utf-8")
        assert "response_in" not in text and "response_to" not in text, path
