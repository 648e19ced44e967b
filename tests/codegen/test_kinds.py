"""Interface kinds: a spec's framing.kind picks its schema, resolver and renderers; a spec that
names none is the primary interface's kind."""
import pytest

from codegen.compile import DEFAULT_SPEC, compile_text, spec_files
from codegen.errors import SpecError
from codegen.kinds import DEFAULT_KIND, KINDS, kind_name


def test_a_spec_without_a_kind_is_the_primary_interface():
    assert kind_name({"framing": {"message_header": {}}}) == DEFAULT_KIND
    assert DEFAULT_KIND in KINDS


def test_an_unknown_kind_is_named_at_its_path():
    with pytest.raises(SpecError) as caught:
        compile_text("spec_format: 1\nframing: {kind: carrier_pigeon}\n", "probe.yaml")
    (problem,) = caught.value.problems
    assert problem.path == "framing.kind" and problem.line == 2 and "carrier_pigeon" in problem.message


def test_every_spec_names_a_known_kind():
    assert DEFAULT_SPEC in spec_files()
    for spec in spec_files():
        import yaml
        assert kind_name(yaml.safe_load(spec.read_text(encoding="utf-8"))) in KINDS, spec


def test_a_kind_is_defined_by_its_modules_and_renders_every_target():
    """kinds.define builds a kind from its package's resolve, plan and renderer modules, one per
    target and named after it, and its diff; it refuses a kind that lacks a renderer."""
    from codegen.kinds import TARGETS, define
    from codegen.kinds.packages import c, epan, lua, plan, python, reference, resolve

    kind = define("probe", "spec.schema.json", resolve, plan, [c, epan, lua, python], reference.diff)
    assert kind.resolve is resolve.resolve and kind.plan is plan.plan and kind.diff is reference.diff
    with pytest.raises(ValueError, match="epan"):
        define("probe", "spec.schema.json", resolve, plan, [c, lua, python], reference.diff)
    assert sorted(TARGETS) == ["c", "epan", "lua", "python"]


def test_a_kind_imports_nothing_from_another_kind():
    """What kinds share lives at the top of codegen/ (ir, resolve, lang, emit, ...), never in a
    kind that the others borrow from."""
    import ast
    from pathlib import Path

    kinds = Path(__file__).resolve().parents[2] / "codegen" / "kinds"
    names = {p.name for p in kinds.iterdir() if (p / "__init__.py").exists()}
    for package in sorted(names):
        for source in sorted((kinds / package).glob("*.py")):
            for node in ast.walk(ast.parse(source.read_text(encoding="utf-8"))):
                if not isinstance(node, ast.ImportFrom):
                    continue
                module = node.module or ""
                if node.level == 2:      # from ..x import y, in a kind's module: x or y may be a kind
                    borrowed = {module.split(".")[0]} if module else {a.name for a in node.names}
                elif module.startswith("codegen.kinds."):
                    borrowed = {module.split(".")[2]}
                else:
                    borrowed = set()
                assert not borrowed & (names - {package}), \
                    f"{source.relative_to(kinds)} imports {'.' * node.level}{module} from another kind"
