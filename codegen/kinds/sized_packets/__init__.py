"""The kind `sized_packets`: an interface of fixed packets, each opened by an int32 size that
chooses its layout (the real-time interface, 30003). Its layouts are gated by software version
like the primary interface's, and layouts that share a size are told apart by the rule the spec
states (framing.same_size), rendered from the plan in every target.

model.py holds its IR, resolve.py makes it, plan.py lays out offsets and the forms by size, and
one module per target renders them."""
from __future__ import annotations

from .. import define
from . import c, diff, epan, lua, plan, python, resolve

KIND = define("sized_packets", "sized_packets.schema.json", resolve, plan, [c, epan, lua, python],
             diff.diff)
