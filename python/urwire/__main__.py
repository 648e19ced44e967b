"""python -m urwire: the same as the `urwire` command."""
import sys

from .cli import main

sys.exit(main())
