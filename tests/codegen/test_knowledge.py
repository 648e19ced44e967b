"""The project owns its knowledge: every citation points into the repository, and the generated
API comments carry what a user needs (label, meaning, unit, versions), not research notes."""
from __future__ import annotations

import re
import subprocess
from pathlib import Path

from codegen import ir
from codegen.comments import field_text, repeats
from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages.reference import forms_at, protocol_markdown
from codegen.kinds.packages import c, lua, python

ROOT = Path(__file__).resolve().parents[2]
# Notes the project was researched from but does not hold; spelled in pieces so that this file
# does not cite them either.
PRIVATE = ["FIRMWARE" + "-LAYOUTS", "FIELD" + "-NOTES", "CON" + "TRACT", ".." + "/shared"]
CITATION = re.compile(r"docs/([a-z-]+\.md)#([A-Za-z0-9_-]+)")
PLAN = plan(compile_text(DEFAULT_SPEC.read_text(encoding="utf-8")))


def tracked_files() -> list[Path]:
    """Every file of the repository outside .git: git's list where there is one, else the tree
    (an exported copy) without build outputs."""
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
        return [ROOT / name for name in out.decode().split("\0") if name]
    except (OSError, subprocess.CalledProcessError):
        skip = {".git", "build", "__pycache__", ".pytest_cache", ".hypothesis"}
        return [p for p in ROOT.rglob("*") if p.is_file() and not skip & set(p.relative_to(ROOT).parts)]


def texts() -> dict[str, str]:
    out = {}
    for path in tracked_files():
        try:
            out[str(path.relative_to(ROOT))] = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, FileNotFoundError, IsADirectoryError):
            continue     # binary files (captures, pictures) cite nothing
    return out


def slug(heading: str) -> str:
    """A Markdown heading's anchor, as GitHub makes it."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def anchors(doc: Path) -> set[str]:
    return {slug(line.lstrip("#")) for line in doc.read_text(encoding="utf-8").splitlines() if line.startswith("#")}


def test_no_file_cites_notes_the_repository_does_not_hold():
    found = [f"{name}: {word}" for name, text in texts().items() for word in PRIVATE if word in text]
    assert found == []


def test_every_citation_of_the_docs_names_a_heading_there():
    targets = {}
    broken = []
    for name, text in texts().items():
        for doc, anchor in CITATION.findall(text):
            path = ROOT / "docs" / doc
            if doc not in targets:
                targets[doc] = anchors(path) if path.exists() else set()
            if anchor not in targets[doc]:
                broken.append(f"{name}: docs/{doc}#{anchor}")
    assert broken == []
    assert "masterboard-data" in targets["firmware-history.md"]


def test_every_link_between_the_docs_names_a_heading():
    """Links inside docs/ ([..](contract.md#names), [..](#masterboard-data)) land on a heading."""
    broken = []
    for page in sorted((ROOT / "docs").glob("*.md")):
        for doc, anchor in re.findall(r"\]\(([a-z-]+\.md)?#([A-Za-z0-9_-]+)\)", page.read_text(encoding="utf-8")):
            target = ROOT / "docs" / (doc or page.name)
            if not target.exists() or anchor not in anchors(target):
                broken.append(f"{page.name}: {doc}#{anchor}")
    assert broken == []


def test_a_doc_that_repeats_the_label_is_left_out():
    f = ir.ScalarField("safety_mode", label="Safety mode", doc="Safety mode.", scalar=ir.SCALARS["uint8"])
    assert repeats("Safety mode", "Safety mode.") and not repeats("Safety mode", "Safety mode of the robot.")
    assert field_text([f]) == "Safety mode."


def test_a_field_comment_says_label_unit_meaning_and_versions_but_not_its_sources():
    f = ir.ScalarField("x", label="TCP offset X", unit="m", doc="Offset of the tool flange.",
                       field_note="From 3.1 (NIST table); medium confidence.", scalar=ir.SCALARS["float64"],
                       versions=ir.VersionRange((3, 1, 0), None))
    assert field_text([f]) == "TCP offset X (m). Offset of the tool flange. Sent by software 3.1 and later."


def test_generated_api_comments_carry_no_research_notes():
    outputs = {**c.render(PLAN, ["test"]), **lua.render(PLAN, ["test"]), **python.render(PLAN, ["test"])}
    for name, text in outputs.items():
        for research in ("firmware-history.md", "confidence", "ur_modern_driver", "python-urx", "NIST"):
            assert research not in text, (name, research)
    header = outputs["c/urwire.h"]
    assert "Safety mode. Safety mode." not in header
    assert "/* Safety mode. Sent by software 3.0 and later. See enum urwire_safety_mode. */" in header


def test_no_field_comment_of_the_spec_stutters():
    stutters = []
    for mp in PLAN.messages:
        for choice in mp.layouts:
            for f in choice.layout.struct.fields:
                text = field_text(choice.layout.struct.named(f.name)).lower()
                if re.search(rf"\b{re.escape(f.label.lower())}\. {re.escape(f.label.lower())}\b", text):
                    stutters.append(text)
    assert stutters == []


def test_the_reference_links_each_form_to_its_history_and_sources():
    text = protocol_markdown(PLAN, "spec/ur_primary.yaml")
    assert ("| 3.2 to 3.4 | 46 | " in text and
            "[robot-mode-data](firmware-history.md#robot-mode-data), "
            "[when-the-robot-mode-grew](firmware-history.md#when-the-robot-mode-grew) |" in text)
    assert "- `reserved_1` (5.25.1 and later): From 5.25.1" in text and "URCL 15882dca" in text


def column_version(heading: str) -> tuple[int, int, int]:
    """The version a column of docs/firmware-history.md#sizes-by-version stands for: the first
    its heading names ("5.25.1 on", "3.2-3.4", "10.x"); early CB2 is taken as 1.5, as the spec does."""
    if heading == "early CB2":
        return (1, 5, 0)
    return ir.parse_version(re.match(r"\d+\.(\d+|x)(\.\d+)?", heading).group().replace(".x", ".0"))


def test_the_history_size_table_is_what_the_spec_decodes():
    """Each number of the sizes table is the size of the spec's form for that code at that
    column's version (with Euromap67 where the cell says +N E); a cell may name several sizes
    ("10 or 7") when a release sends both. Dashes and question marks say nothing to check."""
    lines = (ROOT / "docs" / "firmware-history.md").read_text(encoding="utf-8").split("## Sizes by version")[1]
    table = lines.split("\n## ")[0].splitlines()
    headings = [cell.strip() for cell in next(line for line in table if line.startswith("| code |")).split("|")[3:-1]]
    rows = [line.split("|")[1:-1] for line in table if re.match(r"\| \d+ \|", line)]
    assert len(rows) == 15 and all(len(row) == len(headings) + 2 for row in rows)
    checked = 0
    for version, column in zip(map(column_version, headings), range(2, len(headings) + 2)):
        forms = forms_at(PLAN, version)
        for row in rows:
            form = forms.get(("robot_state", int(row[0])))
            cell = row[column]
            if form is None or not re.match(r"\s*\d", cell) or form.sizes.startswith("at least"):
                continue
            spec = [int(n) for n in re.findall(r"\d+", form.sizes)]
            sizes = [int(n) for n in re.findall(r"(?<![+.\d])(\d+)(?! E)(?!\.\d)", cell)]
            extra = re.search(r"\+(\d+) E", cell)
            assert spec[0] in sizes, (version, row[1], cell, form.sizes)
            if extra:
                assert spec[1] == spec[0] + int(extra.group(1)), (version, row[1], cell, form.sizes)
            checked += 1
    assert checked >= 100
