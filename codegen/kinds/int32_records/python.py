"""The Python target of an int32-record interface: generated/python/urwire/generated/<name>.py,
the record classes, their enums and their layouts by driver release, from the plan."""
from __future__ import annotations

from ... import ir
from ...emit import environment
from ...lang.python import class_name
from .model import FROM_ROBOT
from .plan import PublicField, RecordsPlan


def _json_kind(f: PublicField) -> str:
    if f.is_list:
        return "list:f64" if f.scaled else "list:int"
    return "f64" if f.scaled else "enum" if f.enum else "int"


def _type(f: PublicField) -> str:
    one = "float" if f.scaled else class_name(f.enum.name) if f.enum else "int"
    text = f"list[{one}]" if f.is_list else one if not f.enum else f"Union[{one}, int]"
    return text if f.always else f"Optional[{text}]"


def view(p: RecordsPlan) -> dict:
    m = p.model
    enums = [dict(name=class_name(e.name), doc=e.doc, members=[dict(name=v.name, value=v.value) for v in e.values])
             for e in m.enums.values()]
    records = []
    for r in p.records:
        cls = class_name(r.record.name)
        layouts = []
        for lay in r.layouts:
            slots = [f"_rt.Slot({s.field.name!r}, {s.index}, {s.count}, {s.scale!r}, "
                     f"{class_name(s.field.enum.name) if s.field.enum else None})" for s in lay.slots]
            layouts.append(dict(describe=lay.describe(), slots=slots))
        records.append(dict(
            cls=cls, type=r.record.name, label=r.record.label, doc=r.record.doc, from_robot=r.record.direction == FROM_ROBOT,
            json=[f"({f.name!r}, {_json_kind(f)!r}, {not f.always!r})" for f in r.fields],
            fields=[dict(name=f.name, type=_type(f), default="" if f.always else " = None",
                         metadata=f'{{"label": {f.label!r}, "unit": {f.unit!r}}}', doc=f.doc) for f in r.fields],
            starts=[repr(s) for s in r.starts], layouts=layouts))
    records.sort(key=lambda r: r["from_robot"])
    return dict(name=m.name, title=m.title, doc=m.doc, ports=repr(m.ports), releases=[repr(v) for v in m.releases],
                default_release=repr(m.default_release), default_text=ir.version_text(m.default_release),
                enums=enums, records=records)


def render(p: RecordsPlan, banner: list[str]) -> dict[str, str]:
    text = environment("python").get_template("int32_records/module.py.j2").render(banner=banner, **view(p))
    return {f"python/urwire/generated/{p.model.name}.py": text}
