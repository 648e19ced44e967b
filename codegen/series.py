"""Software series (CB2, CB3, e-Series, PolyScope X: the primary spec's `protocol.generations`)
and the rules a `versions:` range keeps against them.

A range is stated per series: `{from: "5.27", through: "e-Series"}` ends with the e-Series, and
`through:` the last series (which is open) runs on through every later version. An open
`{from: F}` is allowed only in the last series, so that a change in one series never leaks into
the next unless the spec says so. `until:` keeps its meaning: an explicit bound, in any series.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from . import ir


@dataclass(frozen=True)
class Series:
    name: str
    versions: ir.VersionRange

    def describe(self) -> str:
        """"e-Series: 5.0 to 5.99", "PolyScope X: 10.0 and later"."""
        return f"{self.name}: {self.versions.describe()}"


def index_of(series: list[Series], version: ir.Version) -> Optional[int]:
    """The position of the series a version lies in, or None (2.x, 4.x, past a series' end)."""
    for i, s in enumerate(series):
        if s.versions.contains(version):
            return i
    return None


def range_problems(series: list[Series], raw: dict, low: Optional[ir.Version],
                   high: Optional[ir.Version]) -> list[tuple[Optional[str], str]]:
    """What is wrong with a written range against the declared series, as (key of the range
    the problem is at, or None for the range itself, message). `high` is the resolved upper
    bound (`until:`, or the end of the `through:` series)."""
    out: list[tuple[Optional[str], str]] = []
    if "through" in raw and "until" in raw:
        out.append((None, "give either `until:` (an explicit last version) or `through:` (the end of a "
                          "series), not both"))
    if not series:
        if "through" in raw:
            out.append(("through", "`through:` names a series, and this spec declares none"))
        return out
    names = "; ".join(s.describe() for s in series)
    first = None
    if low is not None:
        first = index_of(series, low)
        if first is None:
            out.append(("from", f"{raw['from']} lies in no series ({names})"))
    if "until" in raw and index_of(series, high) is None:
        out.append(("until", f"{raw['until']} lies in no series ({names})"))
    if "through" in raw:
        named = [i for i, s in enumerate(series) if s.name == raw["through"]]
        if not named:
            out.append(("through", f"'{raw['through']}' is not a series ({names})"))
        elif first is not None and named[0] < first:
            out.append(("through", f"{series[named[0]].name} ends before {raw['from']} "
                                   f"({series[first].name}) starts"))
    elif "until" not in raw and first is not None and first < len(series) - 1:
        out.append((None, _open_range_message(series, first, raw["from"])))
    return out


def _open_range_message(series: list[Series], first: int, start: str) -> str:
    names = [s.name for s in series[first + 1:]]
    later = " and ".join([", ".join(names[:-1]), names[-1]] if len(names) > 1 else names)
    return (f"{{from: \"{start}\"}} has no end, so it would run on into {later}: say which series it runs "
            f"through, `through: \"{series[first].name}\"` ({series[first].name} only) or "
            f"`through: \"{series[-1].name}\"` (every later series too)")


def through_end(series: list[Series], name: str) -> Optional[ir.Version]:
    """The last version of the series `name`: its `until`, or None (unbounded) for the last
    series, which is open. None too for a name that is no series (range_problems says so)."""
    for s in series:
        if s.name == name:
            return s.versions.high
    return None


# ---- tables with a column per series (RTDE variables, dashboard commands) ----------------------

NONE, UNKNOWN = "none", "unknown"      # a column's value that is no version
E_SERIES_FROM = (5, 0, 0)              # the first e-Series and PolyScope X versions, as the
POLYSCOPE_X_FROM = (10, 0, 0)          # primary spec's protocol.generations gives them


def polyscope_x_first(e_series, stated, follows: Optional[ir.Version]):
    """A table row's first PolyScope X version (a Version, NONE or UNKNOWN) and a problem, or None.

    `stated` is the row's own `polyscope_x:` (a version text or "none"), which wins. Without it the
    row is on PolyScope X from its first version exactly when the e-Series has it from a version
    PolyScope X is known to follow (`polyscope_x_follows:`, `follows`): what 10.x read from the
    e-Series column before the table had its own. A newer e-Series row must say so, or a row made
    for 5.x would be offered on every 10.x."""
    if stated is not None:
        if stated == NONE:
            return NONE, None
        first = ir.parse_version(stated)
        if first < POLYSCOPE_X_FROM:
            return NONE, f"{stated} is not a PolyScope X version ({ir.version_text(POLYSCOPE_X_FROM)} or later)"
        return first, None
    if e_series in (NONE, UNKNOWN):
        return e_series, None
    if follows is not None and e_series <= follows:
        return POLYSCOPE_X_FROM, None
    known = f"`polyscope_x_follows: \"{ir.version_text(follows)}\"`" if follows else "no `polyscope_x_follows:`"
    return NONE, (f"e-Series {ir.version_text(e_series)} is newer than the last e-Series version PolyScope X is "
                  f"known to follow ({known}): state `polyscope_x:`, the first 10.x version that has it, "
                  f"or \"none\"")
