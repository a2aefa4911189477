"""One validation module for every input table: typed getters whose messages name the key
(as a dotted path), the value as the user wrote it, and the expected unit.

Used by the scene files (every table through :mod:`stand.scene.tables`), the
instruments' settings, the sweep and stress catalogues.  Every problem raises :class:`stand.scene.model.SceneError` (a
``ValueError``), e.g. ``balancer.mass = -0.045: must be > 0 (kg)``, with a
"did you mean" suggestion for misspelt keys.
"""
from __future__ import annotations

import difflib
import math
import numbers
from typing import Any, Callable, Mapping, Optional

import numpy as np

from stand.errors import SceneError
from stand.io.units import QUANTITIES, UnitError, parse_quantity

__all__ = ["Table", "number", "angle", "fmt", "kind", "suggest", "REQUIRED"]

REQUIRED = _REQUIRED = object()   #: marks a key without a default


# ---------------------------------------------------------------- messages
def _fmt(value: Any) -> str:
    """A value as the user wrote it (TOML spelling), shortened if long."""
    if isinstance(value, (bool, np.bool_)):
        text = "true" if value else "false"
    elif isinstance(value, str):
        text = '"' + value.replace('"', '\\"') + '"'
    elif isinstance(value, float):
        text = repr(value) if math.isfinite(value) else str(value)
    elif isinstance(value, (list, tuple)):
        text = "[" + ", ".join(_fmt(v) for v in value) + "]"
    elif isinstance(value, Mapping):
        text = "{" + ", ".join(f"{k} = {_fmt(v)}" for k, v in value.items()) + "}"
    else:
        text = str(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _kind(value: Any) -> str:
    """TOML name of a value's type, for messages."""
    if isinstance(value, (bool, np.bool_)):
        return "a boolean"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, (list, tuple)):
        return "an array"
    if isinstance(value, Mapping):
        return "a table"
    return f"a {type(value).__name__}"


def _suggest(word: str, valid) -> str:
    lower = {v.lower(): v for v in valid}
    close = difflib.get_close_matches(word.lower(), list(lower), n=1, cutoff=0.6)
    return f"did you mean {lower[close[0]]!r}? " if close else ""


def _number(name: str, value: Any, unit: str, *, gt=None, ge=None, lt=None) -> float:
    """Check one number; return it as float."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise SceneError(f"{name} = {_fmt(value)}: must be a number ({unit}), not {_kind(value)}")
    try:
        x = float(value)
    except OverflowError:
        raise SceneError(f"{name} = {_fmt(value)}: out of floating-point range ({unit})") from None
    if not math.isfinite(x):
        raise SceneError(f"{name} = {_fmt(value)}: must be finite ({unit})")
    for bound, ok, sign in ((gt, x > (gt or 0), ">"), (ge, x >= (ge or 0), ">="),
                            (lt, x < (lt or 0), "<")):
        if bound is not None and not ok:
            raise SceneError(f"{name} = {_fmt(value)}: must be {sign} {_fmt(bound)} ({unit})")
    return x


def _angle(name: str, value: Any, default_unit: str = "deg") -> float:
    """An angle [rad]: a number in ``default_unit`` (a scene file's: degrees) or a string with
    its unit, ``"0.7 rad"``, ``"40 deg"`` (:func:`stand.io.units.parse_quantity`)."""
    what = (f"an angle: a number ({default_unit}) or a string with its unit, e.g. \"0.7 rad\" "
            f"({', '.join(QUANTITIES['angle'])})")
    if isinstance(value, str):
        try:
            x = parse_quantity(value, "angle", name, default_unit)
        except (UnitError, OverflowError) as exc:
            why = str(exc).split(": ", 1)[-1] if isinstance(exc, UnitError) else "out of range"
            raise SceneError(f"{name} = {_fmt(value)}: {why}; write a number ({default_unit}) or "
                             "a string such as \"0.7 rad\"") from None
        if not math.isfinite(x):
            raise SceneError(f"{name} = {_fmt(value)}: must be finite ({what})")
        return x
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise SceneError(f"{name} = {_fmt(value)}: must be {what}, not {_kind(value)}")
    x = _number(name, value, default_unit)
    with np.errstate(all="ignore"):
        out = x * QUANTITIES["angle"][default_unit]
    if not math.isfinite(out):
        raise SceneError(f"{name} = {_fmt(value)}: out of floating-point range ({default_unit})")
    return out


class _Table:
    """One TOML table with its dotted path; typed getters with messages."""

    def __init__(self, data: Any, path: str):
        if not isinstance(data, Mapping):
            raise SceneError(f"{path} = {_fmt(data)}: must be a table [{path}], not {_kind(data)}")
        self.data, self.path = data, path

    def name(self, key: str) -> str:
        return f"{self.path}.{key}"

    def __contains__(self, key: str) -> bool:
        return key in self.data

    def allow(self, keys, why: Optional[Callable[[str], Optional[str]]] = None) -> None:
        """Reject every key not in ``keys``; ``why(key)`` may explain the rejection."""
        for key in self.data:
            if key in keys:
                continue
            reason = why(key) if why else None
            if reason:
                raise SceneError(reason)
            raise SceneError(f"unknown key {self.name(key)}: {_suggest(key, keys)}"
                             f"valid keys in [{self.path}]: {', '.join(keys)}")

    def _get(self, key: str, default: Any, what: str) -> Any:
        if key in self.data:
            return self.data[key]
        if default is _REQUIRED:
            raise SceneError(f"{self.name(key)}: missing required key ({what})")
        return default

    def number(self, key: str, unit: str, default: Any = _REQUIRED, **bounds) -> Any:
        value = self._get(key, default, unit)
        if key not in self.data:
            return value
        return _number(self.name(key), value, unit, **bounds)

    def integer(self, key: str, minimum: int = 1, default: Any = _REQUIRED,
                maximum: Optional[int] = None) -> int:
        value = self._get(key, default, "integer")
        if key in self.data:
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
                raise SceneError(f"{self.name(key)} = {_fmt(value)}: must be an integer, "
                                 f"not {_kind(value)}")
            if value < minimum:
                raise SceneError(f"{self.name(key)} = {_fmt(value)}: must be >= {minimum}")
            if maximum is not None and value > maximum:
                raise SceneError(f"{self.name(key)} = {_fmt(value)}: must be <= {maximum}")
        return int(value)

    def string(self, key: str, choices=None, default: Any = _REQUIRED) -> str:
        what = "one of " + ", ".join(f'"{c}"' for c in choices) if choices else "string"
        value = self._get(key, default, what)
        if key in self.data:
            if not isinstance(value, str):
                raise SceneError(f"{self.name(key)} = {_fmt(value)}: must be a string "
                                 f"({what}), not {_kind(value)}")
            if choices and value not in choices:
                raise SceneError(f"{self.name(key)} = {_fmt(value)}: {_suggest(value, choices)}"
                                 f"must be {what}")
        return value

    def per_weight(self, key: str, count: int, count_key: str, unit: str,
                   default: Any = _REQUIRED, scalar: bool = True, **bounds) -> Any:
        """A number per weight: a list of ``count`` numbers, or one number for all."""
        name = self.name(key)
        value = self._get(key, default, unit)
        if key not in self.data:
            return None if value is None else np.full(count, float(value))
        if isinstance(value, (list, tuple)):
            if len(value) != count:
                raise SceneError(f"{name} = {_fmt(value)}: expected {count} values (one per "
                                 f"weight, {count_key} = {count}), got {len(value)}")
            return np.array([_number(f"{name}[{i}]", v, unit, **bounds)
                             for i, v in enumerate(value)])
        if not scalar:
            raise SceneError(f"{name} = {_fmt(value)}: must be a list of {count} numbers ({unit})")
        return np.full(count, _number(name, value, unit, **bounds))


# ---------------------------------------------------------------- tables


#: public names
Table = _Table
number = _number
angle = _angle
fmt = _fmt
kind = _kind
suggest = _suggest
