"""The dashboard server (29999) in Python: the golden vectors whole and split at every byte, the
conversation's state (pairing, version), hostile input, and its entry in the interfaces table."""
from __future__ import annotations

import random

import pytest

from tests.interface_vectors import bytewise, conversation_cases
from urwire import to_dict
from urwire.generated import ur_dashboard
from urwire.interfaces import INTERFACES, interface_of_port
from urwire.text_lines import PENDING_KEPT, matches

CASES = conversation_cases("ur_dashboard")
SENDER_CASES = conversation_cases("ur_script_sender")


def decode(segments, version=None) -> list[dict]:
    conversation = ur_dashboard.conversation(version)
    records = []
    for segment in segments:
        records += conversation.feed(segment.data, segment.from_robot)
    return [to_dict(r) for r in records + conversation.close()]


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_golden_vectors(case):
    assert decode(case.segments, case.version) == case.expect


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_golden_vectors_one_byte_at_a_time(case):
    assert decode(bytewise(case.segments), case.version) == case.expect


def test_patterns_take_any_text_at_each_placeholder_and_nothing_more():
    pieces = ("Loading program: ", "")
    assert matches(pieces, "Loading program: ") and matches(pieces, "Loading program: a b")
    assert not matches(pieces, "Loading program:") and not matches(pieces, "xLoading program: a")
    quoted = ("could not understand: '", "'")
    assert matches(quoted, "could not understand: ''") and not matches(quoted, "could not understand: 'x")
    assert matches(("a", "b", "c"), "abc") and matches(("a", "b", "c"), "a-b-c") and not matches(("a", "b", "c"), "acb")
    assert not matches(("ab", "b"), "ab")   # the pieces may not overlap


def test_two_conversations_keep_their_own_version_and_pending_commands():
    first, second = ur_dashboard.conversation(), ur_dashboard.conversation()
    first.feed(b"PolyscopeVersion\n", False)
    first.feed(b"URSoftware 3.15.7.106331 (Aug 02 2022)\n", True)
    second.feed(b"play\n", False)
    (command,) = first.feed(b"safetystatus\n", False)
    (reply,) = second.feed(b"Starting program\n", True)
    assert command.available is False and reply.command_name == "play"
    (other,) = second.feed(b"safetystatus\n", False)
    assert other.available is None      # the second never learnt a version


def test_a_line_too_long_is_one_error_and_the_next_line_reads():
    conversation = ur_dashboard.conversation()
    records = []
    for chunk in [b"x" * 1000] * 20 + [b"\nplay\n"]:
        records += conversation.feed(chunk, False)
    assert [to_dict(r) for r in records] == [
        {"type": "error", "offset": 0, "error": f"line longer than {ur_dashboard.MAX_LINE} bytes"},
        {"type": "command", "command": "play", "command_name": "play"}]
    assert len(conversation.commands.buffer) == 0     # nothing of the long line was kept


def test_a_line_too_long_still_takes_its_place_in_the_pairing():
    # The server answers the long command with one line; "play" gets the next one.
    conversation = ur_dashboard.conversation()
    records = conversation.feed(b"Connected: Universal Robots Dashboard Server\n", True)
    records += conversation.feed(b"popup " + b"x" * 5000 + b"\nplay\n", False)
    records += conversation.feed(b"could not understand: 'line longer than 4096 bytes'\nStarting program\n", True)
    assert [r.command_name for r in records[-2:]] == [None, "play"]
    # A reply too long answers the oldest command: "stop" gets the line after it.
    records = conversation.feed(b"robotmode\nstop\n", False)
    records += conversation.feed(b"Robotmode: " + b"y" * 5000 + b"\nStopped\n", True)
    assert to_dict(records[2])["type"] == "error" and records[3].command_name == "stop"


def test_a_line_of_exactly_max_line_bytes_reads_and_one_more_is_too_long():
    for ending in (b"\n", b"\r\n"):
        ok = ur_dashboard.conversation().feed(b"p" * ur_dashboard.MAX_LINE + ending, False)
        bad = ur_dashboard.conversation().feed(b"p" * (ur_dashboard.MAX_LINE + 1) + ending, False)
        assert to_dict(ok[0])["type"] == "command" and to_dict(bad[0])["type"] == "error"


def test_commands_never_answered_keep_bounded_memory():
    conversation = ur_dashboard.conversation()
    conversation.feed(b"play\n" * (PENDING_KEPT * 4), False)
    assert len(conversation.pending) == PENDING_KEPT


NOT_KEPT = f"command not kept: more than {PENDING_KEPT} commands awaited replies"
REPLY_NOT_KEPT = f"reply to a command that was not kept: more than {PENDING_KEPT} commands awaited replies"


def test_past_the_kept_commands_a_reply_pairs_with_nothing_and_says_why():
    # 256 commands kept, then "play" and "robotmode" not kept: their replies must not be read as
    # the replies of other commands ("Starting program" as a robotmode reply).
    conversation = ur_dashboard.conversation()
    said = conversation.feed(b"robotmode\n" * PENDING_KEPT + b"play\nrobotmode\n", False)
    answers = conversation.feed(b"Robotmode: IDLE\n" * PENDING_KEPT + b"Starting program\nRobotmode: IDLE\n", True)
    assert [to_dict(c).get("error") for c in said] == [None] * PENDING_KEPT + [NOT_KEPT, NOT_KEPT]
    assert all(to_dict(r) == {"type": "reply", "reply": "Robotmode: IDLE", "command_name": "robotmode",
                              "reply_name": "robotmode", "error": False} for r in answers[:PENDING_KEPT])
    assert [to_dict(r) for r in answers[PENDING_KEPT:]] == [
        {"type": "reply", "reply": "Starting program", "error": REPLY_NOT_KEPT},
        {"type": "reply", "reply": "Robotmode: IDLE", "error": REPLY_NOT_KEPT}]
    # Every lost command answered, pairing starts again.
    (command,) = conversation.feed(b"stop\n", False)
    (reply,) = conversation.feed(b"Stopped\n", True)
    assert to_dict(command).get("error") is None and reply.command_name == "stop" and reply.error is False


def test_a_command_behind_a_lost_one_is_lost_too_though_there_is_room():
    conversation = ur_dashboard.conversation()
    conversation.feed(b"robotmode\n" * (PENDING_KEPT + 1), False)      # the last one lost
    conversation.feed(b"Robotmode: IDLE\n", True)                     # room for one again
    (late,) = conversation.feed(b"play\n", False)
    assert late.error == NOT_KEPT                                     # its reply comes after the lost one's
    replies = conversation.feed(b"Robotmode: IDLE\n" * (PENDING_KEPT - 1) + b"Robotmode: IDLE\nStarting program\n", True)
    assert [r.command_name for r in replies] == ["robotmode"] * (PENDING_KEPT - 1) + [None, None]
    assert [r.error for r in replies[-2:]] == [REPLY_NOT_KEPT, REPLY_NOT_KEPT]


def test_a_conversation_told_to_keep_more_pairs_past_256_and_says_its_own_bound():
    conversation = ur_dashboard.conversation()
    conversation.keep_pending(PENDING_KEPT + 2)
    said = conversation.feed(b"robotmode\n" * (PENDING_KEPT + 3), False)
    answers = conversation.feed(b"Robotmode: IDLE\n" * (PENDING_KEPT + 3), True)
    assert [r.command_name for r in answers] == ["robotmode"] * (PENDING_KEPT + 2) + [None]
    bound = f"more than {PENDING_KEPT + 2} commands awaited replies"
    assert said[-1].error == f"command not kept: {bound}"
    assert answers[-1].error == f"reply to a command that was not kept: {bound}"


def test_the_script_sender_keeps_only_its_latest_request_and_never_overflows():
    from urwire.generated import ur_script_sender
    conversation = ur_script_sender.conversation()
    records = conversation.feed(b"request_program\n" * (PENDING_KEPT * 2), True)
    assert not any(to_dict(r).get("error") for r in records)


def test_random_bytes_never_raise_and_every_record_renders():
    rng = random.Random(23)
    for _ in range(200):
        conversation = ur_dashboard.conversation(rng.choice([None, "3.15", "5.11"]))
        for _ in range(rng.randint(1, 8)):
            data = bytes(rng.choice(b"\n\r ab:'<>\xff\x00") if rng.random() < 0.7 else rng.randrange(256)
                         for _ in range(rng.randint(0, 300)))
            for record in conversation.feed(data, rng.random() < 0.5):
                to_dict(record)
        for record in conversation.close():
            to_dict(record)


def test_the_interfaces_table_knows_the_dashboard_by_port():
    interface = interface_of_port(29999)
    assert interface is INTERFACES["ur_dashboard"] and interface.ports == (29999,)
    conversation = interface.conversation()
    records = conversation.feed(b"Connected: Universal Robots Dashboard Server\n", True)
    assert to_dict(records[0])["reply_name"] == "connected"


def test_records_carry_labels_as_metadata():
    import dataclasses

    labels = {f.name: f.metadata["label"] for f in dataclasses.fields(ur_dashboard.Reply)}
    assert labels["error"] == "Says an error" and labels["reply"] == "Reply"


@pytest.mark.parametrize("case", SENDER_CASES, ids=lambda c: c.name)
def test_the_script_sender_golden_vectors_whole_and_one_byte_at_a_time(case):
    from urwire.generated import ur_script_sender

    for segments in (case.segments, bytewise(case.segments)):
        conversation = ur_script_sender.conversation(case.version)
        records = [r for s in segments for r in conversation.feed(s.data, s.from_robot)] + conversation.close()
        assert [to_dict(r) for r in records] == case.expect


def test_the_script_sender_is_the_robot_asking_a_client_of_port_50002():
    interface = interface_of_port(50002)
    assert interface is INTERFACES["ur_script_sender"] and interface.robot_is_client
