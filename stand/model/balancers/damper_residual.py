"""Autobalancer-damper (book 7.2): residual unbalance left by dry friction, (7.80)-(7.84).

Part of :mod:`stand.model.balancers.damper`.  A Coulomb moment in the CW suspension
(cardan, sphere in a spherical cavity, ball joint) lets the CW stick short of
the balancing position; the worst-case residual unbalance follows from the
parametric form (7.80) with the friction ratio ``R_f`` of (7.81) (cardan,
sphere) or (7.84) (ball joint).  The time-domain counterpart is the
regularised friction of :class:`~stand.model.balancers.damper.DryFriction`.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from stand.model.balancers._params import BOOK

__all__ = ["R_f_cardan", "R_f_ball_joint", "residual_parametric", "residual_unbalance",
           "residual_cubic"]


# ---------------------------------------------------------------------------
# dry friction: residual unbalance (7.80)-(7.84)
# ---------------------------------------------------------------------------

def R_f_cardan(R_l: float, f: float) -> float:
    """``R_f = R_l f / sqrt(1 + f^2)`` [-] (7.81), ``R_l = h_j / l`` (joint radius over arm)."""
    R_l, f = BOOK.each(("R_l", R_l, "dimensionless", ">= 0"), ("f", f, "dimensionless", ">= 0"))
    return R_l * f / math.sqrt(1.0 + f * f)


def R_f_ball_joint(phi: float, R_l: float, theta: float, f: float) -> float:
    """Ball-joint friction ratio (7.84) [-]: ``R_l sin(gamma_f)`` for ``phi <= theta + gamma_f``,
    else ``R_l [sin(phi - theta) + sin(phi - theta - gamma_f)]`` (``gamma_f = arctan f``,
    ``theta`` the socket wrap angle [rad]), valid for ``phi < pi/2 - theta``."""
    R_l, f, theta, phi = BOOK.each(("R_l", R_l, "dimensionless", ">= 0"),
                                   ("f", f, "dimensionless", ">= 0"),
                                   ("theta", theta, "rad", ">= 0"), ("phi", phi, "rad", ">= 0"))
    if phi >= math.pi / 2 - theta:
        raise ValueError(f"phi must be < pi/2 - theta = {math.pi / 2 - theta:g} [rad], got {phi!r}")
    gf = math.atan(f)
    if phi <= theta + gf:
        return R_l * math.sin(gf)
    return R_l * (math.sin(phi - theta) + math.sin(phi - theta - gf))


def residual_parametric(phi, R_m: float, R_f) -> tuple[np.ndarray, np.ndarray]:
    """(7.80): ``s(phi)`` and ``s_res(phi)`` [capacity units] for ``0 <= phi < arccos R_f``.

    ``s_res = R_f sin phi / (R_m (cos phi - R_f))``, ``s = sin phi + s_res``.
    ``R_m`` here is ``m / M_Sigma`` (equal to :attr:`DamperParams.R_m` when
    ``A = m l^2``); ``R_f`` may be an array (ball joint, (7.84))."""
    phi = np.asarray(phi, dtype=float)
    R_f = np.asarray(R_f, dtype=float)
    sres = R_f * np.sin(phi) / (R_m * (np.cos(phi) - R_f))
    return np.sin(phi) + sres, sres


def residual_unbalance(s, R_m: float, R_f: float) -> np.ndarray:
    """Exact worst-case residual unbalance ``s_res(s)`` [capacity units] from (7.80) (root of the
    parametric form; cardan/sphere, constant ``R_f``).  Valid while ``phi <= pi/2`` (s <= 1 region
    and beyond up to the parametric limit)."""
    R_m, R_f = BOOK.each(("R_m", R_m, "dimensionless", "> 0"), ("R_f", R_f, "dimensionless", ">= 0"))
    if R_f >= 1.0:
        raise ValueError(f"R_f must be < 1 [dimensionless], got {R_f!r}")
    s_arr = np.atleast_1d(np.asarray(s, dtype=float))
    out = np.empty_like(s_arr)
    top = min(math.pi / 2, math.acos(R_f)) - 1e-12
    s_top = float(residual_parametric(top, R_m, R_f)[0])
    for k, sv in enumerate(s_arr):
        if sv < 0 or not math.isfinite(sv):
            raise ValueError(f"s must be a finite number >= 0 [capacity units], got {sv!r}")
        if sv == 0.0:
            out[k] = 0.0
            continue
        if sv > s_top:
            raise ValueError(f"s must be <= {s_top:g} [capacity units] for R_m = {R_m}, R_f = {R_f}, got {sv!r}")
        phi = brentq(lambda a: float(residual_parametric(a, R_m, R_f)[0]) - sv, 0.0, top, xtol=1e-14)
        out[k] = float(residual_parametric(phi, R_m, R_f)[1])
    return out if np.ndim(s) else float(out[0])


def residual_cubic(s, R_m: float, R_f: float, *, printed: bool = True):
    """Explicit approximation (7.82) ``a1 s + a3 s^3`` [capacity units].

    ``a1 = R_f/(R_m + R_f(1 - R_m))`` is correct; the printed
    ``a3 = R_m^3 R_f (1 - R_f)^2 / [R_m + R_f (1 - R_m)]^4`` does not give the
    claimed 3 % (E9); ``printed=False`` uses the Taylor value ``a3/2`` (still ~7 %).
    Prefer :func:`residual_unbalance`.
    """
    s = np.asarray(s, dtype=float)
    d = R_m + R_f * (1.0 - R_m)
    a1 = R_f / d
    a3 = R_m ** 3 * R_f * (1.0 - R_f) ** 2 / d ** 4
    if not printed:
        a3 = 0.5 * a3
    return a1 * s + a3 * s ** 3
