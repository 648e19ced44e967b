"""The kind `typed_messages`: length-framed messages whose type code means one layout per direction
and negotiated protocol version, with state kept per connection (RTDE's recipes). The spec language
part is codegen/schema/typed_messages.schema.json; `resolve` makes the IR (model.py), `plan` the
decisions every target shares (plan.py); each target renders the plan (c.py, epan.py, lua.py,
python.py)."""
from __future__ import annotations

from .. import define
from . import c, diff, epan, lua, plan, python, resolve

KIND = define("typed_messages", "typed_messages.schema.json", resolve, plan, [c, epan, lua, python],
             diff.diff)
