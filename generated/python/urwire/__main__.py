# Copied from codegen/templates/python/runtime/__main__.py: edit it there and run `make generate`.
"""python -m urwire: the same as the `urwire` command."""
import sys

from .cli import main

sys.exit(main())
