"""Every MCAP file the MCAP tests write, read by Foxglove's own TypeScript reader (@mcap/core with
@mcap/nodejs, the library the Foxglove app reads with) under Node.js: the script
tests/node/read_mcap.mjs prints what it reads as JSON, which must be what the Python reader reads:
the summary, the chunk indexes, the metadata and every message (each strict JSON: JSON.parse).
`npm ci --prefix tests/node` (scripts/setup.sh) installs the packages its lock file pins; without
Node.js or them the tests are skipped, except in CI (CI=true), where they fail."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

from tests.python.test_mcap import ROOT, dashboard_capture, export, raw_vector, read_back

NODE_DIR = ROOT / "tests" / "node"


def node() -> str:
    found = shutil.which("node")
    missing = ("node is not on PATH" if found is None else
               None if (NODE_DIR / "node_modules" / "@mcap" / "nodejs").is_dir() else
               "the npm packages are not installed: npm ci --prefix tests/node")
    if missing:
        if os.environ.get("CI") == "true":
            pytest.fail(missing)
        pytest.skip(missing)
    return found


def read_with_node(path: Path) -> dict:
    done = subprocess.run([node(), str(NODE_DIR / "read_mcap.mjs"), str(path)], capture_output=True, text=True,
                          timeout=120, cwd=NODE_DIR)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def assert_both_read_alike(path: Path) -> dict:
    """Node's reader and Python's find the same summary, chunk indexes, metadata and messages."""
    node_read = read_with_node(path)
    summary, messages, metadata = read_back(path)
    assert node_read["header"]["library"].startswith("urwire ")
    stats = node_read["statistics"]
    assert int(stats["messageCount"]) == summary.statistics.message_count == len(messages)
    assert stats["channelCount"] == len(summary.channels) and stats["schemaCount"] == len(summary.schemas)
    assert {int(k): int(v) for k, v in stats["channelMessageCounts"].items()} == \
        summary.statistics.channel_message_counts
    assert {s["id"]: (s["name"], s["encoding"], s["data"]) for s in node_read["schemas"]} == \
        {i: (s.name, s.encoding, s.data.decode()) for i, s in summary.schemas.items()}
    assert {c["id"]: (c["topic"], c["schemaId"], c["messageEncoding"]) for c in node_read["channels"]} == \
        {i: (c.topic, c.schema_id, c.message_encoding) for i, c in summary.channels.items()}
    assert node_read["metadata"] == [{"name": name, "metadata": data} for name, data in metadata]
    assert [(int(c["messageStartTime"]), int(c["messageEndTime"]), c["compression"], sorted(c["channels"]))
            for c in node_read["chunkIndexes"]] == \
        [(c.message_start_time, c.message_end_time, c.compression, sorted(c.message_index_offsets))
         for c in summary.chunk_indexes]
    assert [(m["channelId"], m["sequence"], int(m["logTime"]), int(m["publishTime"]), m["data"])
            for m in node_read["messages"]] == \
        [(m.channel_id, m.sequence, m.log_time, m.publish_time, m.data.decode()) for _, _, m in messages]
    return node_read


def test_the_cell_sample_as_foxglove_reads_it(tmp_path):
    node_read = assert_both_read_alike(export(tmp_path))
    assert {c["compression"] for c in node_read["chunkIndexes"]} == {"zstd"}
    assert len(node_read["messages"]) == 88 and len(node_read["channels"]) == 54


@pytest.mark.parametrize("source", ["generation_eseries_5_11_robot_state", "nonfinite_floats", "dashboard"])
def test_the_other_exports_as_foxglove_reads_them(source, tmp_path):
    made = dashboard_capture(tmp_path) if source == "dashboard" else raw_vector(tmp_path, source)
    assert assert_both_read_alike(export(tmp_path / "out", made))["messages"]
