"""The kind `lines`: interfaces that speak in text lines (the dashboard server, port 29999).

A client's commands and the server's replies are lines ending in a newline; the spec lists
every command with its replies (patterns with placeholders), which say an error, and the
software versions that have each command (spec/ur_dashboard.yaml)."""
from __future__ import annotations

from .. import define
from . import c, diff, epan, lua, plan, python, resolve

KIND = define("lines", "lines.schema.json", resolve, plan, [c, epan, lua, python],
             diff.diff)
