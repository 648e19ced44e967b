"""Request/response tracking in the Wireshark dissectors, as Wireshark's own request/response
protocols show it (dns.response_in, dns.response_to, dns.time): the three fields every kind that
pairs replies with requests declares, under its protocol's filter name (ur_dashboard.response_in,
rtde.time), and how each target spells them. Which reply answers which request is the kind's
(the lines kind: in order, from `framing.replies`; the typed-messages kind: the spec's `exchanges`);
the links themselves are kept by runtime/lua/common/exchange.lua and runtime/epan/common/exchange.c."""
from __future__ import annotations

from dataclasses import dataclass

from .lang import c, lua
from .wrap import spread


@dataclass(frozen=True)
class ExchangeField:
    name: str                  # filtered as <protocol>.<name>
    label: str
    doc: str
    frametype: str             # what the frame it holds is: REQUEST or RESPONSE; "" for the time


# Wireshark's names and its FT_FRAMENUM types: on a request, the frame of its reply; on a reply, the
# frame of its request and the seconds since it (FT_RELATIVE_TIME).
FIELDS = (
    ExchangeField("response_in", "Response in", "The frame that holds the reply to this request.", "RESPONSE"),
    ExchangeField("response_to", "Request in", "The frame that holds the request this reply answers.", "REQUEST"),
    ExchangeField("time", "Time since request", "The time from the request to this reply.", ""),
)
NAMES = tuple(f.name for f in FIELDS)


def lua_field(f: ExchangeField, protocol: str, key: str, indent: str) -> str:
    """`key = ProtoField...(...)`, an entry of a table of fields, wrapped when long (Wireshark 4.0's
    ProtoField.framenum takes frametype.REQUEST or RESPONSE)."""
    args = [lua.string(f"{protocol}.{f.name}"), lua.string(f.label)]
    if f.frametype:
        call, args = "framenum", args + ["base.NONE", f"frametype.{f.frametype}", "nil", lua.string(f.doc)]
    else:
        call, args = "relative_time", args + [lua.string(f.doc)]
    return spread(args, f"{key} = ProtoField.{call}(", "),", indent)


def epan_type(f: ExchangeField) -> tuple[str, str, str]:
    """An hf_register_info entry's type, display and strings."""
    if f.frametype:
        return "FT_FRAMENUM", "BASE_NONE", f"FRAMENUM_TYPE(FT_FRAMENUM_{f.frametype})"
    return "FT_RELATIVE_TIME", "BASE_NONE", "NULL"


def epan_field(f: ExchangeField, protocol: str) -> dict:
    """One hf_register_info entry as the templates lay it out."""
    ftype, display, strings = epan_type(f)
    return dict(name=f.name, label=c.string(f.label), abbrev=c.string(f"{protocol}.{f.name}"), type=ftype,
                display=display, strings=strings, blurb=c.string(f.doc))
