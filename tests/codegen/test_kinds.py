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
