#!/usr/bin/env bash
# docs/img/recording-view.png from scratch (`make docs-pictures`): a simulated robot recorded as MCAP
# by `urwire listen --mcap`, then drawn from that file by `urwire plot`. The commands below the
# line are the ones docs/recording-view.md shows, word for word (tests/test_recording_view.py).
set -euo pipefail
cd "$(dirname "$0")/.."
urwire() { PYTHONPATH=python:generated/python "${PYTHON:-python3}" -m urwire "$@"; }
mkdir -p build
# ---- the commands of docs/recording-view.md
urwire serve --port 31101 --rate 50 --duration 25 &     # a simulated UR5e (software 5.11): every interface
sleep 1                                                 # while serve opens its ports
urwire listen 127.0.0.1:31101 --out build/recording-view.jsonl --mcap build/recording-view.mcap --duration 20
urwire plot build/recording-view.mcap --out docs/img/recording-view.png
wait                                                    # serve stops after its 25 s
