# Copied from codegen/templates/python/runtime/plot.py: edit it there and run `make generate`.
"""placeholder"""


def add_parser(sub, version_arg) -> None:
    pass
