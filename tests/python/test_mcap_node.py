"""The MCAP file `urwire export --format mcap` writes, read by Foxglove's own TypeScript reader
(@mcap/core with @mcap/nodejs, the library the Foxglove app reads with) under Node.js: the script
tests/node/read_mcap.mjs prints what it reads as JSON, which must be what the Python reader reads.
`npm ci --prefix tests/node` (scripts/setup.sh) installs the packages its lock file pins; without
Node.js or them the test is skipped, except in CI (CI=true), where it fails."""
from __future__ import annotations

import json
import os
import shutil
import subprocess

import pytest

from tests.python.test_mcap import ROOT, export, read_back

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


@pytest.fixture(scope="module")
def both(tmp_path_factory) -> tuple:
    """What Node's reader and Python's read in one exported file."""
    path = export(tmp_path_factory.mktemp("mcap"))
    done = subprocess.run([node(), str(NODE_DIR / "read_mcap.mjs"), str(path)], capture_output=True, text=True,
                          timeout=120, cwd=NODE_DIR)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout), read_back(path)


def test_summary_as_foxglove_reads_it(both):
    node_read, (summary, messages, metadata) = both
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


def test_chunk_indexes_as_foxglove_reads_them(both):
    node_read, (summary, _, _) = both
    assert [(int(c["messageStartTime"]), int(c["messageEndTime"]), c["compression"], sorted(c["channels"]))
            for c in node_read["chunkIndexes"]] == \
        [(c.message_start_time, c.message_end_time, c.compression, sorted(c.message_index_offsets))
         for c in summary.chunk_indexes]
    assert {c["compression"] for c in node_read["chunkIndexes"]} == {"zstd"}


def test_every_message_as_foxglove_reads_it(both):
    node_read, (_, messages, _) = both
    assert [(m["channelId"], m["sequence"], int(m["logTime"]), int(m["publishTime"]), m["data"])
            for m in node_read["messages"]] == \
        [(m.channel_id, m.sequence, m.log_time, m.publish_time, m.data.decode()) for _, _, m in messages]
