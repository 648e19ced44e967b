"""Generated files read like hand-written ones: no line is longer than codegen.wrap.LIMIT columns
(the templates wrap prose at word boundaries and spread long lists over aligned lines)."""
import subprocess
from pathlib import Path

from codegen import wrap
from codegen.wrap import c_comment, docstring, spread

ROOT = Path(__file__).resolve().parents[2]


def generated_files() -> list[Path]:
    """The files the generator writes (what git keeps under generated/; build leftovers aside)."""
    listed = subprocess.run(["git", "ls-files", "generated"], cwd=ROOT, capture_output=True, text=True)
    if listed.returncode == 0 and listed.stdout.strip():
        return [ROOT / name for name in listed.stdout.split()]
    return [p for p in sorted((ROOT / "generated").rglob("*")) if p.is_file() and "egg-info" not in p.parts[-2]]


def test_no_generated_line_is_over_the_limit():
    long = []
    for path in generated_files():
        if path.is_file():
            for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if wrap.columns(line) > wrap.LIMIT:
                    long.append(f"{path.relative_to(ROOT)}:{n}: {wrap.columns(line)} columns")
    assert not long, f"{len(long)} lines over {wrap.LIMIT} columns:\n" + "\n".join(long[:20])


def test_a_comment_wraps_at_word_boundaries():
    text = " ".join(f"word{n}" for n in range(60))
    lines = c_comment(text, "    ").splitlines()
    assert len(lines) > 1 and all(len(line) <= wrap.PROSE for line in lines)
    assert lines[0].startswith("    /* ") and all(line.startswith("     * ") for line in lines[1:])
    assert " ".join(line.strip(" /*") for line in lines) == text


def test_a_long_list_continues_under_its_first_item():
    items = [f"argument_{n}" for n in range(30)]
    lines = spread(items, "call(", ")", "    ").splitlines()
    assert len(lines) > 1 and all(len(line) <= wrap.LIMIT for line in lines)
    assert all(line.startswith(" " * len("    call(")) and line[len("    call("):][0] != " " for line in lines[1:])
    assert "".join(lines).replace(" ", "") == "call(" + ",".join(items) + ")"


def test_a_short_docstring_stays_on_one_line():
    assert docstring("One line.", "    ") == '    """One line."""'


def test_a_wrapped_lua_string_keeps_its_value():
    import re

    from codegen.lang.lua import string as lua_str, text as lua_text

    text = 'A "quoted" word,  two spaces, a\\backslash and ' + " ".join(f"w{n}" for n in range(80))
    literal = lua_text(text, "        ", 8)
    assert len(literal.splitlines()) > 1
    # Lua's \z skips the line break and the indentation after it.
    assert re.sub(r"\\z\s*", "", literal) == lua_str(text)
