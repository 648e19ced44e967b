"""urwire's generator: spec/ (YAML) -> checked, resolved model (IR) -> generated/ per target.

Passes, one module each: load (YAML with line numbers) -> validate (JSON Schema) ->
resolve (typed IR, sizes and gates computed) -> targets/<name> (Jinja2 templates).
"""
