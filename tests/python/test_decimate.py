"""Min/max decimation for plot: bounded points, every extreme kept, the line's order kept."""
from __future__ import annotations

import math

from urwire.data.decimate import MinMaxLines


def test_few_points_come_back_as_they_went_in():
    lines = MinMaxLines(max_buckets=8)
    for x in range(5):
        lines.add(x, [x * 2.0, None if x == 2 else -x])
    assert lines.line(0) == ([0, 1, 2, 3, 4], [0.0, 2.0, 4.0, 6.0, 8.0])
    assert lines.line(1) == ([0, 1, 3, 4], [0, -1, -3, -4])


def test_any_number_of_points_keeps_a_bounded_number_and_every_extreme():
    lines = MinMaxLines(max_buckets=16)
    n = 10_000
    for x in range(n):
        lines.add(x, [math.sin(x / 50.0) + (5.0 if x == 7_777 else 0.0), float("nan")])
    xs, ys = lines.line(0)
    assert lines.points == n and len(xs) <= 2 * 16
    assert xs == sorted(xs)
    assert (7_777, math.sin(7_777 / 50.0) + 5.0) in zip(xs, ys)       # a lone spike survives
    assert min(ys) == min(math.sin(x / 50.0) for x in range(n))
    assert lines.line(1) == ([], [])                                   # NaNs draw nothing
