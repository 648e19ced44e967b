"""The C backend (the extension urwire._ccore: the generated C parser and the C command's JSON
writer) against pure Python: every golden and conformance vector, every input of the fuzzers' kept
corpora and sessions of every controller generation (tests/tools/valid.py) give the same canonical
JSON Lines, byte for byte, and the same error flag, whole and fed in pieces; the same records
through the Framer (robot states from urwire._ccore.PackageStates): equal under ==, with the same
to_dict, JSON line, bytes again and versions, first read and then copied from what the same bytes
gave before; hostile robot states (cut short, lengths past the end) the same errors; and the
backend is picked as URWIRE_BACKEND says.

The extension is built by `make python-ext` (and by scripts/setup.sh and `make test`); without it
these tests fail, as the differential cannot run."""
from __future__ import annotations

import contextlib
import os
import random
import subprocess
import sys
from pathlib import Path

import pytest

from tests.tools import valid
from tests.tools.fuzz_inputs import HARNESSES, decodable
from tests.vectors import all_cases
from tests.tools import ccore_sanitized

import urwire
from urwire import decoding
from urwire._runtime import StreamError
from urwire.canonical import has_error

ROOT = Path(__file__).resolve().parents[2]
PIECES = (1, 7, 64, 4093)       # chunk sizes: inside a header, inside a field, across messages


@pytest.fixture(scope="module")
def ccore():
    return ccore_sanitized.extension()


def python_json_lines(data: bytes, hint) -> tuple[bytes, bool]:
    """What pure Python prints: each record of the Framer as to_json_line, and whether one held an error."""
    records = list(urwire.decode_stream(data, hint))
    return "".join(urwire.to_json_line(r) + "\n" for r in records).encode(), any(map(has_error, records))


def c_json_lines(ccore, data: bytes, hint, piece: int = 0) -> tuple[bytes, bool]:
    version = urwire.parse_version(hint)
    lines = ccore.PrimaryJsonLines(None if version is None else "%d.%d.%d" % version)
    step = piece or max(len(data), 1)
    out = b"".join(lines.feed(data[at:at + step]) for at in range(0, len(data), step)) + lines.close()
    return out, lines.errors


def assert_same(ccore, data: bytes, hint, what: str, pieces=PIECES) -> None:
    expected = python_json_lines(data, hint)
    assert c_json_lines(ccore, data, hint) == expected, what
    for piece in pieces:
        assert c_json_lines(ccore, data, hint, piece) == expected, f"{what} in pieces of {piece}"


# ---- records: robot states from C (PackageStates) against pure Python ----------------------

def new_states(ccore, recipes: bool = True):
    """A PackageStates of the robot state as decode_message's, with nothing remembered yet;
    without recipes, every new package is read by its Python decoder."""
    from urwire.generated.messages import ITEM_RUNS, RUN_RECIPES

    kind = decoding._PACKAGE_LIST
    return ccore.PackageStates(kind.cls, kind.forms, kind.body_offset, *((RUN_RECIPES, ITEM_RUNS) if recipes else ()),
                               message_type=decoding._PACKAGE_LIST_TYPE, type_offset=decoding.MESSAGE_TYPE_OFFSET,
                               default_version=decoding.DEFAULT_VERSION)


@contextlib.contextmanager
def robot_states_from(states):
    """decode_message (and so the Framer) reads robot states with `states`; None: pure Python."""
    saved = decoding._C_STATES
    decoding._C_STATES = states
    try:
        yield
    finally:
        decoding._C_STATES = saved


def framed(data: bytes, hint, piece: int = 0) -> list:
    framer = urwire.Framer(hint)
    step = piece or max(len(data), 1)
    records = []
    for at in range(0, len(data), step):
        records += framer.feed(data[at:at + step])
    return records + framer.close()


def versions_of(record) -> tuple:
    """The versions == leaves out: the one each part was read in, and the one a state implied."""
    parts = getattr(record, "packages", None) or [record]
    return (getattr(record, "implied_version", None), tuple(getattr(p, "decoded_version", None) for p in parts))


def described(records: list) -> list:
    """All that must agree about each record: itself, its dict, its JSON line, its bytes again
    (stream faults have none), its versions and its repr (where == cannot tell True from 1)."""
    return [(r, urwire.to_dict(r), urwire.to_json_line(r),
             None if isinstance(r, StreamError) else urwire.encode_message(r), versions_of(r), repr(r))
            for r in records]


def assert_same_described(got: list, expected: list, again: list, what: str) -> None:
    """got against expected, item by item. A record holding a NaN is not equal even to itself
    read again (NaN != NaN): where pure Python's two reads differ, the records are compared by
    JSON line, bytes, versions and repr instead."""
    assert len(got) == len(expected), what
    for k, (g, e, a) in enumerate(zip(got, expected, again)):
        assert type(g[0]) is type(e[0]), f"{what}: record {k}"
        if e == a:
            assert g == e, f"{what}: record {k}"
        else:
            assert g[2:] == e[2:], f"{what}: record {k}"


def assert_same_records(states, data: bytes, hint, what: str, pieces=PIECES) -> None:
    with robot_states_from(None):
        expected, again = described(framed(data, hint)), described(framed(data, hint))
    with robot_states_from(states):
        # Twice whole: first read, then copied from what the same packages gave the first time.
        for piece in (0, 0, *pieces):
            assert_same_described(described(framed(data, hint, piece)), expected, again,
                                  f"{what} in pieces of {piece}")


def recipe_cases() -> list:
    from urwire.generated.messages import RUN_RECIPES
    return sorted(RUN_RECIPES.items(), key=lambda kv: kv[0].__qualname__)


@pytest.mark.parametrize("decode, recipe", recipe_cases(), ids=lambda x: getattr(x, "__qualname__", ""))
def test_every_run_recipe_builds_what_its_decoder_builds(ccore, decode, recipe):
    """Each form read by fixed runs (RUN_RECIPES), made in C from random bytes of the size it reads
    (NaNs, bools of any byte, enum codes outside the tables, the Euromap67 flag set or not among
    them): the record its Python decoder makes, which a stand-in decoder that fails the test if
    called shows was made in C; one byte short or extra, None (PackageList.decode's case)."""
    import types

    from urwire.generated.messages import ITEM_RUNS

    def never(buf, body, stop, version):
        raise AssertionError(f"{decode.__qualname__}: read in Python")

    cls = decode.__self__
    stand_in = types.MethodType(never, cls)
    code, form = next((c, f) for c, forms in decoding._PACKAGE_LIST.forms.by_code.items()
                      for f in forms if f.decode == decode)

    class OneForm:
        def fast(self, version):
            return {code: stand_in}

    states = ccore.PackageStates(decoding._PACKAGE_LIST.cls, OneForm(), decoding._PACKAGE_LIST.body_offset,
                                 {stand_in: recipe}, ITEM_RUNS)
    runs, _ = recipe
    size = sum(st.size for st, *_ in runs)          # every run read; fewer when a flag is zero
    rng = random.Random(decode.__qualname__)
    nan_bits = (b"\x7f\xc0\x00\x00", b"\x7f\x80\x00\x01", b"\xff\xff\xff\xff")

    def framed_package(body: bytes) -> bytes:
        return (10 + len(body)).to_bytes(4, "big") + bytes([16]) + (5 + len(body)).to_bytes(4, "big") \
            + bytes([code]) + body

    sending = [v for v in valid.versions() if decoding._PACKAGE_LIST.forms.fast(v).get(code) == decode]
    for version in {form.rep, *sending}:
        for k in range(12):
            body = bytearray(rng.getrandbits(8) for _ in range(size))
            for at in rng.sample(range(max(size - 3, 1)), min(3, max(size - 3, 1))):
                body[at:at + 4] = rng.choice(nan_bits)
            if k % 3 == 0:
                body = bytearray(len(body))             # zeros: flags unset, the smallest size
            _, used = decode(framed_package(bytes(body[:size])), 10, 10 + size, version)
            state = framed_package(bytes(body[:used - 10]))
            got = states.decode(state, version)
            expected, used = decode(state, 10, len(state), version)
            assert used == len(state) and got is not None
            (pkg,) = got.packages
            assert type(pkg) is cls
            if expected == decode(state, 10, len(state), version)[0]:     # no NaN (NaN != NaN)
                assert pkg == expected
            assert (repr(pkg), pkg.encode(), pkg.decoded_version) == (repr(expected), expected.encode(), version)
        for other in (size - 1, size + 1):
            body = bytes([1]) * other                  # flags set: short by one, or one byte extra
            assert states.decode(framed_package(body), version) is None   # the Python decoder's case


def test_every_form_of_fixed_sizes_has_a_recipe():
    """The generator writes a recipe for every robot-state form whose sizes are fixed (the
    Euromap67 block's two included); a form of open size (safety_data's raw bytes) has none."""
    from urwire.generated.messages import RUN_RECIPES

    forms = [f for fs in decoding._PACKAGE_LIST.forms.by_code.values() for f in fs]
    assert [f.decode.__qualname__ for f in forms if (f.decode in RUN_RECIPES) != (f.sizes is not None)] == []
    assert len(RUN_RECIPES) == sum(f.sizes is not None for f in forms) > 20


def test_a_class_with_a_post_init_is_left_to_its_decoder(ccore):
    """A record made past __init__ would miss what a __post_init__ adds: a class that has one is
    never made from a recipe (its Python decoder reads it; here a stand-in that declines)."""
    import dataclasses
    import types

    from urwire.generated.messages import ITEM_RUNS, RUN_RECIPES

    @dataclasses.dataclass(slots=True)
    class Noted(urwire.CartesianInfo):
        def __post_init__(self):
            pass

    decode = next(d for d in RUN_RECIPES if d.__self__ is urwire.CartesianInfo)
    code = urwire.CartesianInfo.CODE
    calls = []
    stand_in = types.MethodType(lambda cls, buf, body, stop, version: calls.append(stop) or (None, -1), Noted)

    class OneForm:
        def fast(self, version):
            return {code: stand_in}

    states = ccore.PackageStates(decoding._PACKAGE_LIST.cls, OneForm(), decoding._PACKAGE_LIST.body_offset,
                                 {stand_in: RUN_RECIPES[decode]}, ITEM_RUNS)
    size = sum(st.size for st, *_ in RUN_RECIPES[decode][0])
    state = (10 + size).to_bytes(4, "big") + b"\x10" + (5 + size).to_bytes(4, "big") + bytes([code]) + bytes(size)
    assert states.decode(state, (5, 11, 0)) is None and calls == [len(state)]


@pytest.mark.parametrize("case", all_cases(), ids=lambda c: c.name)
def test_every_vector_gives_the_same_records(ccore, case):
    assert_same_records(new_states(ccore), case.data, case.version, case.name)
    assert_same_records(new_states(ccore, recipes=False), case.data, case.version, case.name, pieces=())


@pytest.mark.parametrize("harness", HARNESSES)
def test_every_kept_fuzz_input_gives_the_same_records(ccore, harness):
    states = new_states(ccore)
    for hint, data, name in decodable(harness):
        assert_same_records(states, data, hint, name, pieces=(1, 97))


@pytest.mark.parametrize("version", valid.versions(), ids=lambda v: ".".join(map(str, v)))
def test_sessions_of_every_generation_give_the_same_records(ccore, version):
    rng = random.Random(hash(version))
    hint = ".".join(map(str, version))
    states = new_states(ccore)
    for _ in range(4):
        data = valid.session(rng, version, 12)
        cut = data[int.from_bytes(data[:4], "big"):]
        for stream, given in ((data, None), (cut, None), (cut, hint)):
            assert_same_records(states, stream, given, f"{given} {stream[:40].hex()}", pieces=(5, 1000))


def test_a_message_class_that_declares_its_bases_slots_again_is_filled_through_the_visible_ones(ccore):
    """dataclass(slots=True) on Python 3.10 declares every slot of a base again in the subclass,
    where the base's are hidden and stay empty: PackageStates fills the visible ones (it once
    refused such a class, and the package fell back to Python on 3.10)."""
    from urwire.generated.messages import ITEM_RUNS, RUN_RECIPES

    kind = decoding._PACKAGE_LIST
    names = tuple(name for cls in kind.cls.__mro__ for name in getattr(cls, "__slots__", ()))
    again = type("Again", (kind.cls,), {"__slots__": names})
    assert again.__basicsize__ > kind.cls.__basicsize__          # the base's slots are still there
    states = ccore.PackageStates(again, kind.forms, kind.body_offset, RUN_RECIPES, ITEM_RUNS,
                                 message_type=decoding._PACKAGE_LIST_TYPE, type_offset=decoding.MESSAGE_TYPE_OFFSET,
                                 default_version=decoding.DEFAULT_VERSION)
    for state in real_states():
        msg = states.decode(state, (5, 11, 0))
        expected = decoding.decode_in_python(state, (5, 11, 0), None)
        assert type(msg) is again
        assert [getattr(msg, name) for name in names] == [getattr(expected, name) for name in names]


def real_states() -> list[bytes]:
    folder = ROOT / "tests" / "conformance" / "Universal_Robots_Client_Library"
    return [bytes.fromhex((folder / f"{name}.hex").read_text().strip())
            for name in ("robot_state_real_robot_5.11_pr137", "robot_state_ursim5.8_ur5e_first")]


def hostile(state: bytes, rng: random.Random) -> list[bytes]:
    """A real robot state's variants, each framed as one message: cut at random places (the
    message length follows), and each sub-package length set to 0, 4, one past the end, the
    largest int32 and a negative one."""
    out = []
    for cut in sorted(rng.sample(range(5, len(state)), 40)):
        out.append(cut.to_bytes(4, "big") + state[4:cut])
    pos = 5
    while pos + 5 <= len(state):
        size = int.from_bytes(state[pos:pos + 4], "big")
        for bad in (0, 4, len(state) - pos + 1, 0x7FFFFFFF, 0xFFFFFFF0):
            out.append(state[:pos] + bad.to_bytes(4, "big") + state[pos + 4:])
        pos += max(size, 5)
    return out


def test_hostile_robot_states_give_the_same_records_and_errors(ccore):
    """Read after the same packages were seen whole (so that copies are at hand), every variant
    gives pure Python's record: its errors with their fields and offsets, in the same places."""
    rng = random.Random(25)
    states = new_states(ccore)
    faults = 0
    for state in real_states():
        for version in (None, (5, 11, 0), (3, 2, 0)):
            with robot_states_from(states):
                for _ in range(2):               # twice: the records made in C are then kept
                    decoding.decode_message(state, version)
            for msg in hostile(state, rng):
                with robot_states_from(None):
                    expected = described([decoding.decode_message(msg, version)])
                    again = described([decoding.decode_message(msg, version)])
                with robot_states_from(states):
                    got = described([decoding.decode_message(msg, version)])
                assert_same_described(got, expected, again, msg[:40].hex())
                faults += has_error(expected[0][0])
    assert faults > 100


def mutable_parts(obj, seen: list) -> list:
    """Every list and record object reachable from obj (ints, floats, texts and enum members
    are immutable)."""
    if isinstance(obj, list):
        seen.append(obj)
        for item in obj:
            mutable_parts(item, seen)
    elif hasattr(obj, "__dataclass_fields__"):
        seen.append(obj)
        for name in obj.__dataclass_fields__:
            mutable_parts(getattr(obj, name), seen)
    return seen


def test_records_from_c_share_nothing_that_can_change(ccore):
    """Two reads of the same state share no list or record, and changing one record changes
    neither the next read nor what the C side keeps."""
    states = new_states(ccore)
    state = real_states()[0]
    with robot_states_from(None):
        expected = decoding.decode_message(state, (5, 11, 0))
    with robot_states_from(states):
        first = decoding.decode_message(state, (5, 11, 0))
        second = decoding.decode_message(state, (5, 11, 0))
        assert first == second == expected
        assert not {id(x) for x in mutable_parts(first, [])} & {id(x) for x in mutable_parts(second, [])}
        joints = first.package(urwire.JointData).joints
        joints[0].q_actual += 1.0
        joints.pop()
        first.packages.clear()
        assert decoding.decode_message(state, (5, 11, 0)) == expected
        assert second == expected


def decoded_again(states, state: bytes, times: int = 3):
    """The record of `state` read `times` times in a row, each read dropped but the last: the
    packages are then kept, and copies of them were lent out and dropped."""
    with robot_states_from(states):
        for _ in range(times - 1):
            decoding.decode_message(state, (5, 11, 0))
        return decoding.decode_message(state, (5, 11, 0))


def new_memory(read) -> int:
    """The bytes that read() allocates and that are still in use once it returns (tracemalloc)."""
    import tracemalloc
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        result = read()
        after = tracemalloc.get_traced_memory()[0]
    finally:
        tracemalloc.stop()
    del result
    return after - before


def test_a_dropped_state_lends_its_copies_to_the_next(ccore):
    """Read again after the state before was dropped, the packages that did not move are the
    copies that state had, taken back: the read allocates no more than the message and its list
    (a few hundred bytes, where copies of a real state's packages take kilobytes), and its record
    is still pure Python's."""
    states = new_states(ccore)
    state = real_states()[0]
    with robot_states_from(None):
        expected = decoding.decode_message(state, (5, 11, 0))
    decoded_again(states, state)
    with robot_states_from(states):
        taken_back = new_memory(lambda: decoding.decode_message(state, (5, 11, 0)))
        held = decoding.decode_message(state, (5, 11, 0)), decoding.decode_message(state, (5, 11, 0))
        copied = new_memory(lambda: decoding.decode_message(state, (5, 11, 0)))   # both lent copies held
        assert decoding.decode_message(state, (5, 11, 0)) == expected and held[0] == held[1] == expected
    assert taken_back < 1000 and copied > 5 * taken_back, (taken_back, copied)


def test_a_copy_is_not_lent_again_while_any_part_of_it_is_held(ccore):
    """A state dropped while a list or record of it is still held, or after it was changed,
    gives the next read new copies: the next state shares nothing with what is held, and equals
    pure Python's record."""
    states = new_states(ccore)
    state = real_states()[0]
    with robot_states_from(None):
        expected = decoding.decode_message(state, (5, 11, 0))
    first = decoded_again(states, state)
    joints = first.package(urwire.JointData).joints
    joint = joints[1]
    del first
    second = decoded_again(states, state, times=1)
    assert second == expected
    assert not {id(joints), id(joint)} & {id(x) for x in mutable_parts(second, [])}
    joints.pop()
    joint.q_actual += 1.0
    assert second == expected
    del second, joints, joint
    for change in (lambda m: setattr(m.package(urwire.JointData).joints[0], "q_actual", 9.0),
                   lambda m: m.package(urwire.JointData).joints.append(None),
                   lambda m: m.package(urwire.JointData).joints.reverse()):
        changed = decoded_again(states, state, times=1)
        change(changed)
        del changed
        assert decoded_again(states, state, times=1) == expected


def test_records_from_c_are_the_classes_own(ccore):
    """Made past __init__: the same classes, every slot set, usable as records built in Python
    (replace, repr, the field defaults)."""
    import dataclasses

    states = new_states(ccore)
    with robot_states_from(states):
        for _ in range(2):
            msg = decoding.decode_message(real_states()[0], (5, 11, 0))
    assert type(msg) is urwire.RobotStateMessage and msg.error is None and msg.raw == b""
    for pkg in msg.packages:
        for f in dataclasses.fields(pkg):
            getattr(pkg, f.name)        # AttributeError if a slot were left empty
        assert dataclasses.replace(pkg) == pkg and repr(pkg)
    assert msg.implied_version is None and dataclasses.replace(msg) == msg


def test_under_the_c_backend_decode_message_asks_c_first(ccore):
    """decode_message asks PackageStates first for every message, and pure Python reads what it
    declines (a stand-in that counts its calls and declines them all); the real one declines
    every message but a robot state, and arguments it does not take (a bytearray, a text version)
    are made into those it does."""
    calls = []

    class Declining:
        def decode(self, buf, version):
            calls.append(buf[4])
            return None

    stream = b"".join(real_states()) + all_cases()[0].data
    with robot_states_from(Declining()):
        records = framed(stream, None)
    with robot_states_from(None):
        assert records == framed(stream, None)
    assert len(calls) == len(records) - sum(1 for r in records if isinstance(r, StreamError))
    states = new_states(ccore)
    state = real_states()[0]
    for buf in (b"\0\0\0\5\x14", b"\0\0\0\x10", b"\x10", b""):
        assert states.decode(buf, None) is None
    assert states.decode(b"\0\0\0\5\x10", None) == decoding.decode_in_python(b"\0\0\0\5\x10", None, None)
    assert states.decode(state, (5, 11)) is None and states.decode(bytearray(state), None) is None
    with robot_states_from(states):
        assert type(decoding.decode_message(state, (5, 11, 0))) is urwire.RobotStateMessage
    for buf, version in ((bytearray(state), "5.11"), (memoryview(state), (5, 11, 0))):
        with robot_states_from(None):
            expected = decoding.decode_message(buf, version)
        with robot_states_from(states):
            assert decoding.decode_message(buf, version) == expected


@pytest.mark.parametrize("case", all_cases(), ids=lambda c: c.name)
def test_every_vector_gives_the_same_lines(ccore, case):
    assert_same(ccore, case.data, case.version, case.name)


@pytest.mark.parametrize("harness", HARNESSES)
def test_every_kept_fuzz_input_gives_the_same_lines(ccore, harness):
    inputs = decodable(harness)
    assert len(inputs) > 20
    for hint, data, name in inputs:
        assert_same(ccore, data, hint, name, pieces=(1, 97))


@pytest.mark.parametrize("version", valid.versions(), ids=lambda v: ".".join(map(str, v)))
def test_sessions_of_every_generation_give_the_same_lines(ccore, version):
    rng = random.Random(hash(version))
    hint = ".".join(map(str, version))
    for _ in range(6):
        data = valid.session(rng, version, 12)
        cut = data[int.from_bytes(data[:4], "big"):]          # as a capture that starts mid-stream
        for stream, given in ((data, None), (cut, None), (cut, hint)):
            assert_same(ccore, stream, given, f"{given} {stream[:40].hex()}", pieces=(5, 1000))


def test_the_extension_refuses_what_is_not_a_stream_or_version(ccore):
    with pytest.raises(TypeError):
        ccore.PrimaryJsonLines(None).feed("text")
    with pytest.raises(ValueError):
        ccore.PrimaryJsonLines("five")
    lines = ccore.PrimaryJsonLines(None)
    lines.close()
    with pytest.raises(ValueError):
        lines.feed(b"\0\0\0\5\x14")


def backend_under(value) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
    env.pop("URWIRE_BACKEND", None)
    if value is not None:
        env["URWIRE_BACKEND"] = value
    return subprocess.run([sys.executable, "-c", "import urwire; print(urwire.backend())"],
                          env=env, capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize("value, expected", [(None, "c"), ("c", "c"), ("python", "python"), ("PYTHON", "python")])
def test_urwire_backend_picks_the_decoder(ccore, value, expected):
    result = backend_under(value)
    assert (result.returncode, result.stdout.strip()) == (0, expected), result.stderr


def test_an_unknown_backend_is_refused(ccore):
    result = backend_under("rust")
    assert result.returncode != 0 and "URWIRE_BACKEND" in result.stderr


def test_the_command_prints_the_same_bytes_under_both_backends(ccore, tmp_path):
    """`urwire decode` of a raw stream: the C backend's lines and exit status are pure Python's."""
    stream = tmp_path / "stream.bin"
    stream.write_bytes(b"".join(case.data for case in all_cases() if case.version is None))
    runs = {}
    for value in ("c", "python"):
        env = dict(os.environ, URWIRE_BACKEND=value,
                   PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
        result = subprocess.run([sys.executable, "-m", "urwire", "decode", str(stream)], env=env,
                                capture_output=True, timeout=120)
        runs[value] = (result.returncode, result.stdout, result.stderr)
    assert runs["c"] == runs["python"]
    assert runs["c"][0] == 1 and runs["c"][1].count(b"\n") > 100


def test_the_command_writes_to_a_text_stdout_in_its_place(ccore, tmp_path, monkeypatch):
    """In-process, with stdout an io.StringIO: the C backend's lines come out as text (the C
    backend chosen here whatever URWIRE_BACKEND says)."""
    import contextlib
    import io

    from urwire import backends, cli

    case = next(c for c in all_cases() if c.name == "text_message_invalid_utf8")
    stream = tmp_path / "stream.bin"
    stream.write_bytes(case.data)
    monkeypatch.setattr(backends, "_CCORE", ccore)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = cli.main(["decode", "--no-progress", str(stream)])
    assert (code, out.getvalue().encode()) == (0, python_json_lines(case.data, None)[0])


@pytest.mark.deep  # a sanitized build of the extension: make test-deep
def test_the_extension_under_asan_and_ubsan(tmp_path):
    """urwire._ccore's own C (the module, the memory stream each feed writes into, the robot
    states' records) built with ASan and UBSan and run over every vector and kept fuzz input and
    the hostile robot states (tests/python/ccore_asan_peer.py): no report, the same lines and
    records."""
    result = ccore_sanitized.run_peer("ccore_asan_peer.py", tmp_path)
    assert result.returncode == 0 and "ERROR" not in result.stderr, result.stderr[-3000:]
    lines, records = map(int, result.stdout.split())
    assert lines > 300 and records > 300
