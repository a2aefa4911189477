"""The ``[[axis]]`` tables of a sweep file: one swept key and its values (a list, a
grid or seeded random samples)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Optional

import numpy as np

from stand.sweep.checks import SweepSpecError, _allow, _fmt, _integer, _kind, _number, _require
from stand.sweep.keys import check_key

__all__ = ["Axis", "read_axis", "AXIS_KEYS"]

AXIS_KEYS = ("key", "values", "start", "stop", "num", "spacing", "random", "low", "high",
             "count", "seed", "name")
#: the keys of each way of giving the values (the first ones select it)
MODES = (("values", ("values",)), ("grid", ("start", "stop", "num")), ("random", ("random",)))
#: keys that do not belong to each way
NOT_USED = {"values": ("spacing", "low", "high", "count", "seed", "start", "stop", "num", "random"),
            "grid": ("low", "high", "count", "seed", "values", "random"),
            "random": ("start", "stop", "num", "spacing", "values")}


@dataclass(frozen=True)
class Axis:
    """One swept parameter.

    Attributes
    ----------
    key : str
        Scene key (dotted), ``R_omega``/``speed`` or a bare dimensionless name.
    values : tuple of float
        The values taken, in the unit of that key (scene-file units: SI, degrees,
        rev/s; dimensionless for ``R_omega`` and the bare names).
    kind : str
        "grid", "values" or "random".
    """

    key: str
    values: tuple
    kind: str


def read_axis(i: int, t: Any, default_seed: Optional[int], base: dict) -> Axis:
    """Validate the ``i``-th ``[[axis]]`` table against the base scene document.

    Parameters
    ----------
    i : int
        Index of the table (for messages: ``axis[i].field``).
    t : mapping
        The table.
    default_seed : int or None
        ``[sweep] seed``, used by a random axis without its own seed.
    base : dict
        The base scene document (:func:`stand.sweep.keys.check_key`).

    Returns
    -------
    Axis

    Raises
    ------
    SweepSpecError
    """
    path = f"axis[{i}]"
    if not isinstance(t, Mapping):
        raise SweepSpecError(f"{path}: must be a table [[axis]], not {_kind(t)}")
    _allow(t, path, AXIS_KEYS)
    if "key" not in t:
        raise SweepSpecError(f"{path}.key: missing required key (a scene key such as "
                             f'"rotor.eccentricity", or "R_omega", "e0", ...)')
    key = t["key"]
    if not isinstance(key, str):
        raise SweepSpecError(f"{path}.key = {_fmt(key)}: must be a string")
    check_key(f"{path}.key", key, base)
    modes = [m for m, ks in MODES if any(k in t for k in ks)]
    if len(modes) != 1:
        raise SweepSpecError(f"{path}: give exactly one of values = [...], a grid (start, stop, "
                             f"num[, spacing]) or random = \"uniform\"|\"log-uniform\" (low, high, "
                             f"count[, seed]); got {' and '.join(modes) if modes else 'none'}")
    mode = modes[0]
    for k in NOT_USED[mode]:
        if k in t:
            raise SweepSpecError(f"{path}.{k} = {_fmt(t[k])}: not used by a {mode} axis")
    unit = f"the unit of {key}"
    if mode == "values":
        vals = t["values"]
        if not isinstance(vals, list) or not vals:
            raise SweepSpecError(f"{path}.values = {_fmt(vals)}: must be a non-empty list of numbers")
        out = tuple(_number(f"{path}.values[{j}]", v, unit) for j, v in enumerate(vals))
    elif mode == "grid":
        out = _grid(path, t, unit)
    else:
        out = _random(i, path, t, unit, default_seed)
    return Axis(key, out, mode)


def _grid(path: str, t: Mapping, unit: str) -> tuple:
    _require(t, path, ("start", "stop", "num"), "a grid axis (start, stop, num[, spacing])")
    a = _number(f"{path}.start", t["start"], unit)
    b = _number(f"{path}.stop", t["stop"], unit)
    num = _integer(f"{path}.num", t["num"], 2)
    spacing = t.get("spacing", "linear")
    if spacing not in ("linear", "log"):
        raise SweepSpecError(f"{path}.spacing = {_fmt(spacing)}: must be \"linear\" or \"log\"")
    if spacing == "log":
        if not (a > 0 and b > 0):
            raise SweepSpecError(f"{path}.start, stop = {_fmt(a)}, {_fmt(b)}: a log grid needs "
                                 "start > 0 and stop > 0")
        return tuple(float(v) for v in np.geomspace(a, b, num))
    return tuple(float(v) for v in np.linspace(a, b, num))


def _random(i: int, path: str, t: Mapping, unit: str, default_seed: Optional[int]) -> tuple:
    dist = t["random"]
    if dist not in ("uniform", "log-uniform"):
        raise SweepSpecError(f"{path}.random = {_fmt(dist)}: must be \"uniform\" or \"log-uniform\"")
    _require(t, path, ("low", "high", "count"), "a random axis (low, high, count[, seed])")
    lo = _number(f"{path}.low", t["low"], unit)
    hi = _number(f"{path}.high", t["high"], unit)
    if not hi > lo:
        raise SweepSpecError(f"{path}.high = {_fmt(t['high'])}: must be > low = {_fmt(t['low'])}")
    count = _integer(f"{path}.count", t["count"], 1)
    seed = t.get("seed", default_seed)
    if seed is None:
        raise SweepSpecError(f"{path}.seed: missing; a random axis needs a seed (here or "
                             "[sweep] seed) so that the sweep can be resumed and repeated")
    seed = _integer(f"{path}.seed", seed, 0, 2 ** 63 - 1)
    # a per-axis stream: the same seed on two axes still gives independent samples
    rng = np.random.default_rng([seed, i])
    if dist == "log-uniform":
        if not lo > 0:
            raise SweepSpecError(f"{path}.low = {_fmt(t['low'])}: log-uniform needs low > 0")
        return tuple(float(v) for v in np.exp(rng.uniform(math.log(lo), math.log(hi), count)))
    return tuple(float(v) for v in rng.uniform(lo, hi, count))
