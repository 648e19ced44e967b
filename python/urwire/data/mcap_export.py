"""`urwire export --format mcap`: a capture as one MCAP file (urwire.mcap_recording, docs/mcap.md)."""
from __future__ import annotations

import os
import sys
from pathlib import Path

from ..mcap_recording import McapRecording, mcap_missing
from .export_failure import FAILED, export_failed
from .records import records_of_file


def export_mcap(path: str, out: str, hint=None) -> int:
    """`urwire export --format mcap`: the capture at `path` as OUT/<its name>.mcap. Exit status as
    for export: 1 when a record holds an error, 2 when the file cannot be read or written."""
    if mcap_missing():
        print(f"urwire export: {mcap_missing()}", file=sys.stderr)
        return FAILED
    target = Path(out) / (Path(path).stem + ".mcap")
    try:
        os.makedirs(out, exist_ok=True)
        with open(path, "rb") as fh, open(target, "wb") as sink:
            recording = McapRecording(sink)
            for position, record in enumerate(records_of_file(fh, hint)):
                recording.add(position, record)
            recording.finish()
    except (OSError, ValueError) as exc:
        return export_failed(path, exc)
    for topic in sorted(recording.counts):
        print(f"{topic}: {recording.counts[topic]} messages", file=sys.stderr)
    print(f"wrote {target}", file=sys.stderr)
    return 1 if any(topic.endswith("/error") for topic in recording.counts) else 0
