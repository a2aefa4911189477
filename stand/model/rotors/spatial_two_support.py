"""Paper 003 (Filimonikhina & Filimonikhin), model M2: a rigid compound rotor
on two isotropic elastic supports, balanced by passive autobalancers in one or
two planes (papers digest sections 2.3-2.6, oracles O10-O13).

:func:`two_support_rotor` builds a validated :class:`TwoSupportRotor` with
(14), the central axes (31)-(34), the rotating-frame steady equations
(17)-(19), the critical speeds (36)-(41), the criterion form (26) with its
compact form "K_xi(w) and K_eta(w) negative definite", single-plane static
balancing (42)-(43), and the fixed-frame :class:`LinearRotor`
(:meth:`TwoSupportRotor.linear_rotor`).  Axial coordinate from the rotor's
centre of mass O: support 1 at ``-l1``, support 2 at ``+l2`` (paper (12)).

:mod:`stand.model.rotors.spatial` re-exports these names.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from stand.model.rotors._build import finite, gyroscopic_pair, nonnegative, positive
from stand.model.rotors.spatial_supports import _REL, _supports_at, numbered_planes, plane_map
from stand.model.rotors.structure import LinearRotor

__all__ = ["TwoSupportRotor", "two_support_rotor"]


@dataclass(frozen=True)
class TwoSupportRotor:
    """Paper 003 model M2: rigid compound rotor on two isotropic elastic supports.

    Axial coordinate ``zeta`` from the rotor's centre of mass O: support 1 at
    ``-l1``, support 2 at ``+l2`` (paper (12)); the compound rotor's centre of
    mass G at ``zeta_G``; balancer planes at ``a_i``.  ``J_xi``, ``J_eta`` are
    the transverse moments about the O axes, ``C`` the axial moment (all of the
    compound rotor in the main motion); ``d1``, ``d2`` optional support damping.
    Use :func:`two_support_rotor` to build it (validation).

    Central axes (31)-(33)::

        J_G = J - M zeta_G^2,  l1~ = l1 + zeta_G,  l2~ = l2 - zeta_G,  a~ = a - zeta_G,
        c11~ = c1 + c2,  c14~ = c2 l2~ - c1 l1~,  c33~ = c1 l1~^2 + c2 l2~^2

    Rotating-frame steady equations (17): ``K_xi(w) (x~, phi) = w^2 (M xi_G, J_xi_zeta)``,
    ``K_eta(w) (y~, -theta) = w^2 (M eta_G, J_eta_zeta)`` with
    ``K(w) = [[c11~ - M w^2, c14~], [c14~, c33~ - (J_G - C) w^2]]``; the fixed-
    frame tilts are ``beta <-> phi``, ``alpha <-> theta``.
    """

    c1: float
    c2: float
    l1: float
    l2: float
    M: float
    J_xi: float
    J_eta: float
    C: float
    zeta_G: float = 0.0
    d1: float = 0.0
    d2: float = 0.0

    # (14), (31)-(34) -----------------------------------------------------
    def stiffness_O(self):
        """(14): ``(c11, c14, c33)`` about O: ``c1 + c2``, ``c2 l2 - c1 l1``,
        ``c1 l1^2 + c2 l2^2`` [N/m, N/rad, N m/rad]."""
        return (self.c1 + self.c2, self.c2 * self.l2 - self.c1 * self.l1,
                self.c1 * self.l1 ** 2 + self.c2 * self.l2 ** 2)

    @property
    def l_tilde(self):
        """(32): distances of the supports from G, ``(l1 + zeta_G, l2 - zeta_G)`` [m]."""
        return self.l1 + self.zeta_G, self.l2 - self.zeta_G

    def central_moments(self):
        """(31): ``(J_G_xi, J_G_eta) = (J_xi - M zeta_G^2, J_eta - M zeta_G^2)`` [kg m^2]."""
        s = self.M * self.zeta_G ** 2
        return self.J_xi - s, self.J_eta - s

    def stiffness_G(self, c1=None, c2=None):
        """(33): ``(c11~, c14~, c33~)`` about G (pass ``c1``, ``c2`` = damping
        coefficients to get the damping analogue)."""
        c1 = self.c1 if c1 is None else c1
        c2 = self.c2 if c2 is None else c2
        L1, L2 = self.l_tilde
        return c1 + c2, c2 * L2 - c1 * L1, c1 * L1 ** 2 + c2 * L2 ** 2

    def invariant(self) -> float:
        """(34): ``c11~ c33~ - c14~^2 = c1 c2 (l1 + l2)^2`` [N^2/rad] (shift-invariant)."""
        c11, c14, c33 = self.stiffness_G()
        return c11 * c33 - c14 * c14

    def a_tilde(self, a):
        """(32): balancer-plane position from G, ``a - zeta_G`` [m]."""
        return np.asarray(a, dtype=float) - self.zeta_G

    def _J(self, axis):
        Jx, Je = self.central_moments()
        if axis in ("xi", "x"):
            return Jx
        if axis in ("eta", "y"):
            return Je
        raise ValueError(f"axis must be 'xi' or 'eta', got {axis!r}")

    # (17)-(19), (38)-(41) -------------------------------------------------
    def K(self, omega: float, axis: str = "xi") -> np.ndarray:
        """(17): rotating-frame synchronous stiffness ``K_xi(w)`` or ``K_eta(w)`` (2 x 2)."""
        c11, c14, c33 = self.stiffness_G()
        w2 = float(omega) ** 2
        return np.array([[c11 - self.M * w2, c14], [c14, c33 - (self._J(axis) - self.C) * w2]])

    def delta_coefficients(self, axis: str = "xi"):
        """(39): ``(a, b, c)`` of ``Delta_1(w) = a w^4 - b w^2 + c`` (38) and ``D = b^2 - 4ac``."""
        c11, c14, c33 = self.stiffness_G()
        JC = self._J(axis) - self.C
        a, b, c = self.M * JC, JC * c11 + self.M * c33, c11 * c33 - c14 * c14
        return a, b, c, (self.M * c33 - JC * c11) ** 2 + 4 * self.M * JC * c14 * c14

    def delta(self, omega, axis: str = "xi"):
        """(38): ``Delta_{1,2}(w) = det K_{xi,eta}(w)`` [N^2/rad]; ``omega`` may be an array."""
        a, b, c, _ = self.delta_coefficients(axis)
        w2 = np.square(np.asarray(omega, dtype=float))
        return a * w2 * w2 - b * w2 + c

    def critical_speeds(self, axis: str = "xi") -> np.ndarray:
        """(40)-(41): critical speeds of the compound rotor [rad/s], ascending.

        ``J_G > C``: two, ``sqrt((b -+ sqrt(D)) / (2a))`` (40); ``J_G < C``: one,
        ``sqrt((b - sqrt(D)) / (2a))`` (41); ``J_G = C``: one, ``sqrt(c / b)``.
        """
        a, b, c, D = self.delta_coefficients(axis)
        if abs(a) <= _REL * self.M * max(self._J(axis), self.C):
            return np.array([math.sqrt(c / b)])
        q = 0.5 * (b + math.copysign(math.sqrt(D), b))   # cancellation-free roots
        return np.sqrt(np.sort([x for x in (q / a, c / q) if x > 0]))

    def plane_stiffness(self, a) -> float:
        """(33): ``c~_(i) = c1 (l1~ + a~)^2 + c2 (l2~ - a~)^2`` [N m/rad], the tilting
        stiffness about the axis point of the plane at ``a`` [m] (from O)."""
        at = float(self.a_tilde(a))
        L1, L2 = self.l_tilde
        return self.c1 * (L1 + at) ** 2 + self.c2 * (L2 - at) ** 2

    def plane_speed(self, a, axis: str = "xi") -> float:
        """(36)-(37): ``w_i = sqrt(c~_(i) / P_i)``, ``P_i = J_G + M a~^2 - C`` [rad/s]
        (``nan`` if ``P_i <= 0``)."""
        at = float(self.a_tilde(a))
        P = self._J(axis) + self.M * at * at - self.C
        return math.sqrt(self.plane_stiffness(a) / P) if P > 0 else math.nan

    # criterion (1)/(24)-(30), (43) ----------------------------------------
    def criterion_form(self, omega: float, a1: float, a2: float) -> np.ndarray:
        """(26) with ``mu m = 1``: the 4 x 4 symmetric matrix of ``f`` in
        ``(xi_1, xi_2, eta_1, eta_2)`` [m per (kg m)],
        ``diag(w^2 P K_xi^-1 P^T, w^2 P K_eta^-1 P^T)``, ``P = [[1, a1~], [1, a2~]]``.
        The main motion is stable iff it is negative definite (undamped rotor)."""
        P = np.array([[1.0, float(self.a_tilde(a1))], [1.0, float(self.a_tilde(a2))]])
        w2 = float(omega) ** 2
        F = np.zeros((4, 4))
        F[:2, :2] = w2 * P @ np.linalg.solve(self.K(omega, "xi"), P.T)
        F[2:, 2:] = w2 * P @ np.linalg.solve(self.K(omega, "eta"), P.T)
        return 0.5 * (F + F.T)

    def is_stable(self, omega: float) -> bool:
        """Compact form of the generalised criterion for two distinct planes:
        stable main motion iff ``K_xi(w)`` and ``K_eta(w)`` are negative definite
        (papers digest section 2.4).  Independent of the plane positions."""
        return all(bool(np.all(np.linalg.eigvalsh(self.K(omega, ax)) < 0)) for ax in ("xi", "eta"))

    def single_plane_stable(self, omega: float, a: float) -> bool:
        """(42)-(43): static balancing by one balancer at ``a`` [m]: stable iff
        ``(c~_(1) - w^2 P_1) / Delta < 0`` for both xi and eta."""
        at = float(self.a_tilde(a))
        out = True
        for ax in ("xi", "eta"):
            P = self._J(ax) + self.M * at * at - self.C
            out &= bool((self.plane_stiffness(a) - omega ** 2 * P) / self.delta(omega, ax) < 0)
        return out

    # steady response (18)-(19) -------------------------------------------
    def steady_response(self, omega: float, unbalances) -> dict:
        """(18)-(19): rotating-frame steady (main-motion) displacement ``K^-1 RHS``.

        ``unbalances``: sequence of ``(a [m from O], s [kg m], angle [rad])``.
        With support damping (d1, d2) the two systems couple::

            [[K_xi, -w D], [w D, K_eta]] (x~, phi, y~, -theta) = w^2 (F_xi, F_eta)

        Returns a dict with ``x``, ``y`` (of G) [m], ``theta``, ``phi`` [rad]
        (rotor frame; the fixed-frame motion is ``x + i y -> (x + i y) e^{i w t}``,
        ``beta - i alpha -> (phi - i theta) e^{i w t}``).
        """
        w = float(omega)
        F = np.zeros(4)
        for a, s, ang in unbalances:
            at = float(self.a_tilde(a))
            F += w * w * s * np.array([math.cos(ang), at * math.cos(ang),
                                       math.sin(ang), at * math.sin(ang)])
        d11, d14, d33 = self.stiffness_G(self.d1, self.d2)
        Dm = np.array([[d11, d14], [d14, d33]])
        S = np.block([[self.K(w, "xi"), -w * Dm], [w * Dm, self.K(w, "eta")]])
        x, phi, y, mth = np.linalg.solve(S, F)
        return {"x": x, "y": y, "theta": -mth, "phi": phi}

    # fixed-frame LinearRotor ----------------------------------------------
    def linear_rotor(self, balancers=(), unbalances=(), name: str = "two_support") -> LinearRotor:
        """The fixed-frame :class:`LinearRotor` in central coordinates
        ``(x_G, y_G, alpha, beta)`` (axisymmetric compound rotor only, ``J_xi = J_eta``;
        an unequal pair makes the fixed-frame coefficients periodic).

        Planes: ``"com"`` (G), ``"support1"``, ``"support2"``, ``"O"``,
        ``"balancer1"``, ... at ``a_i`` [m from O] and ``"unbalance1"``, ...
        """
        if not math.isclose(self.J_xi, self.J_eta, rel_tol=_REL):
            raise ValueError(f"linear_rotor needs an axisymmetric rotor, got J_xi = {self.J_xi!r} "
                             f"and J_eta = {self.J_eta!r} kg m^2; use K_xi/K_eta (rotating frame)")
        JG = self.central_moments()[0]
        L1, L2 = self.l_tilde
        K = _supports_at((-L1, L2), (self.c1, self.c2), (self.c1, self.c2), "paper 003 (33)").matrix
        D = _supports_at((-L1, L2), (self.d1, self.d2), (self.d1, self.d2), "damping").matrix
        planes = {"com": plane_map(0.0), "support1": plane_map(-L1), "support2": plane_map(L2),
                  "O": plane_map(-self.zeta_G)}
        numbered, ubs = numbered_planes(balancers, unbalances, origin=self.zeta_G)
        planes.update(numbered)
        return LinearRotor(name=name, coords=("x_G [m]", "y_G [m]", "alpha [rad]", "beta [rad]"),
                           M=np.diag([self.M, self.M, JG, JG]), G=gyroscopic_pair(4, 2, 3, self.C),
                           D=D, K=K, planes=planes, unbalances=ubs,
                           source="paper 003 (Filimonikhina & Filimonikhin), (12)-(14), (31)-(33)")


def two_support_rotor(c1: float, c2: float, l1: float, l2: float, M: float, J_xi: float,
                      J_eta: float, C: float, zeta_G: float = 0.0, d1: float = 0.0,
                      d2: float = 0.0) -> TwoSupportRotor:
    """Paper 003 (model M2): rigid compound rotor on two isotropic supports.

    Parameters
    ----------
    c1, c2 : float   support stiffnesses [N/m] (> 0)
    l1, l2 : float   distances of supports 1 (at zeta = -l1) and 2 (at +l2) from O [m]
    M : float        mass of the compound rotor [kg]
    J_xi, J_eta : float  transverse moments about the O axes [kg m^2] (> M zeta_G^2)
    C : float        axial moment [kg m^2]
    zeta_G : float   axial position of the compound centre of mass G [m], |zeta_G| shifts (31)-(32)
    d1, d2 : float   optional support viscous damping [N s/m] (not in the paper)
    """
    c1 = positive("c1", c1, "N/m")
    c2 = positive("c2", c2, "N/m")
    l1 = finite("l1", l1, "m")
    l2 = finite("l2", l2, "m")
    if l1 + l2 <= 0:
        raise ValueError(f"support separation l1 + l2 must be > 0 m, got {l1 + l2!r} m")
    M = positive("M", M, "kg")
    J_xi = positive("J_xi", J_xi, "kg m^2")
    J_eta = positive("J_eta", J_eta, "kg m^2")
    C = nonnegative("C", C, "kg m^2")
    zeta_G = finite("zeta_G", zeta_G, "m")
    for n, J in (("J_xi", J_xi), ("J_eta", J_eta)):
        if J - M * zeta_G ** 2 <= 0:
            raise ValueError(f"{n} = {J!r} kg m^2 must exceed M zeta_G^2 = {M * zeta_G ** 2!r} "
                             "kg m^2 (the central moment (31) must be positive)")
    return TwoSupportRotor(c1, c2, l1, l2, M, J_xi, J_eta, C, zeta_G,
                           nonnegative("d1", d1, "N s/m"), nonnegative("d2", d2, "N s/m"))
