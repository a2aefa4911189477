"""Autobalancer-damper (book 7.2): steady motions, efficiency and their stability.

Theory of the model :mod:`stand.model.balancers.damper`.  The steady motions are the equilibria
of the rotating frame (:func:`stand.theories.weights.one_model.rotating_form`): the CW locked to the
rotor at ``u = cos(phi)``, a real root of (7.53)
``(1 - u^2) Delta(u) = R_m^2 R_omega^8 e0^2 u^2 / R_g^4`` with
``Delta(u) = (R_omega^2 - 1 + R_m R_omega^4 u / R_g^2)^2 + (H R_omega)^2``,
the shaft deflection (7.52)/(7.62), the efficiency (7.54), the existence
boundaries (7.55)-(7.56) and the stability (numerical counterpart of (7.63),
fast-rotor asymptotics (7.72), critical speeds (7.73)-(7.74)).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from stand.model.balancers._ode import central_jacobian
from stand.model.balancers._params import BOOK
from stand.model.balancers.damper_motion import _EZ, state_from_angles
from stand.theories.weights.one_model import rotating_form

if TYPE_CHECKING:
    from stand.model.balancers.damper_params import DamperParams

__all__ = [
    "DamperSteady", "steady_quartic_roots", "steady_motions", "efficiency", "efficiency_approx",
    "critical_speeds_undamped", "jacobian", "eigenvalues", "is_stable", "fast_rotor_roots",
]


# ---------------------------------------------------------------------------
# steady motions (7.51)-(7.60)
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class DamperSteady:
    """A steady motion of the ABD (an equilibrium of the rotating frame).

    Attributes
    ----------
    label : int
        Book index (Fig. 7.25): e0 < 1: 1, 2 main, 3 (heavy side), 4 (light side);
        e0 >= 1: 1 main, 2 side.
    kind : str
        ``"main"`` or ``"side"``.
    phi : float
        Nutation angle [rad] (negative: heavy side, the book's convention).
    psi : float
        Angle relative to the rotor [rad].
    u : float
        ``cos(phi)`` [-].
    xi, eta : float
        Shaft deflection [-] (7.52), (7.62).
    """

    label: int
    kind: str
    phi: float
    psi: float
    u: float
    xi: float
    eta: float

    def state(self, R_omega: float) -> np.ndarray:
        """Rotating-frame state (CW locked to the rotor, ``theta' = 0``)."""
        return state_from_angles(self.phi, self.psi, R_omega, xi=self.xi, eta=self.eta)

    @property
    def deflection(self) -> float:
        """``|xi + i eta|`` [-]."""
        return math.hypot(self.xi, self.eta)


def _need_rg(p):
    if p.R_g <= 0.0:
        raise ValueError("R_g must be > 0 [dimensionless] for the steady-motion solver (7.53), got 0.0")
    if p.R_omega <= 0.0:
        raise ValueError(f"R_omega must be > 0 [dimensionless], got {p.R_omega!r}")


def steady_quartic_roots(p: DamperParams) -> np.ndarray:
    """Real roots ``u = cos(phi)`` in [-1, 1] of ``(1 - u^2) Delta(u) = R_m^2 R_omega^8 e0^2 u^2 / R_g^4`` (7.53)."""
    _need_rg(p)
    R = p.R_omega
    a, b, c2 = R * R - 1.0, p.R_m * R ** 4 / p.R_g ** 2, (p.H * R) ** 2
    Q = (p.R_m * R ** 4 / p.R_g ** 2) ** 2 * p.e0 ** 2
    Delta = np.array([b * b, 2 * a * b, a * a + c2])         # highest power first
    poly = np.polymul([-1.0, 0.0, 1.0], Delta)
    poly = np.polyadd(poly, [-Q, 0.0, 0.0])
    r = np.roots(poly)
    tol = 1e-7
    r = r[np.abs(r.imag) <= tol * np.maximum(1.0, np.abs(r))].real
    r = r[(r >= -1.0 - 1e-12) & (r <= 1.0 + 1e-12)]
    # polish
    out = []
    for u in r:
        u = float(np.clip(u, -1.0, 1.0))
        out.append(u)
    return np.array(sorted(set(np.round(out, 13)), reverse=True))


def _Delta(u, p):
    R = p.R_omega
    return (R * R - 1.0 + p.R_m * R ** 4 / p.R_g ** 2 * u) ** 2 + (p.H * R) ** 2


def steady_motions(p: DamperParams) -> list[DamperSteady]:
    """All steady motions at ``p.R_omega`` (7.51)-(7.53), labelled as in Fig. 7.25.

    The book's continuation labels are assigned as follows: heavy-side roots
    (CW unbalance along the rotor's) are motion 3 (e0 < 1) or 2 (e0 >= 1);
    light-side roots sorted by decreasing ``u`` are (1, 4, 2) when there are
    three, and for a single one: 1 if ``u > 0`` else 2 (e0 < 1).
    """
    _need_rg(p)
    R, Rm, e0 = p.R_omega, p.R_m, p.e0
    K = complex(R * R - 1.0, -p.H * R)
    eg = complex(math.cos(p.gamma), math.sin(p.gamma))
    roots = steady_quartic_roots(p)
    light, heavy = [], []
    for u in roots:
        s = math.sqrt(max(0.0, 1.0 - u * u))
        if e0 == 0.0:
            # no unbalance: only the axial positions, e^{i psi} arbitrary
            if s > 1e-12:
                continue
            ent = (u, 0.0, 0.0j)
            light.append(ent)
            continue
        if s < 1e-14 or abs(u) < 1e-14:
            continue
        # i e^{i psi} [-(R_g^2/(R^2 u)) K s - R_m R^2 s] = R_m R^2 e0 e^{i gamma}
        q = -(p.R_g ** 2 / (R * R * u)) * K * s - Rm * R * R * s
        ie = Rm * R * R * e0 * eg / q
        eip = ie / 1j
        psi = math.atan2(eip.imag, eip.real)
        zeta = (p.R_g ** 2 / (R * R)) * (s / u) * 1j * complex(math.cos(psi), math.sin(psi))
        # side: CW offset i s e^{i psi} along e^{i gamma} is the heavy side
        along = (1j * s * complex(math.cos(psi), math.sin(psi)) * eg.conjugate()).real
        if along > 0:
            heavy.append((u, psi, zeta))
        else:
            light.append((u, psi, zeta))
    out = []
    small = e0 < 1.0
    light.sort(key=lambda t: -t[0])
    if small:
        if len(light) >= 3:
            labs = [1, 4, 2] + [0] * (len(light) - 3)
        elif len(light) == 2:
            labs = [1, 2] if light[1][0] < 0 else [1, 4]
        else:
            labs = [1 if (light and light[0][0] > 0 and R > 1.0) else 2]
    else:
        labs = [1] * len(light)
    for (u, psi, zeta), lab in zip(light, labs):
        kind = "main" if lab in (1, 2) else "side"
        out.append(DamperSteady(lab, kind, math.acos(u), psi, u, zeta.real, zeta.imag))
    for (u, psi, zeta) in heavy:
        # book convention: the heavy side has phi < 0 (psi shifted by pi)
        out.append(DamperSteady(3 if small else 2, "side", -math.acos(u),
                                math.atan2(-math.sin(psi), -math.cos(psi)), u,
                                zeta.real, zeta.imag))
    return sorted(out, key=lambda m: m.label)


def efficiency(p: DamperParams, u: float | None = None) -> float:
    """Efficiency ``n = sqrt(Delta(0)/Delta(u))`` [-] (7.54): shaft deflection with the ABD
    over that without it.  ``u`` defaults to the largest positive root of (7.53)
    (the branch stable by (7.68))."""
    _need_rg(p)
    if u is None:
        r = steady_quartic_roots(p)
        r = r[r > 0]
        if r.size == 0:
            return math.nan
        u = float(r.max())
    return math.sqrt(_Delta(0.0, p) / _Delta(u, p))


def efficiency_approx(p: DamperParams) -> float:
    """Approximation of (6.114) with ``u = sqrt(1 - e0^2)`` [-] (e0 <= 0.6); the print lacks the
    square root on the numerator (digest 2.3)."""
    _need_rg(p)
    if p.e0 >= 1.0:
        raise ValueError(f"e0 must be < 1 [capacity units] for (6.114), got {p.e0!r}")
    return efficiency(p, math.sqrt(1.0 - p.e0 ** 2))


def critical_speeds_undamped(R_m: float, R_g: float, e0: float) -> dict:
    """Existence boundaries (7.55)-(7.56) for ``H = 0`` (duplicated print line removed, E6).

    Returns
    -------
    dict
        ``e0_star`` [-], ``R1`` [-], and ``R2``, ``R3`` [-] (NaN when the
        radicand ``R_g^4 - 4 R_m R_g^2 cos^3 phi_k`` is negative);
        ``phi_k = arcsin(e0^(1/3))``.
    """
    R_m, R_g, e0 = BOOK.each(("R_m", R_m, "dimensionless", "> 0"),
                             ("R_g", R_g, "dimensionless", "> 0"),
                             ("e0", e0, "capacity units", ">= 0"))
    if e0 >= 1.0:
        raise ValueError(f"e0 must be < 1 [capacity units] for (7.56), got {e0!r}")
    g2 = R_g * R_g
    x = (g2 / (4.0 * R_m)) ** (2.0 / 3.0)
    e_star = (1.0 - x) ** 1.5 if x < 1.0 else 0.0
    pk = math.asin(e0 ** (1.0 / 3.0))
    c3 = math.cos(pk) ** 3
    R1 = math.sqrt((math.sqrt(g2 * g2 + 4 * R_m * g2 * c3) - g2) / (2 * R_m * c3))
    disc = g2 * g2 - 4 * R_m * g2 * c3
    if disc >= 0.0:
        R2 = math.sqrt((g2 - math.sqrt(disc)) / (2 * R_m * c3))
        R3 = math.sqrt((g2 + math.sqrt(disc)) / (2 * R_m * c3))
    else:
        R2 = R3 = math.nan
    return {"e0_star": e_star, "phi_k": pk, "R1": R1, "R2": R2, "R3": R3}


# ---------------------------------------------------------------------------
# stability (2.4): numerical Jacobian on the tangent space of |n| = 1
# ---------------------------------------------------------------------------

def _tangent(n):
    t1 = np.cross(n, _EZ)
    if np.linalg.norm(t1) < 1e-8:
        t1 = np.cross(n, np.array([1.0, 0.0, 0.0]))
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    return t1, t2


def jacobian(p: DamperParams, s, *, step: float = 1e-6) -> np.ndarray:
    """9x9 Jacobian of the rotating-frame equations (evaluated on the one model,
    :func:`stand.theories.weights.one_model.rotating_form`) at ``s`` in the chart
    ``(xi, eta, xi', eta', eps1, eps2, W1, W2, W3)``, ``n = normalise(n0 + eps1 t1 + eps2 t2)``
    -- the book's 9 first-order variables (``x, y, phi, psi, p`` and rates), without the
    constraint direction."""
    s = np.asarray(s, dtype=float)
    n0 = s[4:7] / np.linalg.norm(s[4:7])
    t1, t2 = _tangent(n0)

    def full(v):
        n = n0 + v[4] * t1 + v[5] * t2
        n = n / np.linalg.norm(n)
        return np.concatenate([v[:4], n, v[6:9]])

    def red(ds):
        return np.concatenate([ds[:4], [ds[4:7] @ t1, ds[4:7] @ t2], ds[7:10]])

    form = rotating_form("damper", p)
    v0 = np.concatenate([s[:4], [0.0, 0.0], s[7:10]])
    return central_jacobian(lambda v: red(form(full(v))), v0, np.full(9, step))


def eigenvalues(p: DamperParams, motion: DamperSteady) -> np.ndarray:
    """The 9 characteristic roots of a steady motion (numerical counterpart of (7.63)),
    sorted by decreasing real part."""
    lam = np.linalg.eigvals(jacobian(p, motion.state(p.R_omega)))
    return lam[np.argsort(-lam.real)]


def is_stable(p: DamperParams, motion: DamperSteady, *, tol: float = 1e-7) -> bool:
    """Asymptotic stability: all 9 roots with real part < ``-tol``."""
    return bool(np.all(eigenvalues(p, motion).real < -tol))


def fast_rotor_roots(p: DamperParams, phi: float) -> np.ndarray:
    """Fast-rotor asymptotics (7.72) of a main motion, converted to ``lambda`` [-].

    Uses ``lambda = R_omega mu`` (erratum E7: the print's ``mu = lambda / nu``
    contradicts ``b_11 = a_11 / R_omega^2``), ``nu = 1 / R_omega``.  Returns the
    five roots ``lambda^(5), lambda^(6), lambda^(7), lambda^(8), lambda^(9)``.
    """
    R = BOOK.positive("R_omega", p.R_omega, "dimensionless")
    nu, Rm, h, H = 1.0 / R, p.R_m, p.h, p.H
    s2, c2 = math.sin(phi) ** 2, math.cos(phi) ** 2
    den = s2 + Rm * c2
    re56 = -nu / (2 * (1 - Rm) * (1 - Rm * c2)) * (
        h * (s2 + 2 * Rm ** 2 * (1 - Rm) * c2 ** 2) / den + H * Rm * (1 + (1 - 2 * Rm) * c2))
    im56 = math.sqrt(Rm * den / ((1 - Rm) * (1 - Rm * c2)))
    mu = np.array([complex(re56, im56), complex(re56, -im56), complex(-h * nu, 1.0),
                   complex(-h * nu, -1.0), complex(-nu * h * Rm * c2 / den, 0.0)])
    return R * mu


