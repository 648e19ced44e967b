"""The kind `packages`, the primary/secondary interface (spec/ur_primary.yaml): messages framed by
an int32 length and a type byte, robot state made of sub-packages, layouts gated by software
version. model.py is its IR, resolve.py builds it, plan.py plans every layout once, dissector.py
computes from the plan what both Wireshark dissectors show, and c.py, epan.py, lua.py and
python.py render the targets; naming.py spells its identifiers, and pin.py (one version's build)
and reference.py (docs/protocol.md, `codegen diff`) read the plan too."""
from __future__ import annotations

from .. import DEFAULT_KIND, define
from . import c, epan, lua, plan, python, reference, resolve

KIND = define(DEFAULT_KIND, "spec.schema.json", resolve, plan, [c, epan, lua, python],
             reference.diff)
