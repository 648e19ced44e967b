"""Pass 4: plan every layout once, for every target.

A plan says how the bytes of a layout are walked, in the order they come:
- a `FixedRun` is fields whose sizes are known without reading: one bounds check covers them,
  and every field and scalar in it has its offset from the run's start;
- a `CondGroup` is consecutive fields present under one condition (a flag field, a version
  range), with the plan of its inside;
- a `VarField` is one field whose size is known only by reading it.

Messages get their header slots with absolute offsets, the offset where their body starts, the
layouts each type code can have and its forms across software versions: the form of each
segment of the version axis (the nearest below's where none is sent) and the sizes that
recognise one. The protocol gets those segments and where the software version is read.
Targets render these plans and decide nothing about layout themselves: no target splits a
struct, computes an offset or builds a condition from the IR on its own.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Optional, Union

from ... import ir
from ...errors import Problem, SpecError
from . import model


# ---- conditions ---------------------------------------------------------------------------

@dataclass(frozen=True)
class Condition:
    """When a field is on the wire: `flag` (an earlier field) is nonzero, and the stream's
    version lies within `versions`. Targets render each part in their own syntax."""

    flag: Optional[str]
    versions: ir.VersionRange

    @property
    def low(self) -> Optional[ir.Version]:
        return self.versions.low

    @property
    def high(self) -> Optional[ir.Version]:
        return self.versions.high


def condition_of(f: ir.AnyField) -> Optional[Condition]:
    return Condition(f.present_if, f.versions) if f.conditional else None


# ---- layout plans -------------------------------------------------------------------------

@dataclass
class Leaf:
    """One scalar inside a fixed run: its path from the layout (joints[2].q_actual)."""

    path: str
    offset: int          # from the start of the run
    scalar: ir.Scalar


@dataclass
class Member:
    """One field inside a fixed run."""

    field: ir.AnyField
    offset: int          # from the start of the run
    first_leaf: int      # index of its first scalar among the run's leaves
    leaf_count: int
    item: Optional["ItemPlan"] = None   # for a fixed-count group: the plan of one item


@dataclass
class FixedRun:
    index: int                      # the n-th run of its layout, counting inside conditions
    size: int
    members: list[Member]
    leaves: list[Leaf]
    kind: str = "run"

    @property
    def fields(self) -> list[ir.AnyField]:
        return [m.field for m in self.members]


@dataclass
class CondGroup:
    condition: Condition
    fields: list[ir.AnyField]
    steps: list["Step"]
    kind: str = "cond"


@dataclass
class VarField:
    field: ir.AnyField
    path: str
    item: Optional["ItemPlan"] = None   # for a group repeated to the end
    kind: str = "var"


Step = Union[FixedRun, CondGroup, VarField]


@dataclass
class LayoutPlan:
    """How one struct (a package, a message body, or a group item) is walked."""

    struct: ir.Struct
    steps: list[Step]
    runs: list[FixedRun]             # every run, nested ones included, in order
    fixed_size: Optional[int]
    min_size: int


@dataclass
class ItemPlan:
    """One item of a repeated group. A fixed item is read inside its parent's run: `leaves`
    and `members` are then relative to the item's start."""

    group: ir.GroupField
    layout: LayoutPlan
    fixed: bool
    leaf_count: int                  # scalars per item (fixed items)


class _Planner:
    def __init__(self, problems: list[Problem]):
        self.problems = problems
        self.items: dict[int, ItemPlan] = {}

    def item(self, group: ir.GroupField) -> ItemPlan:
        if id(group) not in self.items:
            layout = self.layout(group.item)
            fixed = group.item.fixed_item
            leaves = len(layout.runs[0].leaves) if fixed else 0
            if not fixed and group.count is not None:
                self.problems.append(group.where.problem(
                    "a fixed-count group of variable-size items is not supported: give the items a fixed size "
                    "or repeat them to the end"))
            if not fixed and group.item.needs_version:
                self.problems.append(group.where.problem(
                    "the items of a repeated group cannot depend on the software version"))
            self.items[id(group)] = ItemPlan(group, layout, fixed, leaves)
        return self.items[id(group)]

    def layout(self, struct: ir.Struct) -> LayoutPlan:
        runs: list[FixedRun] = []
        steps = self.steps(struct.fields, runs)
        return LayoutPlan(struct, steps, runs, struct.fixed_size, struct.min_size)

    def steps(self, fields: list[ir.AnyField], runs: list[FixedRun]) -> list[Step]:
        out: list[Step] = []
        pending: list[ir.AnyField] = []

        def flush() -> None:
            if pending:
                run = self.run(list(pending), len(runs))
                runs.append(run)
                out.append(run)
                pending.clear()

        i = 0
        while i < len(fields):
            f = fields[i]
            if f.conditional:
                flush()
                group = [f]
                while i + 1 < len(fields) and condition_of(fields[i + 1]) == condition_of(f):
                    i += 1
                    group.append(fields[i])
                inner = self.steps([_unconditional(g) for g in group], runs)
                out.append(CondGroup(condition_of(f), group, inner))
            elif ir.in_fixed_run(f):
                pending.append(f)
            else:
                flush()
                item = self.item(f) if isinstance(f, ir.GroupField) else None
                out.append(VarField(f, f.name, item))
            i += 1
        flush()
        return out

    def run(self, fields: list[ir.AnyField], index: int) -> FixedRun:
        members, leaves, at = [], [], 0
        for f in fields:
            item = self.item(f) if isinstance(f, ir.GroupField) else None
            mine = self.leaves(f, f.name, at)
            members.append(Member(f, at, len(leaves), len(mine), item))
            leaves += mine
            at += f.fixed_size
        return FixedRun(index, at, members, leaves)

    def leaves(self, f: ir.AnyField, path: str, at: int) -> list[Leaf]:
        if isinstance(f, ir.ScalarField):
            return [Leaf(path, at, f.scalar)]
        if isinstance(f, ir.ArrayField):
            return [Leaf(f"{path}[{k}]", at + k * f.scalar.size, f.scalar) for k in range(f.count)]
        assert isinstance(f, ir.GroupField) and f.count is not None
        out = []
        for k in range(f.count):
            for g in f.item.fields:
                out += self.leaves(g, f"{path}[{k}].{g.name}", at)
                at += g.fixed_size
        return out


def _unconditional(f: ir.AnyField) -> ir.AnyField:
    """The same field planned inside its condition group."""
    g = copy.copy(f)
    g.present_if = None
    g.versions = ir.ALL_VERSIONS
    return g


# ---- messages and the protocol ------------------------------------------------------------

@dataclass
class HeaderSlot:
    """One fixed field of a message's common header, or its subtype byte."""

    field: ir.ScalarField
    offset: int                      # from the message's first byte
    is_subtype: bool = False


@dataclass
class LayoutChoice:
    """A layout a type code can have."""

    layout: model.Layout
    plan: LayoutPlan


@dataclass
class Variant:
    """One form a type code takes on the wire: a layout with the fields that a set of software
    versions sends. `ranges` are the versions (as ir.version_number pairs, inclusive); `sizes`
    the body sizes it can have (its flag-conditioned parts in or out), or None when a variable
    part makes it open-ended (then it needs at least `min_size`). A stream whose version is not
    known decodes a variant chosen by length with `rep`, the version it stands for."""

    choice: LayoutChoice
    ranges: list[tuple[int, int]]
    sizes: Optional[frozenset[int]]
    min_size: int
    rep: ir.Version
    plan: Optional[LayoutPlan] = None   # the layout as this form sends it: no version conditions
    releases: list[tuple[int, int]] = field(default_factory=list)   # the released series (numbers)

    @property
    def layout(self) -> model.Layout:
        return self.choice.layout

    def describe(self) -> str:
        """"3.5 and later", "3.2 to 3.9 or 5.0 to 5.3": ranges that only unreleased versions
        separate read as one."""
        shown: list[tuple[int, int]] = []
        for lo, hi in self.ranges:
            if shown and not any(a < lo and b > shown[-1][1] for a, b in self.releases):
                shown[-1] = (shown[-1][0], hi)
            else:
                shown.append((lo, hi))
        first = self.releases[0][0] if self.releases else 0
        return " or ".join(_range_text(lo, hi, first) for lo, hi in shown)


@dataclass(frozen=True)
class Segment:
    """A piece of the version axis within which every type code of every message sends one
    form: the versions from `first` (None: every version below `upto`) up to, not including,
    `upto` (None: no end)."""

    first: Optional[ir.Version]
    upto: Optional[ir.Version]
    after: Optional[ir.Version] = None
    """The last version of a range that ends just before `first`, when `first` is no version of
    its own (between two series, or past an X.99: ir.past_last_minor): said as "after 5.99"."""

    def describe(self) -> str:
        """"up to 1.5", "1.8", "1.6 to 1.7", "5.4 to 5.25.0", "3.16 to before 5.0",
        "after 5.99, before 10.0", "10.0 and later", "after 10.99"."""
        if self.after is not None:
            since = f"after {ir.version_text(self.after)}"
            return f"{since}, before {ir.version_text(self.upto)}" if self.upto else f"{since}"
        if self.upto is None:
            return f"{ir.version_text(self.first)} and later" if self.first else "all versions"
        major, minor, bugfix = self.upto
        if bugfix:
            last = "%d.%d.%d" % (major, minor, bugfix - 1)
        elif minor:
            last = ir.version_text((major, minor - 1, ir.BUGFIX_ANY))
        else:
            last = f"before {ir.version_text(self.upto)}"
        if self.first is None:
            return last if last.startswith("before") else f"up to {last}"
        first = ir.version_text(self.first)
        return first if first == last else f"{first} to {last}"


@dataclass(frozen=True)
class SegmentForm:
    """The form a type code takes in one segment: its index among the code's variants. When no
    form is sent there (between two series, or newer than the spec knows) it is the form of the
    nearest version below, else the first, and `nearest` says so: it is read as its `rep`."""

    form: int
    nearest: bool = False


@dataclass
class MessagePlan:
    message: model.Message
    header: list[HeaderSlot]         # dispatch messages: the common header, then the subtype
    body_offset: int                 # the first sub-package, or the subtype's (body's) first field
    subtype_offset: Optional[int]    # None for a robot state or a body message
    choices: dict[int, list[LayoutChoice]]   # type code -> the layouts it can have
    variants: dict[int, list[Variant]] = field(default_factory=dict)   # type code -> its forms
    # type code -> its form in each segment of ProtocolPlan.segments
    by_segment: dict[int, list[SegmentForm]] = field(default_factory=dict)
    # type code -> {body size: the index of the one fixed-size form of that size}: the forms a
    # part's length alone recognises (an open-ended form fits too much to be recognised)
    by_length: dict[int, dict[int, int]] = field(default_factory=dict)

    @property
    def is_dispatch(self) -> bool:
        return isinstance(self.message, model.DispatchMessage)

    @property
    def layouts(self) -> list[LayoutChoice]:
        return [c for choices in self.choices.values() for c in choices]

    def forms_of(self, layout: model.Layout) -> list["Variant"]:
        """The forms of one layout (a code with two layouts has forms of each)."""
        return [v for v in self.variants.get(layout.code.value, []) if v.layout is layout]


@dataclass
class VersionSkip:
    """On the way to the version numbers: `fixed` bytes, then a string whose length prefix is
    `prefix` bytes (signed or not)."""

    fixed: int
    prefix: int
    signed: bool


@dataclass
class VersionSource:
    """Where a stream announces its software version: which message and subtype, and how to
    reach the major and minor numbers from the body's start."""

    message_code: int
    subtype_code: int
    subtype_offset: int
    body_offset: int
    layout: model.Layout
    major: ir.ScalarField
    minor: ir.ScalarField
    bugfix: Optional[ir.ScalarField]  # right after minor, in the versions its condition gives
    skips: list[VersionSkip]
    tail: int                        # bytes after the last skip up to major
    rest: int                        # least bytes after minor


@dataclass
class ProtocolPlan:
    protocol: model.Protocol
    header_size: int
    package_header_size: int
    messages: list[MessagePlan]
    version: VersionSource
    items: list[ItemPlan]
    segments: list[Segment]          # the version axis, cut wherever a form starts or ends

    def segment_of(self, version: ir.Version) -> int:
        """The index of the segment that holds `version`."""
        return max(k for k, s in enumerate(self.segments) if s.first is None or s.first <= version)

    def message(self, name: str) -> MessagePlan:
        for m in self.messages:
            if m.message.name == name:
                return m
        raise KeyError(name)

    def item_of(self, group: ir.GroupField) -> ItemPlan:
        for it in self.items:
            if it.group is group:
                return it
        raise KeyError(group.name)


def _version_source(p: model.Protocol, messages: list[MessagePlan], problems: list[Problem]) -> Optional[VersionSource]:
    found = [(m, c.layout) for m in messages for c in m.layouts if c.layout.sets_version]
    if len(found) != 1:
        where = found[1][1].where if found[1:] else p.messages[0].where if p.messages else ir.NOWHERE
        problems.append(where.problem(f"exactly one layout must set the version ({len(found)} do)"))
        return None
    m, lay = found[0]
    major_name, minor_name, bugfix_name = lay.sets_version
    names = [f.name for f in lay.struct.fields]
    if names.index(minor_name) != names.index(major_name) + 1:
        problems.append(lay.where.problem("sets_version: the minor number must follow the major number"))
        return None
    bugfix = lay.struct.field(bugfix_name) if bugfix_name else None
    between = lay.struct.fields[names.index(minor_name) + 1:names.index(bugfix_name)] if bugfix else []
    if bugfix is not None and any(g.present_if or g.versions.overlaps(bugfix.versions) for g in between):
        problems.append(lay.where.problem("sets_version: the bugfix number must follow the minor number"))
    skips, at = [], 0
    for f in lay.struct.fields[:names.index(major_name)]:
        if isinstance(f, ir.StringField) and f.length is not None and not f.conditional:
            skips.append(VersionSkip(at, f.length.size, f.length.signed))
            at = 0
        elif f.fixed_size is not None and not f.conditional:
            at += f.fixed_size
        else:
            problems.append(f.where.problem("the version numbers must be reachable through fixed fields and "
                                            "length-prefixed strings"))
            return None
    after = lay.struct.fields[names.index(minor_name) + 1:]
    return VersionSource(m.message.code.value, lay.code.value, m.subtype_offset, m.body_offset, lay,
                         lay.struct.field(major_name), lay.struct.field(minor_name), bugfix, skips, at,
                         sum(0 if f.conditional else f.min_size for f in after))


# ---- variants: the forms of a type code across software versions ---------------------------

_TOP = ir.version_number((1 << 20, 0, 0))


def _bounds(r: ir.VersionRange) -> tuple[int, int]:
    return (ir.version_number(r.low) if r.low else 0, ir.version_number(r.high) if r.high else _TOP)


def _range_text(lo: int, hi: int, first: int = 0) -> str:
    """A range of version numbers as a reader says it (ir.VersionRange.describe)."""
    return ir.VersionRange(ir.version_of_number(lo), ir.version_of_number(hi) if hi < _TOP else None).describe(
        ir.version_of_number(first))


def _fields_by_version(struct: ir.Struct) -> list[ir.AnyField]:
    return [f for f in struct.fields if not f.versions.unbounded]


def _variants(options: list[LayoutChoice], default: ir.Version,
              releases: list[tuple[int, int]]) -> list[Variant]:
    """Cut the version axis wherever a layout or a field of one starts or ends; each piece
    sends one layout with one set of fields. Pieces that send the same are one variant. Only
    released versions count (`releases`): a piece between two series is no one's."""
    cuts = {0, _TOP + 1}
    for c in options:
        for r in [c.layout.versions] + [f.versions for f in _fields_by_version(c.layout.struct)]:
            lo, hi = _bounds(r)
            cuts |= {lo, hi + 1}
    points = sorted(cuts)
    found: dict[tuple, Variant] = {}
    for lo, nxt in zip(points, points[1:]):
        sample = ir.version_of_number(lo)
        for c in options:
            if not c.layout.versions.contains(sample):
                continue
            released = [(max(lo, a), min(nxt - 1, b)) for a, b in releases if max(lo, a) <= min(nxt - 1, b)]
            if not released:
                continue
            present = tuple(_signature(f) for f in c.layout.struct.fields if f.versions.contains(sample))
            key = (id(c), present)
            if key in found:
                found[key].ranges += released
            else:
                fields = [f for f in c.layout.struct.fields if f.versions.contains(sample)]
                sizes, least = _sizes(fields)
                found[key] = Variant(c, released, sizes, least, default)
    variants = list(found.values())
    for v in variants:
        _merge_adjacent(v.ranges)
        v.rep = _representative(v.ranges, default)
        v.releases = releases
    return variants


def _signature(f: ir.AnyField) -> tuple:
    """What a field puts on the wire: two entries alike in this read the same bytes alike."""
    scalar = getattr(f, "scalar", None)
    return (f.name, type(f).__name__, scalar.name if scalar else None, f.present_if, getattr(f, "count", None),
            id(getattr(f, "enum", None)))


def _releases(p: model.Protocol) -> list[tuple[int, int]]:
    """The released version series as number ranges: only the gaps between them are left out,
    so that a version before the first or after the last still has its forms."""
    ranges = [_bounds(r) for _, r in p.generations] or [(0, _TOP)]
    _merge_adjacent(ranges)
    ranges[0] = (0, ranges[0][1])
    ranges[-1] = (ranges[-1][0], _TOP)
    return ranges


def _sizes(fields: list[ir.AnyField]) -> tuple[Optional[frozenset[int]], int]:
    """The body sizes of a field list: fixed parts, plus each flag's fields in or out."""
    base, flagged = 0, {}
    for f in fields:
        if f.fixed_size is None:
            return None, sum(g.min_size for g in fields if not g.present_if)
        if f.present_if:
            flagged[f.present_if] = flagged.get(f.present_if, 0) + f.fixed_size
        else:
            base += f.fixed_size
    sizes = {base}
    for extra in flagged.values():
        sizes |= {s + extra for s in sizes}
    return frozenset(sizes), base


def _merge_adjacent(ranges: list[tuple[int, int]]) -> None:
    ranges.sort()
    i = 0
    while i + 1 < len(ranges):
        if ranges[i][1] + 1 >= ranges[i + 1][0]:
            ranges[i:i + 2] = [(ranges[i][0], max(ranges[i][1], ranges[i + 1][1]))]
        else:
            i += 1


def _representative(ranges: list[tuple[int, int]], default: ir.Version) -> ir.Version:
    """The version a variant stands for: the default where it covers it, else its newest
    version below the default, else its oldest."""
    d = ir.version_number(default)
    below = [(lo, min(hi, d)) for lo, hi in ranges if lo <= d]
    lo, hi = max(below, key=lambda r: r[1]) if below else (ranges[0][0], ranges[0][0])
    # A bound of any bugfix release ("up to 1.8") stands for its first one: a real version.
    major, minor, bugfix = ir.version_of_number(hi)
    return max(ir.version_of_number(lo), (major, minor, 0)) if bugfix == ir.BUGFIX_ANY else (major, minor, bugfix)


# ---- segments: one lookup gives every type code's form at a version -------------------------

def _after(number: int) -> Optional[ir.Version]:
    """The first version above an inclusive upper bound (a number of the plan): after "up to
    5.8" (any 5.8.x) comes 5.9, after 5.25.0 comes 5.25.1; None after the open end."""
    if number >= _TOP:
        return None
    major, minor, bugfix = ir.version_of_number(number)
    return (major, minor + 1, 0) if bugfix == ir.BUGFIX_ANY else (major, minor, bugfix + 1)


def _segments(messages: list[MessagePlan], series: list[ir.VersionRange]) -> list[Segment]:
    """The version axis cut wherever any form of any type code starts or ends. A segment that
    starts outside every released series (between two of them), or past an X.99 bound, is said
    from the end before it."""
    starts_of_ranges: set[ir.Version] = set()
    ends: dict[ir.Version, ir.Version] = {}   # the version after a range's end -> that end
    for mp in messages:
        for variants in mp.variants.values():
            for v in variants:
                for lo, hi in v.ranges:
                    if lo:
                        starts_of_ranges.add(ir.version_of_number(lo))
                    if _after(hi) is not None:
                        ends[_after(hi)] = ir.version_of_number(hi)
    starts: list[Optional[ir.Version]] = [None] + sorted(starts_of_ranges | set(ends))

    def said_from_the_end(first: Optional[ir.Version]) -> bool:
        if first is None:
            return False
        between_series = bool(series) and not any(r.contains(first) for r in series)
        return between_series or ir.past_last_minor(first) is not None

    return [Segment(first, upto, ends.get(first) if said_from_the_end(first) else None)
            for first, upto in zip(starts, starts[1:] + [None])]


def _by_segment(variants: list[Variant], segments: list[Segment]) -> list[SegmentForm]:
    """The form of one type code in each segment: the one its versions send, else the nearest
    below's (else the first)."""
    out = []
    for s in segments:
        at = ir.version_number(s.first) if s.first else 0
        sent = [k for k, v in enumerate(variants) if any(lo <= at <= hi for lo, hi in v.ranges)]
        if sent:
            out.append(SegmentForm(sent[0]))
        else:
            below = [(lo, k) for k, v in enumerate(variants) for lo, _ in v.ranges if lo <= at]
            out.append(SegmentForm(max(below)[1] if below else 0, nearest=True))
    return out


def _by_length(variants: list[Variant]) -> dict[int, int]:
    """Body sizes that exactly one fixed-size form of a type code has, with that form's index."""
    holders: dict[int, list[int]] = {}
    for k, v in enumerate(variants):
        for size in sorted(v.sizes or ()):
            holders.setdefault(size, []).append(k)
    return {size: ks[0] for size, ks in sorted(holders.items()) if len(ks) == 1}


def plan(p: model.Protocol) -> ProtocolPlan:
    """Plan every layout of the protocol; problems name the spec's path and line."""
    problems: list[Problem] = []
    planner = _Planner(problems)
    releases = _releases(p)
    messages = []
    for m in p.messages:
        choices: dict[int, list[LayoutChoice]] = {}
        if isinstance(m, model.PackageListMessage):
            header, body, subtype_offset = [], p.header_size, None
            layouts = m.packages
        else:
            header, at = [], p.header_size
            for f in m.header.fields:
                header.append(HeaderSlot(f, at))
                at += f.scalar.size
            subtype_offset, body = None, at
            if m.subtype is not None:
                header.append(HeaderSlot(m.subtype, at, is_subtype=True))
                subtype_offset, body = at, at + m.subtype.scalar.size
            layouts = m.subtypes
        for lay in layouts:
            choices.setdefault(lay.code.value, []).append(LayoutChoice(lay, planner.layout(lay.struct)))
        variants = {code: _variants(options, p.default_version, releases) for code, options in choices.items()}
        for forms in variants.values():
            for v in forms:
                v.plan = planner.layout(v.layout.struct.at(v.rep))
        messages.append(MessagePlan(m, header, body, subtype_offset, choices, variants))
    segments = _segments(messages, [r for _, r in p.generations])
    for mp in messages:
        mp.by_segment = {code: _by_segment(forms, segments) for code, forms in mp.variants.items()}
        mp.by_length = {code: _by_length(forms) for code, forms in mp.variants.items()}
    version = _version_source(p, messages, problems)
    if problems:
        raise SpecError(p.source, problems)
    return ProtocolPlan(p, p.header_size, p.package_header_size, messages, version,
                        list(planner.items.values()), segments)
