"""`urwire export` holds a table's rows by column, a chunk at a time, and spills full chunks to
disk: rows whose columns differ (a version change, an optional field) must come back whole and
in order, whatever the chunk and batch sizes. The command's tables and memory are tested in
test_live.py and test_memory.py."""
from __future__ import annotations

import random

import pytest
from urwire.data import export


def table_rows(tables: export.Tables, name: str) -> list[dict]:
    names = list(tables.kinds[name])
    rows = []
    for count, columns in tables.batches(name):
        assert all(len(values) == count for values in columns)
        rows += [dict(zip(names, values)) for values in zip(*columns)]
    return rows


@pytest.mark.parametrize("spill, batch", [(1, 1), (3, 4), (4, 3), (1024, 8192)])
def test_rows_come_back_whole_when_columns_come_and_go(tmp_path, monkeypatch, spill, batch):
    monkeypatch.setattr(export, "SPILL_ROWS", spill)
    monkeypatch.setattr(export, "BATCH_ROWS", batch)
    rng = random.Random(spill * 100 + batch)
    tables = export.Tables(tmp_path)
    expected = {"a": [], "b": []}
    for position in range(50):
        table = rng.choice("ab")
        present = [c for c in ("x", "y", "z") if rng.random() < 0.6]
        columns = [(c, "int", position * 10 + i) for i, c in enumerate(present)]
        tables.add(table, position, columns, time=position / 10 if table == "a" else None)
        row = {"position": position, **({"capture_time": position / 10} if table == "a" else {})}
        expected[table].append({**row, **{c: v for c, _, v in columns}})
    try:
        for name, rows in expected.items():
            names = list(tables.kinds[name])
            assert tables.counts[name] == len(rows)
            assert table_rows(tables, name) == [{n: row.get(n) for n in names} for row in rows]
    finally:
        tables.close()
