"""What a scene file's key is: its type, unit, meaning, limits, allowed values and default,
declared once, on the field of the section's dataclass that holds it
(:mod:`tankfx.scene.sections`). The reader checks a scene by them
(:mod:`tankfx.scene.reader`), and the key reference is generated from them
(:mod:`tankfx.scene.reference`): no table of keys is kept by hand anywhere.
"""
from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, field
from typing import Any

__all__ = ["Limit", "Key", "key", "POSITIVE", "NON_NEGATIVE"]


@dataclass(frozen=True)
class Limit:
    """The values a number may take: above ``low`` (or at it, unless ``low_open``) and below
    ``high`` (or at it, unless ``high_open``); None: no bound on that side."""

    low: float | None = None
    high: float | None = None
    low_open: bool = True
    high_open: bool = False

    def holds(self, value: float) -> bool:
        lo_ok = self.low is None or (value > self.low if self.low_open else value >= self.low)
        hi_ok = self.high is None or (value < self.high if self.high_open
                                      else value <= self.high)
        return lo_ok and hi_ok

    def text(self) -> str:
        """As the messages and the reference write it: '> 0', '>= 0' or '(0, 1]'."""
        def num(x):
            out = f"{x:g}"
            return f"{x:.0e}".replace("e-0", "e-") if "e" not in out and 0 < abs(x) < 1e-3 \
                else out
        if self.high is None:
            return f"{'>' if self.low_open else '>='} {num(self.low)}"
        lo = "-inf" if self.low is None else num(self.low)
        return (f"{'(' if self.low_open or self.low is None else '['}{lo}, {num(self.high)}"
                f"{')' if self.high_open else ']'}")


#: > 0 and >= 0, the two limits most keys have
POSITIVE = Limit(0.0)
NON_NEGATIVE = Limit(0.0, low_open=False)


@dataclass(frozen=True)
class Key:
    """A scene key. ``unit``: its SI unit ('' for a pure number, 'deg' for an angle);
    ``meaning``: what it is, in a line; ``required``: a scene without it is refused;
    ``limit``: the values allowed (checked on reading, with ``why`` in the message where
    given); ``choices``: the words allowed for a string; ``default_doc``: the default in words
    where it is not the field's value (resolved from other keys, e.g. "10000 a"); ``kind``:
    the key's type where the field's is not it (a list of tables); ``custom``: checked by its
    section's own rules rather than by the reader's generic check of ``limit``."""

    unit: str = ""
    meaning: str = ""
    required: bool = False
    limit: Limit | None = None
    why: str = ""
    choices: tuple[str, ...] = ()
    default_doc: str | None = None
    kind: type | None = None
    #: checked by its section's own rules, with a message of its own, not by the reader's
    #: generic check of ``limit`` and ``choices``
    custom: bool = False

    def default_text(self, value: Any = MISSING) -> str:
        """The default as the reference writes it (``value``: the field's default)."""
        if self.default_doc is not None:
            return self.default_doc
        if value is MISSING or value is None:
            return "required" if self.required else "-"
        if isinstance(value, bool):
            return "true" if value else "false"
        if isinstance(value, str):
            return f'"{value}"'
        if isinstance(value, tuple):
            return "none" if not value else repr(list(value))
        if isinstance(value, float) and math.isfinite(value):
            return f"{value:g}"
        return repr(value)


def key(default: Any = MISSING, **spec) -> Any:
    """A dataclass field that is a scene key (``spec``: :class:`Key`'s attributes)."""
    if default is MISSING:
        return field(metadata={"key": Key(**spec)})
    if isinstance(default, (list, dict, set)):
        raise TypeError("a key's default must be immutable")
    return field(default=default, metadata={"key": Key(**spec)})
