"""The inputs of the differential fuzzer (tests/fuzz/fuzz_diff.py): sessions of one interface,
both directions, seeded from its golden vectors and mutated.

A session is what `urwire decode --protocol X ROBOT [--to-robot CLIENT] [--version-hint V]` reads:
the robot's stream, the client's stream (when given: the interfaces that decode both
directions) and a version hint. While it is fuzzed it is held in pieces, (from the robot, bytes),
mostly one message each, so that mutations can splice, repeat or drop whole messages.

On disk (a kept corpus, tests/fuzz/corpus/diff_<interface>/, and what a run finds) a session is:
a flag byte (1: the client's stream is given), the hint's text and a NUL, the client stream's
length as a big-endian uint32, the client's stream, then the robot's stream to the end.
"""
from __future__ import annotations

import random
import re
from dataclasses import dataclass, replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CORPUS = ROOT / "tests" / "fuzz" / "corpus"

# Every interface but the primary one, whose differential fuzzer is tests/python/fuzz_decoder.py.
INTERFACES = ("ur_realtime", "rtde", "ur_dashboard", "ur_reverse", "ur_script_sender", "ur_trajectory",
              "ur_script_command")
ROBOT_ONLY = {"ur_realtime"}     # `--to-robot` is refused: the interface reads the robot's side only

# Hints a session may carry besides its vector's: software versions (the real-time layouts, the
# dashboard's version gates) and driver releases (the driver's sockets); "" is none.
HINTS = {
    "ur_realtime": ("", "1.8", "3.0", "3.2", "3.5", "3.12", "5.9", "5.25.1", "10.7"),
    "rtde": ("", "3.15", "5.9"),
    "ur_dashboard": ("", "1.8", "3.15", "5.9", "5.25.1"),
}
DRIVER_HINTS = ("", "1.0.0", "1.3.1", "2.9", "3.0")

# Lengths that open a message (bytes, big-endian): the real-time packet's int32, RTDE's uint16.
LENGTH_FIELDS = {"ur_realtime": 4, "rtde": 2}
MAX_SESSION = 256 * 1024
REPEATS = (1, 1, 1, 2, 3, 8, 9, 65, 257, 300)     # past the bounded queues and the RTDE limits
LONG_RUNS = (4000, 4090, 4094, 4095, 4096, 4097, 5000, 65536, 70000)   # the lines' limit is 4096 bytes
RTDE_SIZES = {b"BOOL": 1, b"UINT8": 1, b"UINT32": 4, b"INT32": 4, b"UINT64": 8, b"DOUBLE": 8, b"VECTOR3D": 24,
              b"VECTOR6D": 48, b"VECTOR6INT32": 24, b"VECTOR6UINT32": 24}
MAGICS = (b"\xd4\xc3\xb2\xa1", b"\xa1\xb2\xc3\xd4", b"\x4d\x3c\xb2\xa1", b"\n\r\r\n")   # pcap, pcapng
INTERESTING = (0, 1, 2, 3, 4, 5, 7, 8, 0x7f, 0x80, 0xff, 0x100, 0x7fff, 0x8000, 0xffff, 0x10000,
               0x7fffffff, 0x80000000, 0xffffffff)
TEXT_BITS = (b"\n", b"\r\n", b"\r", b"\0", b" ", b"\xff", b"\xc3", b"popup ", b"robotmode\n", b"Robotmode: ",
             b"load x.urp\n", b"Loading program: ", b"could not understand: ", b"true\n", b"false\n")


@dataclass(frozen=True)
class Session:
    pieces: tuple[tuple[bool, bytes], ...]     # (from the robot, bytes), in order
    hint: str = ""
    to_robot: bool = True                      # the client's stream is given (--to-robot)

    def stream(self, from_robot: bool) -> bytes:
        return b"".join(data for robot, data in self.pieces if robot == from_robot)

    def size(self) -> int:
        return sum(len(data) for _, data in self.pieces)


def dump(session: Session) -> bytes:
    client = session.stream(False) if session.to_robot else b""
    return (bytes([1 if session.to_robot else 0]) + session.hint.encode() + b"\0"
            + len(client).to_bytes(4, "big") + client + session.stream(True))


def load(interface: str, raw: bytes) -> Session:
    """A session read from its bytes, its streams cut into messages where the interface frames them."""
    to_robot = bool(raw[:1] and raw[0] & 1) and interface not in ROBOT_ONLY
    hint, _, rest = raw[1:].partition(b"\0")
    n = int.from_bytes(rest[:4], "big")
    client, robot = rest[4:4 + n], rest[4 + n:]
    pieces = [(False, p) for p in messages(interface, client)] if to_robot else []
    return Session(tuple(pieces + [(True, p) for p in messages(interface, robot)]),
                   hint.decode("utf-8", "replace"), to_robot)


def messages(interface: str, data: bytes) -> list[bytes]:
    """A stream cut where its messages end: by the length field, or after each line; as one piece
    where it is not so framed (what is left over stays the last piece)."""
    width = LENGTH_FIELDS.get(interface)
    out, at = [], 0
    if width:
        while at + width <= len(data):
            n = int.from_bytes(data[at:at + width], "big")
            if n < width or at + n > len(data):
                break
            out.append(data[at:at + n])
            at += n
    elif interface in ("ur_dashboard", "ur_script_sender"):
        while (end := data.find(b"\n", at)) >= 0:
            out.append(data[at:end + 1])
            at = end + 1
    if at < len(data):
        out.append(data[at:])
    return out


def hints(interface: str) -> tuple[str, ...]:
    return HINTS.get(interface, DRIVER_HINTS)


def seeds(interface: str) -> list[Session]:
    """The interface's golden vectors as sessions, each with the client's stream and without it;
    then its kept corpus."""
    from tests.interface_vectors import conversation_cases
    from tests.rtde_vectors import rtde_cases
    from tests.vectors import interface_cases

    out: list[Session] = []
    if interface == "ur_realtime":
        out = [Session(tuple((True, m) for m in messages(interface, c.data)), c.version or "", False)
               for c in interface_cases(interface)]
    elif interface == "rtde":
        out = [Session(tuple((robot, m) for robot, data in c.messages for m in messages(interface, data)))
               for c in rtde_cases()]
    else:
        out = [Session(tuple((s.from_robot, m) for s in c.segments for m in messages(interface, s.data)),
                       c.version or "") for c in conversation_cases(interface)]
    if interface not in ROBOT_ONLY:
        out += [Session(tuple(p for p in s.pieces if p[0]), s.hint, False) for s in out]
    return out + [load(interface, raw) for raw in kept(interface)]


def corpus_folder(interface: str) -> Path:
    return CORPUS / f"diff_{interface}"


def kept(interface: str) -> list[bytes]:
    folder = corpus_folder(interface)
    return [p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()] if folder.is_dir() else []


class Mutator:
    """Seeded mutations of sessions: bytes flipped, set, inserted or deleted; messages cut short,
    repeated (up to 300 times: past every bounded queue and limit), dropped, swapped, moved to the
    other direction or spliced in from another session; length fields and other integers set to
    edge values; the hint changed."""

    def __init__(self, interface: str, rng: random.Random):
        self.interface, self.rng = interface, rng
        self.ops = [self.flip, self.set_byte, self.insert, self.delete, self.cut, self.repeat, self.drop,
                    self.swap, self.splice, self.length_field, self.integer, self.hint, self.names, self.magic]
        if interface not in ROBOT_ONLY:
            self.ops += [self.other_direction, self.client_or_not]
        if interface in ("ur_dashboard", "ur_script_sender"):
            self.ops += [self.text] * 3 + [self.stretch]
        if interface == "rtde":
            self.ops += [self.twin_names]

    def __call__(self, session: Session, pool: list[Session]) -> Session:
        for _ in range(self.rng.choice((1, 1, 2, 3, 4))):
            mutated = self.rng.choice(self.ops)(session, pool)
            if mutated.size() <= MAX_SESSION:
                session = mutated
        return session

    # -- helpers
    def _piece(self, session: Session) -> int | None:
        return self.rng.randrange(len(session.pieces)) if session.pieces else None

    def _with(self, session: Session, i: int, data: bytes) -> Session:
        pieces = list(session.pieces)
        pieces[i] = (pieces[i][0], data)
        return replace(session, pieces=tuple(pieces))

    def _bytes(self, session: Session, change, refit: bool = True) -> Session:
        """One piece changed; where messages open with their length, half the time that length is
        set to the piece's new one, so that the change is read inside a message that frames."""
        i = self._piece(session)
        if i is None or not session.pieces[i][1]:
            return session
        data = change(bytearray(session.pieces[i][1]))
        width = LENGTH_FIELDS.get(self.interface)
        if refit and width and width <= len(data) < 1 << 8 * width and self.rng.random() < 0.5:
            data = len(data).to_bytes(width, "big") + data[width:]
        return self._with(session, i, data)

    # -- byte mutations
    def flip(self, session, pool):
        def change(b):
            b[self.rng.randrange(len(b))] ^= 1 << self.rng.randrange(8)
            return bytes(b)
        return self._bytes(session, change)

    def set_byte(self, session, pool):
        def change(b):
            b[self.rng.randrange(len(b))] = self.rng.choice((0, 1, 0x7f, 0x80, 0xff, self.rng.randrange(256)))
            return bytes(b)
        return self._bytes(session, change)

    def insert(self, session, pool):
        def change(b):
            at = self.rng.randrange(len(b) + 1)
            return bytes(b[:at]) + self.rng.randbytes(self.rng.randint(1, 8)) + bytes(b[at:])
        return self._bytes(session, change)

    def delete(self, session, pool):
        def change(b):
            at = self.rng.randrange(len(b))
            return bytes(b[:at] + b[at + self.rng.randint(1, 8):])
        return self._bytes(session, change)

    def cut(self, session, pool):
        return self._bytes(session, lambda b: bytes(b[:self.rng.randrange(len(b))]))

    def text(self, session, pool):
        def change(b):
            at = self.rng.randrange(len(b) + 1)
            return bytes(b[:at]) + self.rng.choice(TEXT_BITS) + bytes(b[at:])
        return self._bytes(session, change)

    def stretch(self, session, pool):
        """A run of one byte inserted: lines at, around and far past the line limit."""
        def change(b):
            at = self.rng.randrange(len(b) + 1)
            run = bytes([self.rng.choice(b"x \t\xc3\x00")]) * self.rng.choice(LONG_RUNS)
            return bytes(b[:at]) + run + bytes(b[at:])
        return self._bytes(session, change)

    def magic(self, session, pool):
        """The robot's stream opened with a capture file's magic: a raw stream is still raw."""
        first = next((i for i, (robot, _) in enumerate(session.pieces) if robot), None)
        if first is None:
            return session
        return self._with(session, first, self.rng.choice(MAGICS) + session.pieces[first][1])

    def integer(self, session, pool):
        def change(b):
            width = self.rng.choice((1, 2, 4, 8))
            if len(b) < width:
                return bytes(b)
            at = self.rng.randrange(len(b) - width + 1)
            value = self.rng.choice(INTERESTING) & ((1 << 8 * width) - 1)
            if width == 8 and self.rng.random() < 0.5:
                value = self.rng.choice((0x7ff8000000000000, 0x7ff0000000000000, 0xfff0000000000000))  # NaN, inf
            b[at:at + width] = value.to_bytes(width, self.rng.choice(("big", "little")))
            return bytes(b)
        return self._bytes(session, change)

    def length_field(self, session, pool):
        width = LENGTH_FIELDS.get(self.interface, 4)

        def change(b):
            if len(b) < width:
                return bytes(b)
            n = len(b)
            value = self.rng.choice((0, 1, width - 1, width, n - 1, n + 1, n + 8, 0x7fff, 0xffff, 0x7fffffff,
                                     0xffffffff, self.rng.randrange(1 << 8 * width)))
            b[:width] = (value & ((1 << 8 * width) - 1)).to_bytes(width, "big")
            return bytes(b)
        return self._bytes(session, change, refit=False)

    def names(self, session, pool):
        """A word of the piece (an RTDE variable name, a dashboard argument) repeated after a comma
        or a space, or dropped."""
        def change(b):
            words = list(re.finditer(rb"[A-Za-z_][A-Za-z_0-9]*", bytes(b)))
            if not words:
                return bytes(b)
            w = self.rng.choice(words)
            if self.rng.random() < 0.25:
                return bytes(b[:w.start()] + b[w.end():])
            return bytes(b[:w.end()]) + self.rng.choice((b",", b" ")) + w.group() + bytes(b[w.end():])
        return self._bytes(session, change)

    def twin_names(self, session, pool):
        """RTDE: the k-th name of a setup repeated in its list, and the k-th type of the next reply
        from the robot with as many: a recipe naming a variable twice, typed alike (or as many
        times as the repeats say: past the limits on names)."""
        def names(robot: bool, data: bytes) -> list:
            if data[2:3] not in (b"O", b"I"):
                return []
            found = list(re.finditer(rb"[A-Za-z_][A-Za-z_0-9]*", data[3:]))
            return [w for w in found if w.group() in RTDE_SIZES or w.group() in (b"NOT_FOUND", b"IN_USE")] \
                if robot else found

        lists = [(i, names(robot, data)) for i, (robot, data) in enumerate(session.pieces)]
        setups = [(i, words) for i, words in lists if not session.pieces[i][0] and words]
        if not setups:
            return session
        i, words = self.rng.choice(setups)
        last = self.rng.random() < 0.5
        k, times = len(words) - 1 if last else self.rng.randrange(len(words)), self.rng.choice((1, 1, 2, 64))
        reply = next(((j, w) for j, w in lists[i + 1:] if session.pieces[j][0] and len(w) == len(words)
                      and session.pieces[j][1][2:3] == session.pieces[i][1][2:3]), None)
        pieces = list(session.pieces)

        def grow(at: int, data: bytes) -> None:
            if len(data) < 1 << 16:
                pieces[at] = (pieces[at][0], len(data).to_bytes(2, "big") + data[2:])

        for at, found in [(i, words)] + ([reply] if reply else []):
            data, word = pieces[at][1], found[k]
            grow(at, data[:3 + word.end()] + (b"," + word.group()) * times + data[3 + word.end():])
        size = RTDE_SIZES.get(reply[1][k].group()) if reply and last else None
        if size:    # the reply's data packages carry the last value as many times more
            for at in range(reply[0] + 1, len(pieces)):
                robot, data = pieces[at]
                recipe = pieces[reply[0]][1][3:4]
                if robot and data[2:3] == b"U" and len(data) >= 4 + size and data[3:4] == recipe:
                    grow(at, data + b"".join(self.rng.choice((data[-size:], self.rng.randbytes(size))) for _ in range(times)))
        return replace(session, pieces=tuple(pieces))

    # -- message mutations
    def repeat(self, session, pool):
        i = self._piece(session)
        if i is None:
            return session
        pieces = list(session.pieces)
        pieces[i + 1:i + 1] = [pieces[i]] * self.rng.choice(REPEATS)
        return replace(session, pieces=tuple(pieces))

    def drop(self, session, pool):
        i = self._piece(session)
        if i is None:
            return session
        return replace(session, pieces=session.pieces[:i] + session.pieces[i + 1:])

    def swap(self, session, pool):
        if len(session.pieces) < 2:
            return session
        i, j = self.rng.sample(range(len(session.pieces)), 2)
        pieces = list(session.pieces)
        pieces[i], pieces[j] = pieces[j], pieces[i]
        return replace(session, pieces=tuple(pieces))

    def splice(self, session, pool):
        donor = self.rng.choice(pool)
        if not donor.pieces:
            return session
        start = self.rng.randrange(len(donor.pieces))
        taken = donor.pieces[start:start + self.rng.randint(1, 4)]
        at = self.rng.randint(0, len(session.pieces))
        return replace(session, pieces=session.pieces[:at] + taken + session.pieces[at:])

    def other_direction(self, session, pool):
        i = self._piece(session)
        if i is None:
            return session
        pieces = list(session.pieces)
        pieces[i] = (not pieces[i][0], pieces[i][1])
        return replace(session, pieces=tuple(pieces))

    def client_or_not(self, session, pool):
        return replace(session, to_robot=not session.to_robot)

    def hint(self, session, pool):
        return replace(session, hint=self.rng.choice(hints(self.interface)))
