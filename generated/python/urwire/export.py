# Copied from codegen/templates/python/runtime/export.py: edit it there and run `make generate`.
"""placeholder"""


def add_parser(sub, version_arg) -> None:
    pass
