"""Tests import the generator from the tree and the Python bindings from python/ (hand-written) and
generated/python/ (the subpackage urwire.generated)."""
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
for path in (ROOT, ROOT / "generated" / "python", ROOT / "python"):
    if str(path) not in sys.path:
        sys.path.insert(0, str(path))
