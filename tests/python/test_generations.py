"""Every controller generation the spec knows, through the Python decoder: sessions of random
valid messages of each generation decode without error and re-encode to the same bytes."""
from __future__ import annotations

import random

import pytest
import urwire

from tests.tools import valid


@pytest.mark.parametrize("version", valid.versions(), ids=lambda v: ".".join(map(str, v)))
def test_a_session_of_each_generation_decodes_cleanly_and_reencodes(version):
    rng = random.Random(hash(version))
    for _ in range(20):
        data = valid.session(rng, version, 15)
        framer = urwire.Framer()
        records = framer.feed(data) + framer.close()
        assert framer.version[:2] == version[:2] and framer.version_seen
        for record in records:
            assert not urwire.canonical.has_error(record), urwire.to_json_line(record)
            assert getattr(record, "extra", b"") == b"", urwire.to_json_line(record)
        assert b"".join(urwire.encode_message(r) for r in records) == data


def test_package_classes_follow_the_version():
    """Type 5 is the laser pointer up to 1.7 and kinematics info from 1.8
    (docs/firmware-history.md#laser-pointer); codes come in order; a text version is accepted."""
    early, late = urwire.package_classes("1.7"), urwire.package_classes((1, 8, 0))
    assert early[5] is urwire.LaserPointer and late[5] is urwire.KinematicsInfo
    assert list(late) == sorted(late) and late[1] is urwire.JointData
    assert urwire.package_classes("5.25.1") == urwire.package_classes((5, 25, 1))
