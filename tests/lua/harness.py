"""Run the generated dissector in real tshark and turn its JSON tree back into canonical records.

The conversion uses the IR (codegen) to know each field's kind, so the comparison with the
golden vectors and with the Python decoder is value for value. tshark prints float64 with 15
significant digits and float32 with 6-7, so floats compare within a relative tolerance.
"""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path
from typing import Optional

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python")]

from codegen import ir  # noqa: E402
from codegen.kinds.packages import model  # noqa: E402
from codegen.compile import compile_file  # noqa: E402
from tests.tools import capture, measure  # noqa: E402
from tests.tools.capture import Segment  # noqa: E402

PLUGIN = ROOT / "generated" / "lua" / "urwire.lua"
F64_TOL = 1e-13
F32_TOL = 5e-6
PROTOCOL = compile_file()


# How a Lua error caught by the dissector's pcall guard shows: an expert, in JSON and in text.
INTERNAL_JSON = '"ur.internal_error"'
INTERNAL_TEXT = "(Error/Malformed): urwire: "
# The same for the RTDE and real-time dissectors, whose label is their protocol's name.
GUARDED = ("rtde", "ur_realtime")


class TsharkError(AssertionError):
    pass


def run_tshark(pcap: Path, *args: str, check_tree: bool = True, plugin: Path = PLUGIN) -> str:
    """tshark with the dissector (the generated one, or `plugin`); fails on any Lua error."""
    cmd = ["tshark", "-r", str(pcap), "-X", f"lua_script:{plugin}", *args]
    return _checked(subprocess.run(cmd, capture_output=True, text=True, timeout=600))


def run_tshark_peak_rss(pcap: Path, *args: str, limit: int = 2 << 30) -> tuple[str, int]:
    """run_tshark, and tshark's peak resident memory in bytes. Its address space is limited to
    `limit`, so that a dissector gone wrong fails here instead of taking the machine's memory."""
    res, _, peak = measure.run(["tshark", "-r", str(pcap), "-X", f"lua_script:{PLUGIN}", *args], limit=limit)
    return _checked(res), peak


def _checked(res: subprocess.CompletedProcess) -> str:
    """tshark's output, after failing on any Lua error or a bad exit."""
    if "Lua: Error" in res.stderr or "Lua: Error" in res.stdout:
        raise TsharkError(f"Lua error: {res.stderr[:2000]}")
    if "_ws.lua.error" in res.stdout:
        raise TsharkError("_ws.lua.error in the output")
    if INTERNAL_JSON in res.stdout or INTERNAL_TEXT in res.stdout or any(
            f'"{name}.internal_error"' in res.stdout or f"(Error/Malformed): {name}: " in res.stdout for name in GUARDED):
        raise TsharkError("the dissector caught an internal Lua error: " + res.stdout[:2000])
    if res.returncode != 0:
        raise TsharkError(f"tshark exited {res.returncode}: {res.stderr[:2000]}")
    return res.stdout


def _pairs(pairs: list) -> dict:
    """A JSON object whose repeated keys become lists (as --no-duplicate-keys does), which also
    keeps its pairs in order under "__pairs__" (the order of a robot state's packages)."""
    out: dict = {}
    for k, v in pairs:
        if k in out:
            out[k] = (out[k] if isinstance(out[k], list) and k in out["__lists__"] else [out[k]]) + [v]
            out["__lists__"].add(k)
        else:
            out.setdefault("__lists__", set())
            out[k] = v
    out["__pairs__"] = pairs
    out.setdefault("__lists__", set())
    return out


def tshark_json(pcap: Path, *opts: str) -> list:
    """tshark's JSON with duplicate keys kept (several messages or packages of one type)."""
    return parse_json(run_tshark(pcap, "-2", "-T", "json", *opts))


def parse_json(text: str) -> list:
    return json.loads(text or "[]", object_pairs_hook=_pairs)


# ---- pcaps holding many sessions ----

def write_sessions(path: Path, streams: list[list[bytes]], pcapng: bool = False, handshake: bool = True,
                   retransmit_every: int = 0) -> Path:
    """One TCP session per entry (a list of robot segment payloads), one after the other;
    with retransmit_every=k, every k-th segment is sent twice."""
    frames = []
    for i, segments in enumerate(streams):
        again = range(0, len(segments), retransmit_every) if retransmit_every else ()
        frames += capture.session_frames([Segment(True, s) for s in segments], port=30001,
                                         client_port=20000 + i, handshake=handshake, retransmit=again)
    return capture.write(path, frames, pcapng=pcapng)


def ur_items_by_stream(frames: list) -> dict[int, list]:
    """The `ur` tree items of each TCP stream, in frame order."""
    out: dict[int, list] = {}
    for fr in frames:
        layers = fr["_source"]["layers"]
        if "ur" not in layers:
            continue
        stream = int(layers["tcp"]["tcp.stream"])
        items = layers["ur"] if isinstance(layers["ur"], list) else [layers["ur"]]
        out.setdefault(stream, []).extend(i for i in items if isinstance(i, dict))
    return out


# ---- tree -> canonical records ----

def _kinds() -> dict[str, tuple]:
    """abbr -> (kind, scalar) for every leaf field; kind in int/bool/f32/f64/text/hex."""
    out: dict[str, tuple] = {}

    def scalar_kind(s: ir.Scalar) -> str:
        return "bool" if s.is_bool else ("f32" if s.size == 4 else "f64") if s.is_float else "int"

    def walk(owner: str, fields):
        for f in fields:
            abbr = f"ur.{owner}.{f.name}"
            if isinstance(f, (ir.ScalarField, ir.ArrayField)):
                out[abbr] = (scalar_kind(f.scalar), f)
            elif isinstance(f, ir.GroupField):
                out[abbr] = ("group", f)
                walk(owner, f.item.fields)
            elif isinstance(f, (ir.StringField,)):
                out[abbr] = ("text", f)
            elif isinstance(f, ir.StringListField):
                out[abbr] = ("texts", f)
            elif isinstance(f, ir.BytesField):
                out[abbr] = ("hex", f)
            elif isinstance(f, ir.SwitchField):
                out[abbr] = (scalar_kind(f.default), f)
                for s in f.cases.values():
                    out[f"{abbr}_{s.name}"] = (scalar_kind(s), f)
            elif isinstance(f, ir.ValueListField):
                out[abbr] = ("values", f)

    for m in PROTOCOL.messages:
        if isinstance(m, model.PackageListMessage):
            for pk in m.packages:
                walk(pk.name, pk.struct.fields)
        else:
            walk(m.name, list(m.header.fields) + ([m.subtype] if m.has_subtype else []))
            for st in m.subtypes:
                walk(st.name, list(m.header.fields) + list(st.struct.fields))
    return out


KINDS = _kinds()
LAYOUTS = {lay.name: lay for lay in PROTOCOL.all_layouts()}
PACKAGE_NAMES = {pk.name for m in PROTOCOL.messages if isinstance(m, model.PackageListMessage) for pk in m.packages}


def _as_list(v) -> list:
    return v if isinstance(v, list) else [v]


def _hex(v: str) -> str:
    return v.replace(":", "")


def _number(kind: str, text: str):
    if kind == "bool":
        return text not in ("0", "False", "false")
    if kind == "int":
        return int(text)
    t = text.lower()
    if t in ("nan", "-nan"):
        return math.nan
    if t in ("inf", "infinity"):
        return math.inf
    if t in ("-inf", "-infinity"):
        return -math.inf
    value = float(text)
    if math.isinf(value):
        # 15 significant digits round the largest doubles up past the maximum.
        value = math.copysign(sys.float_info.max, value)
    return value


def _experts(obj: dict) -> list[dict]:
    out = []
    for key, v in obj.items():
        if key == "_ws.expert":
            out += _as_list(v)
    return out


def _errors(obj: dict) -> list[str]:
    return [e.get("_ws.expert.message", "") for e in _experts(obj)
            if e.get("_ws.expert.severity") == str(0x800000)]


def _values(obj_list, layouts) -> list:
    out = []
    for v in _as_list(obj_list):
        name = v.get("ur.global_variables_update.type")
        lay = layouts.get(name)
        if lay is None or not any(k.startswith("ur.global_variables_update.value") for k in v) \
                and lay.layout in ("scalar", "array"):
            value = None   # a value cut short: its message carries the error
        elif lay.layout == "empty":
            value = None
        elif lay.layout == "string":
            value = v.get("ur.global_variables_update.value_string", "")
        elif lay.layout == "scalar":
            kind = "bool" if lay.item.is_bool else "f32" if lay.item.is_float else "int"
            value = _number(kind, v[f"ur.global_variables_update.value_{lay.item.name}"])
        elif lay.layout == "array":
            value = [_number("f32", x) for x in _as_list(v[f"ur.global_variables_update.value_{lay.item.name}"])]
        elif lay.layout == "list":
            value = _values(v["ur.global_variables_update.variables"], layouts) \
                if "ur.global_variables_update.variables" in v else []
        else:
            value = [_values(r["ur.global_variables_update.variables"], layouts)
                     if "ur.global_variables_update.variables" in r else []
                     for r in _as_list(v.get("ur.global_variables_update.row", []))]
        out.append({"type": name, "value": value})
    return out


def _empty_lists(layout_fields, rec: dict) -> None:
    """Lists running to the end of a layout show no item when empty."""
    for f in layout_fields:
        if isinstance(f, (ir.StringListField, ir.ValueListField)) or (isinstance(f, ir.GroupField) and f.to_end):
            rec.setdefault(f.name, [])


def _fields(owner: str, obj: dict, rec: dict) -> None:
    for key, v in obj.items():
        if key.endswith("_tree") or key.startswith("_ws") or key in ("ur.package.length", "ur.package.type"):
            continue
        if key == "ur.extra":
            rec["extra"] = _hex(v)
            continue
        if key == "ur.raw":
            rec["raw"] = _hex(v)
            continue
        info = KINDS.get(key)
        if info is None:
            continue
        kind, f = info
        name = f.name
        if kind == "group":
            items = []
            for item in _as_list(v):
                sub: dict = {}
                _fields(owner, item, sub)
                items.append(sub)
            rec[name] = items
        elif kind == "text":
            rec[name] = v
        elif kind == "texts":
            rec[name] = _as_list(v)
        elif kind == "hex":
            rec[name] = _hex(v)
        elif kind == "values":
            layouts = PROTOCOL.value_layouts
            rec[name] = _values(v, layouts)
        elif isinstance(f, ir.ArrayField):
            rec[name] = [_number(kind, x) for x in _as_list(v)]
        else:
            rec[name] = _number(kind, v)


def _dispatch_message(code: int) -> Optional[model.DispatchMessage]:
    for m in PROTOCOL.messages:
        if isinstance(m, model.DispatchMessage) and m.code.value == code:
            return m
    return None


def to_records(u: dict) -> list[dict]:
    """Canonical records from one `ur` tree item (a bad header gives an error record)."""
    errors = _errors(u)
    bad_header = [e.get("_ws.expert.message") for e in _experts(u) if "ur.bad_length" in e or "ur.bad_type" in e]
    if bad_header:
        return [{"type": "error", "error": bad_header[0]}]
    if "ur.type" not in u:           # bytes skipped while resynchronising
        return []
    mtype = int(u["ur.type"])
    if mtype == 16:
        rec: dict = {"type": "robot_state", "packages": []}
        for key, obj in u["__pairs__"]:
            if key.startswith("ur.") and key[3:] in PACKAGE_NAMES:
                for obj in [obj]:
                    pkg = {"type": key[3:]}
                    errs = _errors(obj)
                    if errs:
                        pkg["error"] = errs[0].split(": ", 1)[1]
                        pkg["raw"] = _hex(obj.get("ur.raw", ""))
                    else:
                        _fields(key[3:], obj, pkg)
                        _empty_lists(LAYOUTS[key[3:]].struct.fields, pkg)
                    rec["packages"].append(pkg)
            elif key == "ur.unknown_package":
                for obj in [obj]:
                    rec["packages"].append({"type": "unknown", "package_type": int(obj["ur.package.type"]),
                                            "raw": _hex(obj.get("ur.raw", ""))})
        if errors:
            rec["error"] = errors[0]
            rec["raw"] = _hex(u.get("ur.raw", ""))
        return [rec]
    m = _dispatch_message(mtype)
    if m is None:
        return [{"type": "unknown", "message_type": mtype, "raw": _hex(u.get("ur.raw", ""))}]
    for st in m.subtypes:
        if f"ur.{st.name}" in u:
            obj = u[f"ur.{st.name}"]
            rec = {"type": st.name}
            errs = _errors(obj)
            hdr = {f.name for f in m.header.fields}
            _fields(st.name, obj, rec)
            _empty_lists(st.struct.fields, rec)
            if errs:
                rec = {k: v for k, v in rec.items() if k in hdr or k == "type"}
                rec["error"] = errs[0].split(": ", 1)[1]
                rec["raw"] = _hex(obj.get("ur.raw", ""))
            if m.has_subtype:
                rec.pop(m.subtype.name, None)
            return [rec]
    if errors:   # too short for its own header
        return [{"type": "unknown", "message_type": mtype, "error": errors[0], "raw": _hex(u.get("ur.raw", ""))}]
    rec = {"type": "unknown", "message_type": mtype}
    _fields(m.name, u, rec)
    rec["robot_message_type"] = rec.pop(m.subtype.name)
    rec.setdefault("raw", "")
    return [rec]


# ---- expectations ----

def _cut_at_nul(v):
    """Wireshark string fields end at the first NUL byte; the canonical text keeps it."""
    if isinstance(v, str):
        return v.split("\x00", 1)[0]
    if isinstance(v, list):
        return [_cut_at_nul(x) for x in v]
    if isinstance(v, dict):
        return {k: (_cut_at_nul(x) if k not in ("raw", "extra", "error", "type") else x) for k, x in v.items()}
    return v


def comparable(records: list[dict]) -> list[dict]:
    """Canonical records as tshark can show them: a truncated tail never completes in TCP
    reassembly, so neither it nor the messages the stream decoders find inside it give a record;
    stream-fault offsets are stream positions tshark lacks; texts end at a NUL byte."""
    out = []
    for r in _cut_at_nul(records):
        if r.get("type") == "error":
            if r["error"].startswith("truncated"):
                break
            r = {"type": "error", "error": r["error"]}
        out.append(r)
    return out


def float_mismatches(expected, actual, path="") -> list[str]:
    """Like tests.vectors.mismatches, with float tolerances fit for tshark's printing."""
    from tests.vectors import mismatches
    return mismatches(expected, actual, partial=False, tolerance=F64_TOL if not path else F32_TOL, path=path)
