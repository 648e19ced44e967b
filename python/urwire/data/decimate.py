"""Lines of any length drawn from a bounded number of points: min/max decimation.

The points of all lines share their x values and come in order. They are gathered into at most
MAX_BUCKETS buckets of `width` consecutive points; when the buckets are full, neighbours merge
and the width doubles, so memory stays the same however many points come. Each bucket keeps,
per line, its lowest and its highest point, so the drawn line keeps every peak and dip: at the
width of an image (a pixel holds many buckets) it looks as the full line would.
"""
from __future__ import annotations

import math
from typing import Optional, Sequence

MAX_BUCKETS = 4096   # per line, two points each: far more than an image has pixels across


class _Bucket:
    __slots__ = ("count", "extremes")

    def __init__(self) -> None:
        self.count = 0
        self.extremes: dict[int, list] = {}   # line -> [lowest y, its x, highest y, its x]

    def merge(self, later: "_Bucket") -> None:
        self.count += later.count
        for line, (low, low_x, high, high_x) in later.extremes.items():
            self.take(line, low, low_x)
            self.take(line, high, high_x)

    def take(self, line: int, y: float, x) -> None:
        kept = self.extremes.get(line)
        if kept is None:
            self.extremes[line] = [y, x, y, x]
            return
        if y < kept[0]:
            kept[0], kept[1] = y, x
        if y > kept[2]:
            kept[2], kept[3] = y, x


class MinMaxLines:
    """Add points (an x and one y per line, None where a line has none); read back each line's
    lowest and highest point per bucket, in x order."""

    def __init__(self, max_buckets: int = MAX_BUCKETS) -> None:
        if max_buckets < 2 or max_buckets % 2:
            raise ValueError("max_buckets must be even and at least 2")
        self.max_buckets = max_buckets
        self.width = 1          # points per bucket
        self.points = 0         # points added
        self.lines = 0          # the most y values a point has had
        self._buckets: list[_Bucket] = []

    def add(self, x, values: Sequence[Optional[float]]) -> None:
        if not self._buckets or self._buckets[-1].count == self.width:
            if len(self._buckets) == self.max_buckets:
                self._halve()
            if not self._buckets or self._buckets[-1].count == self.width:
                self._buckets.append(_Bucket())
        bucket = self._buckets[-1]
        bucket.count += 1
        self.points += 1
        self.lines = max(self.lines, len(values))
        for line, y in enumerate(values):
            if y is not None and not math.isnan(y):
                bucket.take(line, y, x)

    def _halve(self) -> None:
        merged = []
        for i in range(0, len(self._buckets), 2):
            first = self._buckets[i]
            if i + 1 < len(self._buckets):
                first.merge(self._buckets[i + 1])
            merged.append(first)
        self._buckets = merged
        self.width *= 2

    def line(self, index: int) -> tuple[list, list]:
        """(x values, y values) of one line: per bucket, its lowest and highest point in x order."""
        xs: list = []
        ys: list = []
        for bucket in self._buckets:
            kept = bucket.extremes.get(index)
            if kept is None:
                continue
            low, low_x, high, high_x = kept
            points = [(low_x, low)] if (low_x, low) == (high_x, high) else sorted([(low_x, low), (high_x, high)],
                                                                                  key=lambda p: p[0])
            for x, y in points:
                xs.append(x)
                ys.append(y)
        return xs, ys
