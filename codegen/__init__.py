"""urwire's generator: spec/ (YAML) -> checked, resolved model (IR) -> generated/ per target.

Passes, one module each: load (YAML with line numbers) -> validate (JSON Schema) -> resolve
(typed IR, sizes and gates computed) -> plan -> one renderer per target (Jinja2 templates), the
last three in the spec's kind (kinds/<kind>/resolve.py, plan.py, c.py, epan.py, lua.py, python.py).
"""
