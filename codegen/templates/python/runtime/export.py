"""placeholder"""


def add_parser(sub, version_arg) -> None:
    pass
