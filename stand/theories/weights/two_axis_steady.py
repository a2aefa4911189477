"""Two-axis pendulum CW (ch. 6): steady (synchronous) motions, section 6.2.

Theory of the model :mod:`stand.model.balancers.two_axis`.  First-group motions (sin phi~ != 0)
from the quartic (6.36) in ``u = cos(phi~)`` with (6.37)-(6.38) and the
efficiency (6.40); second-group motions (6.29)-(6.30); the gravity-free,
undamped case of section 6.2.2, (6.46)-(6.51).  Each motion carries the
eigenvalues of the linearised (6.12) (numerical Jacobian); the analytic
characteristic equations are in :mod:`stand.theories.weights.two_axis_theory`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, List, Optional

import numpy as np

from stand.model.balancers._ode import central_jacobian
from stand.theories.weights.one_model import rotating_form

if TYPE_CHECKING:
    from stand.model.balancers.two_axis_params import TwoAxisParams

__all__ = [
    "SteadyMotion", "jacobian", "eigenvalues", "max_real_part",
    "steady_polynomial", "first_group", "second_group", "steady_motions",
    "no_gravity_no_damping", "efficiency", "r0",
]


# ---------------------------------------------------------------------------
# linearisation
# ---------------------------------------------------------------------------

def jacobian(fun, y0, *args, eps=1e-6):
    """Central-difference Jacobian of ``fun(0, y, *args)`` at ``y0`` (8 x 8)."""
    y0 = np.asarray(y0, float)
    return central_jacobian(lambda y: fun(0.0, y, *args), y0, eps * np.maximum(1.0, np.abs(y0)))


def eigenvalues(p: TwoAxisParams, y0) -> np.ndarray:
    """Eigenvalues of the linearised (6.12) at the rotating-frame state ``y0`` (the rotating
    frame evaluated on the one model, :func:`stand.theories.weights.one_model.rotating_form`)."""
    form = rotating_form("two_axis", p)
    return np.linalg.eigvals(jacobian(lambda tau, y: form(y), y0))


def max_real_part(lam, drop_zero=False) -> float:
    """Largest real part; ``drop_zero`` removes the root nearest 0 (neutral phase)."""
    lam = np.asarray(lam)
    if drop_zero:
        lam = np.delete(lam, np.argmin(np.abs(lam)))
    return float(np.max(lam.real))


# ---------------------------------------------------------------------------
# steady (synchronous) motions, section 6.2
# ---------------------------------------------------------------------------

def _D(w, H):
    return (w * w - 1.0) ** 2 + H * H * w * w


def r0(p: TwoAxisParams) -> float:
    """No-ABP deflection r~0 = R_m R_omega^2 e0 / sqrt(D(R_omega)) (6.29)/(6.39)."""
    Rw = p.R_omega
    return p.R_m * Rw ** 2 * p.e0 / math.sqrt(_D(Rw, p.H))


def efficiency(p: TwoAxisParams, u) -> np.ndarray:
    """n = r~/r~0 for a first-group motion with cos(phi~) = u, (6.40).

    Depends on (R_omega, H, R_gm, u) only: R_m R_omega^4/R_g^2 = R_omega^4/R_gm.
    """
    Rw, H = p.R_omega, p.H
    if p.R_g == 0:
        raise ValueError("efficiency (6.40) needs R_g > 0 [-]; without gravity the main "
                         "motions are exactly balanced (n = 0)")
    Q = Rw ** 2 - 1 + Rw ** 4 * np.asarray(u, float) / p.R_gm
    return np.sqrt(_D(Rw, H)) / np.sqrt(Q ** 2 + H * H * Rw * Rw)


def steady_polynomial(p: TwoAxisParams) -> np.ndarray:
    """Coefficients (highest first) of the quartic P(u) of (6.36), u = cos(phi~)."""
    Rm, Rg2, Rw, H, e0 = p.R_m, p.R_g2, p.R_omega, p.H, p.e0
    A = Rw ** 2 - 1
    Dw = A * A + H * H * Rw * Rw
    return np.array([Rm ** 2 * Rw ** 8,
                     2 * Rm * Rg2 * Rw ** 4 * A,
                     Dw * Rg2 ** 2 - Rm ** 2 * Rw ** 8 * (1 - e0 * e0),
                     -2 * Rm * Rg2 * Rw ** 4 * A,
                     -Dw * Rg2 ** 2])


@dataclass
class SteadyMotion:
    """A synchronous (steady) motion of (6.12): all rotating-frame derivatives vanish.

    Attributes
    ----------
    phi, psi : float
        CW angles [rad].
    xi, eta : float
        Rotating-frame deflection [rho1^2/l].
    group : int
        1 (sin phi != 0) or 2 (phi = 0 or pi, CW neutral).
    kind : str
        ``main_below`` / ``main_above`` (balancing, CM below/above the pivot),
        ``side_light`` / ``side_heavy`` (side, CW toward the light/heavy side),
        ``neutral_below`` / ``neutral_above`` (second group).
    c : float
        Compensated fraction sin(phi) sin(psi) (= e0 for perfect balance).
    n : float
        Efficiency r~/r~0 (6.40) (nan if e0 = 0).
    eig : ndarray or None
        Eigenvalues of the linearisation (filled by :func:`steady_motions`).
    """
    phi: float
    psi: float
    xi: float
    eta: float
    group: int
    kind: str = ""
    n: float = math.nan
    eig: Optional[np.ndarray] = field(default=None, repr=False)

    @property
    def u(self) -> float:
        return math.cos(self.phi)

    @property
    def c(self) -> float:
        return math.sin(self.phi) * math.sin(self.psi)

    @property
    def r(self) -> float:
        return math.hypot(self.xi, self.eta)

    @property
    def below(self) -> bool:
        return math.cos(self.phi) > 0

    @property
    def state(self) -> np.ndarray:
        """Rotating-frame state vector ``[phi, psi, xi, eta, phi', psi', xi', eta']`` (6.12)."""
        return np.array([self.phi, self.psi, self.xi, self.eta, 0, 0, 0, 0], float)

    @property
    def max_re(self) -> float:
        return math.nan if self.eig is None else max_real_part(self.eig)

    def distance(self, y) -> float:
        """Max-norm distance of the rotating-frame state ``y`` (positions only) from this
        motion, in invariants (cos phi, sin phi sin psi, sin phi cos psi, xi, eta), so that
        the equivalent representation (-phi, psi + pi) and 2 pi wraps count as equal."""
        def inv(ph, ps, xi, et):
            return np.array([math.cos(ph), math.sin(ph) * math.sin(ps),
                             math.sin(ph) * math.cos(ps), xi, et])
        return float(np.abs(inv(*np.asarray(y, float)[:4])
                            - inv(self.phi, self.psi, self.xi, self.eta)).max())

    @property
    def stable(self) -> Optional[bool]:
        return None if self.eig is None else bool(self.max_re < 0)


def _classify(motions: List[SteadyMotion], e0: float) -> None:
    """Physical labels (digest 3.6): heavy if c < 0; among c > 0 states with the same
    sign of cos(phi), the larger |cos(phi)| is the main motion, the other light-side."""
    for m in motions:
        if m.group == 2:
            m.kind = "neutral_below" if m.below else "neutral_above"
    first = [m for m in motions if m.group == 1]
    for m in first:
        if m.c < 0:
            m.kind = "side_heavy"
    for below in (True, False):
        grp = sorted([m for m in first if m.c >= 0 and m.below == below],
                     key=lambda m: -abs(m.u))
        for k, m in enumerate(grp):
            if e0 > 1:          # e0 > 1: the main motion is the light-side maximal one
                m.kind = "main_below" if below else "main_above"
            else:
                m.kind = ("main_below" if below else "main_above") if k == 0 else "side_light"


def first_group(p: TwoAxisParams, tol=1e-12) -> List[SteadyMotion]:
    """First-group steady motions (sin phi~ != 0) with gravity, H >= 0 (6.33)-(6.40).

    u = cos(phi~) runs over the real roots of P(u) (6.36) in (-1, 1) (2 or 4 of them);
    with s = sign(u): sin(psi~) = s Q / sqrt(Q^2 + H^2 R_omega^2),
    cos(psi~) = -s H R_omega / sqrt(...), Q = R_omega^2 - 1 + R_omega^4 u / R_gm (6.37),
    and (xi~, eta~) from (6.38).  phi~ in (0, pi) (the flip phi -> -phi, psi -> psi + pi
    is the same motion).  Needs R_g > 0 and e0 > 0 (see :func:`no_gravity_no_damping`).
    """
    if p.R_g == 0:
        raise ValueError("first_group needs R_g > 0 [-]; use no_gravity_no_damping for R_g = 0")
    if p.e0 == 0:
        return []
    Rw, H = p.R_omega, p.H
    roots = np.roots(steady_polynomial(p))
    us = sorted({float(r.real) for r in roots
                 if abs(r.imag) <= 1e-7 * max(1.0, abs(r)) and -1 < r.real < 1})
    # polish on the quartic
    poly = np.poly1d(steady_polynomial(p))
    dpoly = poly.deriv()
    out = []
    for u in us:
        for _ in range(3):
            d = dpoly(u)
            if d != 0:
                u = u - poly(u) / d
        if not -1 < u < 1:
            continue
        Q = Rw ** 2 - 1 + Rw ** 4 * u / p.R_gm
        N = math.sqrt(Q * Q + H * H * Rw * Rw)
        s = 1.0 if u >= 0 else -1.0
        psi = math.atan2(s * Q / N, -s * H * Rw / N) if N > 0 else math.pi / 2
        K = p.R_m * Rw ** 2 * p.e0 / (N * N) if N > 0 else math.nan
        out.append(SteadyMotion(phi=math.acos(u), psi=psi, xi=-K * Q, eta=-K * H * Rw,
                                group=1, n=float(efficiency(p, u))))
    _classify(out, p.e0)
    return out


def second_group(p: TwoAxisParams) -> List[SteadyMotion]:
    """Second-group motions (6.29), (6.30): phi~ = 0 (CW hanging) and pi (upright).

    They exist at every speed and are always unstable (6.112).  psi~ is along the
    deflection (xi~ sin psi~ - eta~ cos psi~ = 0).
    """
    Rw, H = p.R_omega, p.H
    Dw = _D(Rw, H)
    K = p.R_m * Rw ** 2 * p.e0 / Dw
    xi, eta = -K * (Rw ** 2 - 1), -K * H * Rw
    psi = math.atan2(eta, xi) if (xi or eta) else 0.0
    return [SteadyMotion(phi=0.0, psi=psi, xi=xi, eta=eta, group=2, n=1.0),
            SteadyMotion(phi=math.pi, psi=psi, xi=xi, eta=eta, group=2, n=1.0)]


def no_gravity_no_damping(p: TwoAxisParams) -> List[SteadyMotion]:
    """First-group motions for R_g = 0 and H = 0, section 6.2.2, (6.46)-(6.51).

    psi~ = pi/2.  e0 < 1: main phi~1 = phi0 = arcsin e0 (below), phi~2 = pi - phi0
    (above), both with xi~ = eta~ = 0 (exact balance); side phi~3 = -pi/2 (heavy
    side), phi~4 = pi/2 (light side) with xi~ = -R_m R_omega^2 (e0 - sin phi~) / (R_omega^2 - 1),
    eta~ = 0 (from s3, s4 of (6.25)).
    e0 > 1: phi~1 = pi/2 (main, light side) and phi~2 = -pi/2 (side, heavy).
    Requires R_omega != 1.  Labels are set directly (the CM is on the pivot level for
    phi = +-pi/2).
    """
    if p.R_g != 0 or p.H != 0:
        raise ValueError(f"no_gravity_no_damping needs R_g = 0 and H = 0 [-], got "
                         f"R_g={p.R_g!r}, H={p.H!r}")
    Rw, e0 = p.R_omega, p.e0
    if Rw == 1:
        raise ValueError("no_gravity_no_damping: R_omega = 1 [-] (resonance) is singular")
    K = p.R_m * Rw ** 2

    def side(sf, kind):
        return SteadyMotion(phi=math.asin(sf), psi=math.pi / 2,
                            xi=-K * (e0 - sf) / (Rw ** 2 - 1), eta=0.0, group=1, kind=kind,
                            n=abs(e0 - sf) / e0 if e0 else math.nan)
    if e0 <= 1:
        ph0 = math.asin(e0)
        return [SteadyMotion(ph0, math.pi / 2, 0.0, 0.0, 1, "main_below", 0.0),
                SteadyMotion(math.pi - ph0, math.pi / 2, 0.0, 0.0, 1, "main_above", 0.0),
                side(-1.0, "side_heavy"), side(1.0, "side_light")]
    return [side(1.0, "main_light"), side(-1.0, "side_heavy")]


def steady_motions(p: TwoAxisParams, *, stability=True) -> List[SteadyMotion]:
    """All steady motions (first group then second), labelled, with eigenvalues.

    Uses :func:`first_group` (R_g > 0) or :func:`no_gravity_no_damping`
    (R_g = H = 0); the R_g = 0, H > 0 case is not covered by the book and raises.
    """
    if p.R_g > 0:
        motions = first_group(p) + second_group(p)
        _classify(motions, p.e0)
    elif p.H == 0:
        motions = no_gravity_no_damping(p) + second_group(p)
        _classify([m for m in motions if m.group == 2], p.e0)
    else:
        raise ValueError(f"steady_motions: R_g = 0 with H = {p.H!r} > 0 [-] is not treated "
                         "in ch. 6 (section 6.2.2 assumes H = 0)")
    if stability:
        for m in motions:
            m.eig = eigenvalues(p, m.state)
    return motions
