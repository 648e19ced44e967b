"""Decisions every target of a typed-messages interface shares, made once over the model: how a
decoder reads each message (runs of scalars behind one bounds check, every other field alone),
which layout a type code, direction and protocol version choose, what each message means to a
connection's recipes, and the type codes the interface names."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ... import ir
from . import model


@dataclass(frozen=True)
class Step:
    """One read of a decoder: a run of consecutive scalars (named by its first field, as Python's
    struct run and C's bounds check are), or one field that is not a scalar."""
    kind: str                          # run | names | values | prefixed_text | rest_text
    fields: tuple[model.BodyField, ...]
    size: int = 0                      # a run's bytes; a prefixed text's prefix bytes


@dataclass(frozen=True)
class MessagePlan:
    message: model.Message
    steps: tuple[Step, ...]
    request_kind: Optional[int]        # the recipe kind (index) whose setup request it is
    reply_kind: Optional[int]          # the recipe kind whose setup reply it is


@dataclass(frozen=True)
class TypedPlan:
    interface: model.Interface
    messages: tuple[MessagePlan, ...]                      # spec order
    dispatch: tuple[tuple[MessagePlan, int], ...]          # each message in each protocol it is sent in
    codes: tuple[tuple[int, str], ...]                     # every type code and its letter, documented or not
    value_scalars: tuple[ir.Scalar, ...]                   # the value types' scalars, once each, spec order


def _steps(message: model.Message) -> tuple[Step, ...]:
    steps: list[Step] = []
    run: list[ir.ScalarField] = []

    def close_run():
        if run:
            steps.append(Step("run", tuple(run), sum(f.scalar.size for f in run)))
            run.clear()

    for f in message.fields:
        if isinstance(f, ir.ScalarField):
            run.append(f)
            continue
        close_run()
        if isinstance(f, model.NamesField):
            steps.append(Step("names", (f,)))
        elif isinstance(f, model.RecipeValuesField):
            steps.append(Step("values", (f,)))
        elif f.length is not None:
            steps.append(Step("prefixed_text", (f,), f.length.size))
        else:
            steps.append(Step("rest_text", (f,)))
    close_run()
    return tuple(steps)


def plan(interface: model.Interface) -> TypedPlan:
    requests = {m.name: i for i, k in enumerate(interface.recipe_kinds) for m in k.requests}
    replies = {m.name: i for i, k in enumerate(interface.recipe_kinds) for m in k.replies}
    messages = tuple(MessagePlan(m, _steps(m), requests.get(m.name), replies.get(m.name)) for m in interface.messages)
    dispatch = tuple((mp, p) for mp in messages for p in mp.message.protocols)
    codes = tuple(sorted({(m.code, m.letter) for m in interface.messages}
                         | {(u.code, chr(u.code)) for u in interface.undocumented}))
    scalars = tuple({t.scalar.name: t.scalar for t in interface.value_types}.values())
    return TypedPlan(interface, messages, dispatch, codes, scalars)
