"""Shared pieces of the rotor builders: parameter validation and the parts of the
:class:`~stand.model.rotors.structure.LinearRotor` assembly that every builder repeats.

Validation.  Every builder checks its physical parameters the same way: a
number that is not a finite real (or fails its rule) raises :class:`ValueError`
naming the parameter, its unit and the value given, e.g.
``mass must be a positive finite number [kg], got -1.0``.  The rules are
``"finite"``, ``"positive"``, ``"nonnegative"`` and ``"nonzero"``
(:func:`check`, with the short forms :func:`positive`, :func:`nonnegative`,
:func:`finite`, :func:`nonzero`; :func:`per_coordinate` for a scalar or one
value per coordinate, e.g. a damping pair).

Assembly (structure.py module docstring, book 2.5-2.8):

* :func:`transverse_gravity` -- the fixed-frame transverse gravity
  ``(g_x, g_y)`` [m/s^2], the ``gravity_plane`` of a rotor;
* :func:`weight_force` -- the constant generalised force of point masses,
  ``sum_i m_i T_i^T (g_x, g_y)`` (virtual work of their weights through the
  plane maps T_i);
* :func:`gyroscopic_pair` -- the per-unit-spin gyroscopic matrix of an
  axisymmetric body, ``G[i, j] = C``, ``G[j, i] = -C`` (the ``C w beta'``,
  ``-C w alpha'`` terms of (2.64) and (2.122));
* :func:`axis_planes` -- named plane maps of points at given positions;
* :func:`listed_unbalance` -- the rotor's own static unbalance as the
  ``unbalances`` tuple (empty for s = 0).
"""
from __future__ import annotations

import math
from typing import Callable, Mapping

import numpy as np

from stand.model.rotors.structure import Unbalance

__all__ = ["check", "positive", "nonnegative", "finite", "nonzero", "per_coordinate",
           "transverse_gravity", "weight_force", "gyroscopic_pair", "axis_planes",
           "listed_unbalance"]

#: rule -> (test on a finite float, words of the error message)
_RULES = {
    "finite": (lambda v: True, "a finite number"),
    "positive": (lambda v: v > 0.0, "a positive finite number"),
    "nonnegative": (lambda v: v >= 0.0, "a non-negative finite number"),
    "nonzero": (lambda v: v != 0.0, "non-zero and finite"),
}


def _as_float(value) -> float:
    """``float(value)``, or nan for anything that is not a real number."""
    try:
        return float(value)
    except (TypeError, ValueError, OverflowError):
        return math.nan


def check(name: str, value, unit: str, rule: str = "finite", note: str = "") -> float:
    """``value`` as a float, checked against ``rule``.

    Parameters
    ----------
    name : str
        The parameter's name as the caller knows it (e.g. ``"k1"``, ``"Hanger.length"``).
    value : float-like
        The value given.
    unit : str
        Its SI unit, e.g. ``"N m/rad"`` (``"-"`` for a pure number).
    rule : {"finite", "positive", "nonnegative", "nonzero"}
        What the value must be besides a finite real number.
    note : str, optional
        Why, appended after the unit (e.g. ``" (a plane at the fixed point does not move)"``).

    Returns
    -------
    v : float
        The value converted, in ``unit``.

    Raises
    ------
    ValueError
        ``"{name} must be {rule words} [{unit}]{note}, got {value!r}"``, also for
        what is not a real number (None, a string, a complex, an overflowing int).
    """
    test, words = _RULES[rule]
    v = _as_float(value)
    if not (math.isfinite(v) and test(v)):
        raise ValueError(f"{name} must be {words} [{unit}]{note}, got {value!r}")
    return v


def positive(name: str, value, unit: str) -> float:
    """:func:`check` with rule ``"positive"`` (> 0)."""
    return check(name, value, unit, "positive")


def nonnegative(name: str, value, unit: str) -> float:
    """:func:`check` with rule ``"nonnegative"`` (>= 0)."""
    return check(name, value, unit, "nonnegative")


def finite(name: str, value, unit: str) -> float:
    """:func:`check` with rule ``"finite"`` (any finite real)."""
    return check(name, value, unit, "finite")


def nonzero(name: str, value, unit: str, note: str = "") -> float:
    """:func:`check` with rule ``"nonzero"`` (finite, != 0)."""
    return check(name, value, unit, "nonzero", note)


def per_coordinate(name: str, value, n: int, unit: str, rule: str = "nonnegative") -> np.ndarray:
    """One value per coordinate, given as a scalar (the same for all) or ``n`` values.

    Parameters
    ----------
    name, unit : str
        As in :func:`check` (e.g. ``"damping"``, ``"N m s/rad"``).
    value : float or sequence of n floats
    n : int
        Number of coordinates.
    rule : str, optional
        Rule of :func:`check` for every value (default ``"nonnegative"``, as for
        viscous damping or damping ratios).

    Returns
    -------
    ndarray (n,)

    Raises
    ------
    ValueError
        Naming the parameter, unit and value when any value breaks the rule or
        the shape does not broadcast to (n,).
    """
    test, words = _RULES[rule]
    try:
        v = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy()
    except (TypeError, ValueError):
        v = np.full(n, math.nan)
    if not all(math.isfinite(x) and test(x) for x in v):
        raise ValueError(f"{name} must be {words} or a sequence of {n} of them [{unit}], "
                         f"got {value!r}")
    return v


def transverse_gravity(g, name: str = "g") -> np.ndarray:
    """The transverse gravity in the fixed frame, checked.

    Parameters
    ----------
    g : (float, float)
        ``(g_x, g_y)`` [m/s^2]; zeros for a vertical axis.
    name : str, optional
        Parameter name for the messages.

    Returns
    -------
    ndarray (2,)
        ``(g_x, g_y)`` [m/s^2]: the rotor's ``gravity_plane``.
    """
    try:
        gx, gy = g
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (g_x, g_y) [m/s^2], got {g!r}") from None
    return np.array([finite(f"{name}[0]", gx, "m/s^2"), finite(f"{name}[1]", gy, "m/s^2")])


def weight_force(g: np.ndarray, *masses) -> np.ndarray:
    """Constant generalised force [N, N m] of point masses under gravity:
    ``sum_i m_i (T_i^T g)``.

    Parameters
    ----------
    g : ndarray (2,)
        Transverse gravity ``(g_x, g_y)`` [m/s^2] (:func:`transverse_gravity`).
    *masses : (float, ndarray (2, n)) pairs
        Each mass m_i [kg] with the plane map T_i of the point where it sits
        (its centre of mass).
    """
    return sum(m * (np.asarray(T, dtype=float).T @ g) for m, T in masses)


def gyroscopic_pair(n: int, i: int, j: int, C: float) -> np.ndarray:
    """Gyroscopic matrix per unit spin of an axisymmetric spinning body.

    Parameters
    ----------
    n : int
        Number of coordinates.
    i, j : int
        Indices of the two tilt coordinates (alpha, beta) of the spin axis.
    C : float
        Polar moment of inertia [kg m^2].

    Returns
    -------
    ndarray (n, n)
        ``G[i, j] = C``, ``G[j, i] = -C``, zero elsewhere [kg m^2]: the terms
        ``C w beta'`` and ``-C w alpha'`` of (2.64) and (2.122).
    """
    G = np.zeros((n, n))
    G[i, j], G[j, i] = C, -C
    return G


def axis_planes(positions: Mapping[str, float], plane_map: Callable[[float], np.ndarray],
                checked: Callable[[str, float], float]) -> dict:
    """Plane maps of named points of the rotor's axis.

    Parameters
    ----------
    positions : mapping of str -> float
        Plane name -> its position [m] (axial distance or coordinate, as the
        builder defines it).
    plane_map : callable
        Position [m] -> the plane map T (2 x n) of that point (e.g. (2.70)).
    checked : callable
        ``checked(name, position)`` validates one position and returns it as a
        float; it chooses the label of the error (e.g. ``"planes['balancer']"``).

    Returns
    -------
    dict of str -> ndarray (2, n)
    """
    return {name: plane_map(checked(name, z)) for name, z in positions.items()}


def listed_unbalance(plane: str, s, angle) -> tuple:
    """The rotor's own static unbalance as the ``unbalances`` field of a LinearRotor.

    Parameters
    ----------
    plane : str
        Plane where the unbalance acts (e.g. ``"balancer"``).
    s : float
        Unbalance [kg m]; 0 lists none.
    angle : float
        Its angle from the reference mark [rad].

    Returns
    -------
    tuple of Unbalance
        One entry, or none when ``s == 0``.
    """
    return (Unbalance(plane, float(s), float(angle)),) if s else ()
