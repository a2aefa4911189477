"""One JSON converter for every result the stand prints or stores.

:func:`to_jsonable` turns dataclasses, mappings, sequences, numpy arrays and
scalars, complex numbers, paths and any object with a ``to_dict()`` method (the
result objects of :mod:`stand.io.result`; pandas objects aside) into plain JSON
values; non-finite floats become ``null`` (JSON has no NaN), as in the reports'
schemas.
"""
from __future__ import annotations

import dataclasses
import json
import math
from pathlib import PurePath
from typing import Any

import numpy as np

__all__ = ["to_jsonable", "dumps"]


def to_jsonable(obj: Any) -> Any:
    """A plain JSON value (dict, list, str, int, float, bool, None) for ``obj``."""
    if type(obj) is not dict and _has_to_dict(obj):
        return to_jsonable(obj.to_dict())
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: to_jsonable(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, (list, tuple, set, frozenset)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [to_jsonable(v) for v in obj.tolist()]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (complex, np.complexfloating)):
        return {"re": to_jsonable(float(obj.real)), "im": to_jsonable(float(obj.imag))}
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, PurePath):
        return str(obj)
    return obj


def _has_to_dict(obj) -> bool:
    """A result object (:class:`stand.io.result.Result` and kin); not a pandas object (whose
    ``to_dict`` is a table's), not a dataclass (its fields are its JSON)."""
    return (callable(getattr(type(obj), "to_dict", None))
            and not type(obj).__module__.startswith("pandas")
            and not dataclasses.is_dataclass(obj))


def dumps(obj: Any, **kwargs) -> str:
    """``json.dumps(to_jsonable(obj))``; strict JSON (no NaN), ``str`` for unknown objects."""
    return json.dumps(to_jsonable(obj), allow_nan=False, default=str, **kwargs)
