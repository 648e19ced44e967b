"""Tests import the generator from the tree and the Python bindings from generated/python."""
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
for path in (ROOT, ROOT / "generated" / "python"):
    if str(path) not in sys.path:
        sys.path.insert(0, str(path))
