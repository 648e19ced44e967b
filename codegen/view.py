"""Pieces the targets' view models share: what a template fragment is handed."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass
class Step:
    """One decode, encode or display step; `kind` names the template fragment that renders it,
    and `data` holds the strings that fragment lays out (read as attributes)."""

    kind: str
    data: dict

    def __getattr__(self, key):
        try:
            return self.__dict__["data"][key]
        except KeyError:
            raise AttributeError(key) from None


def one_line(*texts: str, quote: str = '"""') -> str:
    """Spec doc strings joined into one line, safe inside the target's comment or string."""
    text = " ".join(t.strip() for t in texts if t and t.strip())
    return text.replace(quote, "'''") if quote else text
