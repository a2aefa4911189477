"""Parameters of the liquid float model: LiquidFloatParams and the speed laws.

Part of :mod:`stand.model.balancers.liquid_float` (the model, its equations and units are
described there).  The modules that name the parameters import them from here and this
module imports none of them, so there is no circle.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from stand.model.balancers._params import PAPER

__all__ = ["LiquidFloatParams", "LinearSpeed", "StepSpeed", "GeneralSpeed"]


# ---------------------------------------------------------------------------
# speed laws
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class LinearSpeed:
    """Speed law (6): ``omega = omega_0 + 2 epsilon t``, ``beta = omega_0 t + epsilon t^2``.

    Parameters
    ----------
    omega_0 : float
        Speed at t = 0 [rad/s].
    epsilon : float
        Half the angular acceleration [rad/s^2] (note the factor 2 in (6)).
    """

    omega_0: float
    epsilon: float
    jumps: tuple = field(default=(), init=False)

    def beta(self, t):
        """Rotation angle [rad]."""
        return self.omega_0 * t + self.epsilon * t * t

    def omega(self, t):
        """Angular speed [rad/s]."""
        return self.omega_0 + 2.0 * self.epsilon * t

    def alpha(self, t):
        """Angular acceleration [rad/s^2]."""
        return 2.0 * self.epsilon + 0.0 * t


@dataclass(frozen=True)
class StepSpeed:
    """Step change of speed (paper [2], l. 94): ``omega_0`` before ``t_step``,
    ``omega_1`` after.

    The step is an impulsive angular acceleration.  The shaft force is finite,
    so the velocity of the system COM, ``W' = Z' + i q omega e^{i beta}``, is
    continuous; a run (the oracle's ``simulate``) therefore applies the jump
    ``Z'(+) = Z'(-) - i psi e (omega_1 - omega_0) e^{i beta}`` (rotating frame:
    ``z'(+) = z'(-) - i (omega_1 - omega_0)(z + psi e)``) at ``t_step``.

    Parameters
    ----------
    omega_0, omega_1 : float
        Speeds before / after the step [rad/s].
    t_step : float
        Time of the step >= 0 [s].
    """

    omega_0: float
    omega_1: float
    t_step: float = 0.0

    def __post_init__(self):
        PAPER.each(("omega_0", self.omega_0, "rad/s", "finite"),
                   ("omega_1", self.omega_1, "rad/s", "finite"), ("t_step", self.t_step, "s", ">= 0"))

    @property
    def jumps(self):
        return ((float(self.t_step), float(self.omega_1 - self.omega_0)),)

    def beta(self, t):
        t = np.asarray(t, dtype=float)
        out = np.where(t < self.t_step, self.omega_0 * t,
                       self.omega_0 * self.t_step + self.omega_1 * (t - self.t_step))
        return out if out.ndim else float(out)

    def omega(self, t):
        t = np.asarray(t, dtype=float)
        out = np.where(t < self.t_step, self.omega_0, self.omega_1) + 0.0 * t
        return out if out.ndim else float(out)

    def alpha(self, t):
        return 0.0 * np.asarray(t, dtype=float) if np.ndim(t) else 0.0


@dataclass(frozen=True)
class GeneralSpeed:
    """Any smooth prescribed rotation ``beta(t)``.

    Parameters
    ----------
    beta, omega, alpha : callable
        ``beta(t)`` [rad], its first ``omega(t)`` [rad/s] and second
        ``alpha(t)`` [rad/s^2] derivatives; numpy-vectorised in ``t`` [s].
    """

    beta: Callable
    omega: Callable
    alpha: Callable
    jumps: tuple = field(default=(), init=False)


@dataclass(frozen=True)
class LiquidFloatParams:
    """Parameters of model M1 (paper 001), SI units.

    Parameters
    ----------
    Omega_0 : float
        Critical speed of the bare rotor ``sqrt(c/m1)`` [rad/s] (l. 59).
    psi : float
        ``m1/m`` in (0, 1] [-]; 1 is the rotor without liquid (l. 63, with the
        digest's correction ``m = m1 + r m2``).
    n : float
        Damping parameter ``chi/m1`` >= 0 [1/s] (l. 79).
    e : float
        Rotor eccentricity ``O1P`` > 0 [m] (l. 19).
    omega_0 : float
        Initial (stationary) angular speed >= 0 [rad/s] (l. 53).
    epsilon : float
        **Half** the angular acceleration [rad/s^2]: the speed law (6) is
        ``omega = omega_0 + 2 epsilon t`` (l. 51-53).  Negative = run-down.
    m1 : float, optional
        Rotor mass [kg]; only scales ``m``, ``c``, ``chi``; the deflections do
        not depend on it (digest 1.2).  Default 1 kg.

    Notes
    -----
    Paper values (l. 79): ``Omega_0 = 1000 rad/s``, ``epsilon = 10 rad/s^2``,
    ``omega_0 = 40 rad/s``, ``n`` in [0, 100] 1/s; see :meth:`paper_001`.
    """

    Omega_0: float
    psi: float
    n: float
    e: float
    omega_0: float
    epsilon: float
    m1: float = 1.0

    def __post_init__(self):
        PAPER.fields(self, ("Omega_0", "rad/s", "> 0"), ("n", "1/s", ">= 0"), ("e", "m", "> 0"),
                     ("omega_0", "rad/s", ">= 0"), ("epsilon", "rad/s^2", "finite"),
                     ("m1", "kg", "> 0"), ("psi", "dimensionless", "finite"))
        if not 0.0 < self.psi <= 1.0:
            raise PAPER.error("psi", self.psi, "dimensionless",
                              "in (0, 1] (psi = m1/(m1 + r m2) with r > 1, m2 >= 0)")

    # -- constructors ------------------------------------------------------
    @classmethod
    def from_physical(cls, *, m1: float, m2: float, r1: float, r2: float, c: float,
                      chi: float, e: float, omega_0: float, epsilon: float) -> "LiquidFloatParams":
        """Build the parameters from the physical data of paper 001.

        Parameters
        ----------
        m1 : float
            Rotor mass [kg] (l. 31).
        m2 : float
            Liquid mass [kg] (l. 31), >= 0.
        r1, r2 : float
            Chamber and float radii [m], ``r1 > r2 >= 0`` (l. 35).
        c : float
            Shaft stiffness [N/m] (l. 27).
        chi : float
            External viscous friction coefficient [N s/m] (l. 27).
        e : float
            Eccentricity [m].
        omega_0 : float
            Initial speed [rad/s].
        epsilon : float
            Half the angular acceleration [rad/s^2] (6).

        Returns
        -------
        LiquidFloatParams
            With ``r = r1^2/(r1^2 - r2^2)`` (l. 35), ``m = m1 + r m2`` (l. 41),
            ``psi = m1/m`` (digest correction of l. 63), ``Omega_0 = sqrt(c/m1)``,
            ``n = chi/m1``.
        """
        m1, m2, r1, r2 = PAPER.each(("m1", m1, "kg", "> 0"), ("m2", m2, "kg", ">= 0"),
                                    ("r1", r1, "m", "> 0"), ("r2", r2, "m", ">= 0"))
        if r2 >= r1:
            raise ValueError(f"r2 = {r2!r} [m]: the float radius must be smaller than "
                             f"the chamber radius r1 = {r1!r} m")
        c, chi = PAPER.each(("c", c, "N/m", "> 0"), ("chi", chi, "N s/m", ">= 0"))
        r = r1 * r1 / (r1 * r1 - r2 * r2)
        m = m1 + r * m2
        return cls(Omega_0=math.sqrt(c / m1), psi=m1 / m, n=chi / m1, e=e,
                   omega_0=omega_0, epsilon=epsilon, m1=m1)

    @classmethod
    def paper_001(cls, psi: float = 1.0, n: float = 0.0, *, e: float = 1e-4,
                  **overrides) -> "LiquidFloatParams":
        """The paper's set (l. 79): Omega_0 = 1000 rad/s, omega_0 = 40 rad/s,
        epsilon = 10 rad/s^2 (acceleration 20 rad/s^2); ``e`` is arbitrary [m]."""
        kw = dict(Omega_0=1000.0, psi=psi, n=n, e=e, omega_0=40.0, epsilon=10.0)
        kw.update(overrides)
        return cls(**kw)

    # -- derived quantities --------------------------------------------------
    @property
    def m(self) -> float:
        """Effective mass ``m1/psi = m1 + r m2`` [kg] (l. 41)."""
        return self.m1 / self.psi

    @property
    def c(self) -> float:
        """Shaft stiffness ``m1 Omega_0^2`` [N/m]."""
        return self.m1 * self.Omega_0 ** 2

    @property
    def chi(self) -> float:
        """External damping ``n m1`` [N s/m]."""
        return self.n * self.m1

    @property
    def Omega(self) -> float:
        """Critical speed with the liquid ``Omega_0 sqrt(psi)`` [rad/s] (8)."""
        return self.Omega_0 * math.sqrt(self.psi)

    @property
    def h(self) -> float:
        """Half the damping rate ``chi/(2m) = n psi/2`` [1/s]."""
        return 0.5 * self.n * self.psi

    @property
    def zeta(self) -> float:
        """Damping ratio ``h/Omega = n sqrt(psi)/(2 Omega_0)`` [-]."""
        return self.h / self.Omega

    @property
    def q(self) -> float:
        """``m1 e/m = psi e`` [m]: the COM shift scale of ``W``."""
        return self.psi * self.e

    @property
    def acceleration(self) -> float:
        """Angular acceleration ``2 epsilon`` [rad/s^2]."""
        return 2.0 * self.epsilon

    def speed(self) -> "LinearSpeed":
        """The paper's speed law (6) for these parameters."""
        return LinearSpeed(self.omega_0, self.epsilon)

    def time_at_speed(self, omega: float) -> float:
        """Time [s] at which (6) reaches ``omega`` [rad/s]."""
        omega = PAPER.finite("omega", omega, "rad/s")
        if self.epsilon == 0.0:
            raise ValueError("epsilon = 0 [rad/s^2]: the speed never changes")
        t = (omega - self.omega_0) / (2.0 * self.epsilon)
        if t < 0.0:
            raise ValueError(f"omega = {omega!r} [rad/s]: not reached for t >= 0 "
                             f"(omega_0 = {self.omega_0} rad/s, epsilon = {self.epsilon} rad/s^2)")
        return t

    def time_at_z(self, z: float) -> float:
        """Time [s] at which ``omega/Omega_0`` reaches ``z`` [-]."""
        return self.time_at_speed(z * self.Omega_0)
