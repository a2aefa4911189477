"""Liquid float-type autobalancer on a Jeffcott rotor: model M1 of paper 001.

Dubovik & Pashkov, *Motion of an unbalanced rotor with a liquid autobalancing
device when the angular speed increases linearly* (digest
``papers_001_003_004.md`` section 1, model M1 in section 5.1).

A rotor of mass ``m1`` (eccentricity ``e``) sits on a massless isotropic shaft of
stiffness ``c`` with external viscous damping ``chi`` on the absolute velocity
of the shaft centre O1.  Its chamber (radius ``r1``) holds a liquid of mass
``m2`` and a float (radius ``r2``) that stays centred on the bearing axis O2.
The liquid centroid is at ``r * O2O1`` with ``r = r1^2/(r1^2 - r2^2)`` (3), so
the liquid acts as a rigid "lever" mass and the rotor behaves like a Jeffcott
rotor of effective mass ``m = m1 + r m2`` (l. 41) driven by the unbalance
``m1 e``.  The design parameter is ``psi = m1/m`` (8).

Parameters follow the digest (section 5.1, M1): ``(Omega_0, psi, n, e,
omega_0, epsilon)`` with ``m = m1/psi``, ``c = m1 Omega_0^2``, ``chi = n m1``.
**epsilon is half the angular acceleration**: the speed law is (6)
``beta' = omega_0 + 2 epsilon t``.

Equations (complex notation, ``Z = xi + i eta`` fixed, ``z = x + i y = Z e^{-i beta}``
rotating, all lengths in metres):

* fixed frame, the digest's corrected (4) (the seed prints ``beta^2`` and
  ``beta'`` where ``beta'^2`` and ``beta''`` belong; re-derived here from (2)-(3):
  the rotor COM is ``Z + e e^{i beta}``, the liquid COM ``r Z``, so
  ``-cZ - chi Z' - m1 (Z + e e^{i beta})'' - m2 r Z'' = 0``)::

      m Z'' + chi Z' + c Z = m1 e (beta'^2 - i beta'') e^{i beta}

* rotating frame, (9) exactly as printed (verified: real and imaginary parts of
  the fixed-frame equation after ``Z = z e^{i beta}``)::

      m (x'' - 2 beta' y' - beta'' y - beta'^2 x) + c x + chi (x' - beta' y) =  m1 e beta'^2
      m (y'' + 2 beta' x' + beta'' x - beta'^2 y) + c y + chi (y' + beta' x) = -m1 e beta''

* initial conditions (7) (fixed) / (10) (rotating): the stationary orbit (5) at
  ``omega_0``, ``Z(0) = psi e omega_0^2 / (Omega^2 - omega_0^2 + 2 i h omega_0)``,
  ``Z'(0) = i omega_0 Z(0)``; in the rotating frame ``z' (0) = 0``.

* outputs (11): ``delta = |z|`` [m] and the system unbalance
  ``d = |z/(e psi) + 1|`` [-].  The digest's check of (11) (system COM
  ``m z + m1 e``) confirms ``psi = m1/m = 1/(1 + r m2/m1)``; the printed
  ``psi = 1/(1 + m2/m1)`` (l. 63) drops ``r`` and is **not** used here.

Shorthands used throughout: ``Omega^2 = c/m = psi Omega_0^2`` (8),
``2h = chi/m = n psi``, ``q = psi e`` and the COM variable
``W = Z + q e^{i beta}`` (digest 1.2, "useful reformulation"), which obeys
``W'' + 2h W' + Omega^2 W = q (Omega^2 + 2 i h omega) e^{i beta}`` and has a
continuous velocity even across a speed step.

Integrators: :func:`simulate` wraps :func:`scipy.integrate.solve_ivp` (any of
its methods) and a fixed-step classical Runge-Kutta 4 (``method="RK4"``, the
paper's class of method, l. 77) that shows the numerical damping of the free
whirl described in digest 1.6 / 5.2 item 4.

Modules
-------
This module holds the parameters and re-exports the model's functions from
:mod:`.liquid_float_motion` (speed laws (6), stationary orbit (5), initial
conditions (7)/(10), right-hand sides (4)/(9)) and :mod:`.liquid_float_run`
(RK4, :func:`simulate`, outputs (11)), so ``stand.model.balancers.liquid_float.<name>``
keeps working for all of them.  The closed-form run-up is in
:mod:`.runup_closed_form`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from stand.model.balancers._params import PAPER
from stand.model.balancers.liquid_float_motion import (FRAMES, GeneralSpeed, LinearSpeed, StepSpeed, initial_state,
                                  jac_fixed, jac_rotating, rhs_fixed, rhs_rotating,
                                  stationary_amplitude, steady_amplitudes)
from stand.model.balancers.liquid_float_run import (SCIPY_METHODS, LiquidFloatRun, outputs_from_fixed,
                               outputs_from_rotating, rk4_fixed_step, simulate)

__all__ = [
    "LiquidFloatParams", "LinearSpeed", "StepSpeed", "GeneralSpeed",
    "stationary_amplitude", "initial_state", "rhs_fixed", "rhs_rotating",
    "jac_fixed", "jac_rotating", "rk4_fixed_step", "simulate", "LiquidFloatRun",
    "steady_amplitudes", "outputs_from_fixed", "outputs_from_rotating",
    "FRAMES", "SCIPY_METHODS",
]


# ---------------------------------------------------------------------------
# parameters
# ---------------------------------------------------------------------------

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
