"""Validation helpers of the sweep file: :class:`SweepSpecError` and typed checks whose
messages name the field, its value and what is expected.

The number check and the value spelling are those of every input table
(:mod:`stand.io.validate`, also the scene files'); its
:class:`stand.scene.model.SceneError` becomes a :class:`SweepSpecError` here
(:func:`spec_errors`).
"""
from __future__ import annotations

import difflib
import numbers
from contextlib import contextmanager
from typing import Any, Iterator, Mapping

import numpy as np

from stand.errors import SceneError
from stand.io.validate import fmt as _fmt, kind as _kind, number

__all__ = ["SweepSpecError", "MAX_POINTS", "spec_errors"]

MAX_POINTS = 10_000_000  #: largest number of points accepted in one sweep


class SweepSpecError(ValueError):
    """A sweep file is invalid.  The message names the field, its value and what is expected."""


@contextmanager
def spec_errors(prefix: str = "") -> Iterator[None]:
    """Re-raise a :class:`stand.scene.model.SceneError` of the scene-file checks as a
    :class:`SweepSpecError` (message prefixed with ``prefix``)."""
    try:
        yield
    except SceneError as exc:
        raise SweepSpecError(f"{prefix}{exc}") from None


def _suggest(word: str, valid) -> str:
    """``"did you mean 'x'? "`` for a close valid word, else ``""``; looser than
    :func:`stand.io.validate.suggest` (cutoff 0.5, case kept) so that short keys
    such as ``eo`` -> ``e0`` are suggested."""
    close = difflib.get_close_matches(word, list(valid), n=1, cutoff=0.5)
    return f"did you mean {close[0]!r}? " if close else ""


def _number(name: str, v: Any, unit: str, **bounds) -> float:
    """A finite number (``gt``/``ge``/``lt`` bounds), :func:`stand.io.validate.number`."""
    with spec_errors():
        return number(name, v, unit, **bounds)


def _integer(name: str, v: Any, minimum: int, maximum: int = MAX_POINTS) -> int:
    """An integer in ``[minimum, maximum]``."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Integral):
        raise SweepSpecError(f"{name} = {_fmt(v)}: must be an integer >= {minimum}, "
                             f"not {_kind(v)}")
    if not minimum <= v <= maximum:
        raise SweepSpecError(f"{name} = {_fmt(v)}: must be an integer >= {minimum} and <= {maximum}")
    return int(v)


def _table(name: str, t: Any) -> Mapping:
    """``t`` if it is a table, else an error naming ``[name]``."""
    if not isinstance(t, Mapping):
        raise SweepSpecError(f"[{name}]: must be a table, not {_kind(t)}")
    return t


def _allow(table: Mapping, path: str, keys) -> None:
    """Reject every key of ``table`` not in ``keys`` (with a suggestion)."""
    for k in table:
        if k not in keys:
            raise SweepSpecError(f"unknown key {path}.{k}: {_suggest(k, keys)}"
                                 f"valid keys in [{path}]: {', '.join(keys)}")


def _require(table: Mapping, path: str, keys, what: str) -> None:
    """Every key of ``keys`` present in ``table``, else an error naming the first missing."""
    for k in keys:
        if k not in table:
            raise SweepSpecError(f"{path}.{k}: missing required key of {what}")
