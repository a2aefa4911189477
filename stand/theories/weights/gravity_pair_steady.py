"""Gravity-insensitive coupled pair (book 7.1): steady motions and their stability.

Theory of the model :mod:`stand.model.balancers.gravity_pair`.  The steady (synchronous)
motions are the equilibria of the rotating-frame system (7.6) (evaluated on the one
model, :mod:`stand.theories.weights.one_model`): main motions
``phi = arcsin e0`` (7.7), first-group side motions (CWs fully deflected)
outside the band (7.8), second-group side motions (``sin phi = 0``), and for
``e0 > 1`` the set (7.9).  Stability by the numerical Jacobian (the
counterpart of (7.11), (7.21)-(7.22), (7.26)).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from stand.model.balancers._ode import central_jacobian
from stand.theories.weights.one_model import rotating_form

if TYPE_CHECKING:
    from stand.model.balancers.gravity_pair_params import GravityPairParams

__all__ = ["SteadyMotion", "steady_motions", "side_band", "jacobian", "eigenvalues", "is_stable"]


# ---------------------------------------------------------------------------
# steady (synchronous) motions (7.6)-(7.9)
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class SteadyMotion:
    """A steady synchronous motion: an equilibrium of the rotating-frame system.

    Attributes
    ----------
    label : int
        The book's index (Fig. 7.7 for e0 < 1, Fig. 7.8 for e0 > 1).
    kind : str
        ``"main"``, ``"side-1"`` (first group: CWs fully deflected) or
        ``"side-2"`` (second group: CW centre of mass on the axis).
    phi, psi : float
        Transverse angle and angle relative to the rotor [rad].
    xi, eta : float
        Rotating-frame shaft deflection [-].
    """

    label: int
    kind: str
    phi: float
    psi: float
    xi: float
    eta: float

    @property
    def state(self) -> np.ndarray:
        """Rotating-frame state vector (rates zero)."""
        return np.array([self.phi, self.psi, self.xi, self.eta, 0.0, 0.0, 0.0, 0.0])

    @property
    def deflection(self) -> float:
        """Shaft deflection ``|xi + i eta|`` [-]."""
        return math.hypot(self.xi, self.eta)


def _wrap(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def steady_motions(p: GravityPairParams) -> list[SteadyMotion]:
    """All steady motions at ``p.R_omega`` (solutions of (7.6)).

    For ``e0 < 1`` (7.7): main motions 1 (``phi = arcsin e0``) and 2
    (``pi - arcsin e0``) with ``xi = eta = 0``; first-group side motions 3
    (heavy side, ``phi = -pi/2``) and 4 (light side, ``phi = pi/2``) only
    outside the band (7.8); second-group side motions 5 (``phi = 0``) and 6
    (``phi = pi``).  For ``e0 > 1`` (7.9): 1 (light side, main), 2 (heavy
    side), 3 (``phi = 0``), 4 (``phi = pi``).  First-group motions are labelled by
    continuity of the two roots of their quadratic (see the code comment); the
    heavy-side branch is written with ``phi = -pi/2`` (the book's convention).

    Returns
    -------
    list of SteadyMotion, sorted by label.
    """
    Rw, Rm, e0, g = p.R_omega, p.R_m, p.e0, p.gamma
    if Rw == 0.0:
        raise ValueError("R_omega must be > 0 [dimensionless] for steady motions, got 0.0")
    K = complex(Rw * Rw - 1.0, -p.H * Rw)         # (R^2 - 1 - i H R) zeta = -R_m R^2 (...)
    cR = Rm * Rw * Rw
    eg = complex(math.cos(g), math.sin(g))
    out = []
    small = e0 < 1.0
    if small:
        ph0 = math.asin(e0)
        psi_m = _wrap(g + math.pi / 2)
        out.append(SteadyMotion(1, "main", ph0, psi_m, 0.0, 0.0))
        out.append(SteadyMotion(2, "main", math.pi - ph0, psi_m, 0.0, 0.0))
    # first group: sin(phi) = +1, zeta = i t e^{i psi}, |K t + cR| = cR e0
    if cR > 0.0:
        a2 = abs(K) ** 2
        a1 = 2.0 * K.real * cR
        a0 = cR * cR * (1.0 - e0 * e0)
        disc = a1 * a1 - 4.0 * a2 * a0
        if disc >= 0.0:
            sq = math.sqrt(disc)
            for k, t in enumerate(((-a1 + sq) / (2 * a2), (-a1 - sq) / (2 * a2))):
                q = K * t + cR
                eip = -cR * e0 * eg / (1j * q) if e0 > 0 else 1j
                psi = math.atan2(eip.imag, eip.real)
                zeta = 1j * t * complex(math.cos(psi), math.sin(psi))
                # The larger root t is the light-side branch above resonance and the
                # heavy-side branch below it (H -> 0: t = R_m R^2 (-1 +- e0)/(R^2 - 1));
                # the roots stay distinct inside each region, so this labelling is
                # continuous (a side test fails near the band edges, where the two
                # branches merge).
                heavy = (k == 0) == (Rw < 1.0)
                phi = -math.pi / 2 if heavy else math.pi / 2
                if heavy:                       # same configuration, book convention phi < 0
                    psi += math.pi
                if small:
                    lab, kind = (3, "side-1") if heavy else (4, "side-1")
                else:
                    lab, kind = (2, "side-1") if heavy else (1, "main")
                out.append(SteadyMotion(lab, kind, phi, _wrap(psi), zeta.real, zeta.imag))
    # second group: sin(phi) = 0
    zeta = -cR * e0 * eg / K
    psi = math.atan2(zeta.imag, zeta.real) if abs(zeta) > 0 else 0.0
    base = 5 if small else 3
    out.append(SteadyMotion(base, "side-2", 0.0, psi, zeta.real, zeta.imag))
    out.append(SteadyMotion(base + 1, "side-2", math.pi, psi, zeta.real, zeta.imag))
    return sorted(out, key=lambda s: s.label)


def side_band(p: GravityPairParams) -> tuple[float, float]:
    """Band ``(R^(1), R^(2))`` of (7.8) where the first-group side motions do not exist.

    Requires ``0 < e0 < 1``.  ``R^(1/2) = sqrt(1 + H^2/(4 tg^2 phi0)) -/+ H/(2 tg phi0)``.
    """
    if not (0.0 < p.e0 < 1.0):
        raise ValueError(f"e0 must be in (0, 1) [capacity units] for (7.8), got {p.e0!r}")
    k = p.H / (2.0 * math.tan(p.phi0))
    r = math.sqrt(1.0 + k * k)
    return r - k, r + k


# ---------------------------------------------------------------------------
# stability: numerical Jacobian of the rotating-frame system
# ---------------------------------------------------------------------------

def jacobian(p: GravityPairParams, y, *, step: float = 1e-6) -> np.ndarray:
    """Central-difference Jacobian (8x8) of the rotating-frame equations (7.2) at the state
    ``y``, evaluated on the one model (:func:`stand.theories.weights.one_model.rotating_form`)."""
    return central_jacobian(rotating_form("gravity_pair", p), y, np.full(8, step))


def eigenvalues(p: GravityPairParams, motion: SteadyMotion) -> np.ndarray:
    """Characteristic roots of a steady motion (the numerical counterpart of
    (7.11), (7.21)-(7.22), (7.26)), sorted by decreasing real part."""
    lam = np.linalg.eigvals(jacobian(p, motion.state))
    return lam[np.argsort(-lam.real)]


def is_stable(p: GravityPairParams, motion: SteadyMotion, *, tol: float = 1e-7) -> bool:
    """Asymptotic stability: all roots with real part < ``-tol``."""
    return bool(np.all(eigenvalues(p, motion).real < -tol))
