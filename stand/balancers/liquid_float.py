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
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp

__all__ = [
    "LiquidFloatParams", "LinearSpeed", "StepSpeed", "GeneralSpeed",
    "stationary_amplitude", "initial_state", "rhs_fixed", "rhs_rotating",
    "jac_fixed", "jac_rotating", "rk4_fixed_step", "simulate", "LiquidFloatRun",
    "steady_amplitudes", "outputs_from_fixed", "outputs_from_rotating",
    "FRAMES", "SCIPY_METHODS",
]

FRAMES = ("rotating", "fixed")
SCIPY_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


def _check_finite(name: str, value, unit: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r} [{unit}]: must be a real number") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} = {value!r} [{unit}]: must be finite")
    return v


def _check_positive(name: str, value, unit: str) -> float:
    v = _check_finite(name, value, unit)
    if v <= 0.0:
        raise ValueError(f"{name} = {value!r} [{unit}]: must be > 0")
    return v


def _check_nonneg(name: str, value, unit: str) -> float:
    v = _check_finite(name, value, unit)
    if v < 0.0:
        raise ValueError(f"{name} = {value!r} [{unit}]: must be >= 0")
    return v


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
        for name, unit, check in (("Omega_0", "rad/s", _check_positive),
                                  ("n", "1/s", _check_nonneg),
                                  ("e", "m", _check_positive),
                                  ("omega_0", "rad/s", _check_nonneg),
                                  ("epsilon", "rad/s^2", _check_finite),
                                  ("m1", "kg", _check_positive)):
            object.__setattr__(self, name, check(name, getattr(self, name), unit))
        psi = _check_finite("psi", self.psi, "dimensionless")
        if not 0.0 < psi <= 1.0:
            raise ValueError(f"psi = {self.psi!r} [dimensionless]: must be in (0, 1] "
                             "(psi = m1/(m1 + r m2) with r > 1, m2 >= 0)")
        object.__setattr__(self, "psi", psi)

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
        m1 = _check_positive("m1", m1, "kg")
        m2 = _check_nonneg("m2", m2, "kg")
        r1 = _check_positive("r1", r1, "m")
        r2 = _check_nonneg("r2", r2, "m")
        if r2 >= r1:
            raise ValueError(f"r2 = {r2!r} [m]: the float radius must be smaller than "
                             f"the chamber radius r1 = {r1!r} m")
        c = _check_positive("c", c, "N/m")
        chi = _check_nonneg("chi", chi, "N s/m")
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
        omega = _check_finite("omega", omega, "rad/s")
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
    continuous; :func:`simulate` therefore applies the jump
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
        _check_finite("omega_0", self.omega_0, "rad/s")
        _check_finite("omega_1", self.omega_1, "rad/s")
        _check_nonneg("t_step", self.t_step, "s")

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


def _speed_for(params: LiquidFloatParams, speed):
    return params.speed() if speed is None else speed


# ---------------------------------------------------------------------------
# stationary solution, initial conditions, steady laws
# ---------------------------------------------------------------------------

def stationary_amplitude(params: LiquidFloatParams, omega: float | None = None) -> complex:
    """Complex amplitude ``A`` [m] of the stationary orbit ``Z = A e^{i omega t}`` (5).

    ``A = m1 e omega^2 / (c - m omega^2 + i chi omega)
    = D [(c - m omega^2) - i chi omega]``, with ``D`` of (5).  In the rotating
    frame this is the constant point ``x + i y = A`` of (10).

    Parameters
    ----------
    params : LiquidFloatParams
    omega : float, optional
        Speed [rad/s]; default ``params.omega_0``.

    Raises
    ------
    ValueError
        At the undamped critical speed (``n = 0``, ``omega = Omega``).
    """
    w = params.omega_0 if omega is None else _check_finite("omega", omega, "rad/s")
    den = params.Omega ** 2 - w * w + 2j * params.h * w
    if den == 0:
        raise ValueError(f"omega = {w!r} [rad/s]: equals the critical speed Omega = "
                         f"Omega_0 sqrt(psi) with n = 0; the stationary orbit (5) is unbounded")
    return params.q * w * w / den


def initial_state(params: LiquidFloatParams, frame: str = "rotating",
                  omega: float | None = None) -> np.ndarray:
    """Initial state [m, m, m/s, m/s] from (7) (fixed frame) or (10) (rotating).

    Fixed: ``[xi, eta, xi', eta'] = [Re A, Im A, Re(i w A), Im(i w A)]``, which
    is (7): ``xi = D(c - m w^2)``, ``eta = -D chi w``, ``xi' = D chi w^2``,
    ``eta' = D (c - m w^2) w``.  Rotating: ``[x, y, x', y'] = [Re A, Im A, 0, 0]`` (10).
    At t = 0 the two frames coincide (``beta(0) = 0``).
    """
    frame = _check_frame(frame)
    w = params.omega_0 if omega is None else omega
    A = stationary_amplitude(params, w)
    if frame == "rotating":
        return np.array([A.real, A.imag, 0.0, 0.0])
    V = 1j * w * A
    return np.array([A.real, A.imag, V.real, V.imag])


def steady_amplitudes(params: LiquidFloatParams, omega):
    """Quasi-static (steady) amplitude laws at speed ``omega`` [rad/s] (digest 1.5).

    Returns
    -------
    delta_over_e : ndarray
        ``psi omega^2 / sqrt((Omega^2 - omega^2)^2 + 4 h^2 omega^2)`` [-].
    d : ndarray
        ``sqrt(Omega^4 + 4 h^2 omega^2) / sqrt((Omega^2 - omega^2)^2 + 4 h^2 omega^2)`` [-].
    """
    w = np.asarray(omega, dtype=float)
    O2, h = params.Omega ** 2, params.h
    den = np.sqrt((O2 - w * w) ** 2 + 4.0 * h * h * w * w)
    with np.errstate(divide="ignore"):
        return params.psi * w * w / den, np.sqrt(O2 * O2 + 4.0 * h * h * w * w) / den


# ---------------------------------------------------------------------------
# right-hand sides
# ---------------------------------------------------------------------------

def _check_frame(frame: str) -> str:
    if frame not in FRAMES:
        raise ValueError(f"frame = {frame!r}: must be one of {FRAMES}")
    return frame


def rhs_fixed(params: LiquidFloatParams, speed=None) -> Callable:
    """Right-hand side ``f(t, y)`` of the corrected fixed-frame equations (4).

    ``y = [xi, eta, xi', eta']`` [m, m, m/s, m/s]; ``y`` may also be ``(4, k)``
    (``vectorized=True`` in solve_ivp).  Digest correction of the printed (4):
    the forcing is ``m1 e (beta'^2 cos beta + beta'' sin beta)`` and
    ``m1 e (beta'^2 sin beta - beta'' cos beta)`` (re-derived from (2)-(3)).
    """
    sp = _speed_for(params, speed)
    O2, h2, q = params.Omega ** 2, 2.0 * params.h, params.q
    beta, omega, alpha = sp.beta, sp.omega, sp.alpha

    def f(t, y):
        xi, eta, vxi, veta = y[0], y[1], y[2], y[3]
        b, w, a = beta(t), omega(t), alpha(t)
        cb, sb = np.cos(b), np.sin(b)
        w2 = w * w
        return np.array([vxi, veta,
                         -h2 * vxi - O2 * xi + q * (w2 * cb + a * sb),
                         -h2 * veta - O2 * eta + q * (w2 * sb - a * cb)])
    return f


def rhs_rotating(params: LiquidFloatParams, speed=None) -> Callable:
    """Right-hand side ``f(t, y)`` of the rotating-frame equations (9) (as printed).

    ``y = [x, y, x', y']`` [m, m, m/s, m/s] in the frame ``O2xy`` turning with
    the rotor (x along O1P); ``y`` may be ``(4, k)``.  Divided by ``m``:
    ``x'' = 2 w y' + a y + w^2 x - Omega^2 x - 2h (x' - w y) + q w^2`` and
    ``y'' = -2 w x' - a x + w^2 y - Omega^2 y - 2h (y' + w x) - q a``.
    """
    sp = _speed_for(params, speed)
    O2, h2, q = params.Omega ** 2, 2.0 * params.h, params.q
    omega, alpha = sp.omega, sp.alpha

    def f(t, y):
        x, yy, vx, vy = y[0], y[1], y[2], y[3]
        w, a = omega(t), alpha(t)
        w2 = w * w
        return np.array([vx, vy,
                         2.0 * w * vy + a * yy + (w2 - O2) * x - h2 * (vx - w * yy) + q * w2,
                         -2.0 * w * vx - a * x + (w2 - O2) * yy - h2 * (vy + w * x) - q * a])
    return f


def jac_fixed(params: LiquidFloatParams, speed=None) -> Callable:
    """Jacobian ``J(t, y)`` of :func:`rhs_fixed` (constant) for Radau/BDF/LSODA."""
    O2, h2 = params.Omega ** 2, 2.0 * params.h
    J = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [-O2, 0, -h2, 0], [0, -O2, 0, -h2]], float)
    return lambda t, y: J


def jac_rotating(params: LiquidFloatParams, speed=None) -> Callable:
    """Jacobian ``J(t, y)`` of :func:`rhs_rotating` for Radau/BDF/LSODA."""
    sp = _speed_for(params, speed)
    O2, h2 = params.Omega ** 2, 2.0 * params.h

    def J(t, y):
        w, a = float(sp.omega(t)), float(sp.alpha(t))
        k = w * w - O2
        return np.array([[0, 0, 1, 0], [0, 0, 0, 1],
                         [k, a + h2 * w, -h2, 2 * w],
                         [-a - h2 * w, k, -2 * w, -h2]], float)
    return J


# ---------------------------------------------------------------------------
# fixed-step RK4
# ---------------------------------------------------------------------------

def rk4_fixed_step(fun: Callable, t0: float, y0, dt: float, n_steps: int,
                   record_every: int = 1):
    """Classical 4th-order Runge-Kutta with a fixed step (the paper's method
    class, l. 77, without its step control).

    Parameters
    ----------
    fun : callable
        ``fun(t, y) -> dy/dt`` on a 1-D numpy array.
    t0 : float
        Start time [s].
    y0 : array_like
        Initial state.
    dt : float
        Step [s], > 0.
    n_steps : int
        Number of steps.
    record_every : int
        Keep every ``record_every``-th state (the first and the last are
        always kept).

    Returns
    -------
    t : ndarray, y : ndarray (len(y0), k), nfev : int
    """
    dt = _check_positive("dt", dt, "s")
    n_steps = int(n_steps)
    if n_steps < 0:
        raise ValueError(f"n_steps = {n_steps!r}: must be >= 0")
    if record_every < 1:
        raise ValueError(f"record_every = {record_every!r}: must be >= 1")
    y = np.array(y0, dtype=float)
    ts, ys = [t0], [y.copy()]
    half = 0.5 * dt
    for k in range(1, n_steps + 1):
        t = t0 + (k - 1) * dt
        k1 = fun(t, y)
        k2 = fun(t + half, y + half * k1)
        k3 = fun(t + half, y + half * k2)
        k4 = fun(t + dt, y + dt * k3)
        y = y + (dt / 6.0) * (k1 + 2.0 * (k2 + k3) + k4)
        if k % record_every == 0 or k == n_steps:
            ts.append(t0 + k * dt)
            ys.append(y.copy())
    return np.array(ts), np.array(ys).T, 4 * n_steps


def _rk4_linear_m1(params: LiquidFloatParams, frame: str, omega_0: float, epsilon: float,
                   t0: float, y0, dt: float, n_steps: int, record_every: int):
    """RK4 fast path for M1 with the linear speed law: the same arithmetic as
    :func:`rk4_fixed_step` on :func:`rhs_rotating`/:func:`rhs_fixed` but on
    Python floats (about 4x faster than 4-element numpy arrays)."""
    O2, h2, q = params.Omega ** 2, 2.0 * params.h, params.q
    a = 2.0 * epsilon
    cos, sin = math.cos, math.sin
    if frame == "rotating":
        def f(t, x, y, vx, vy):
            w = omega_0 + a * t
            w2 = w * w
            return (vx, vy,
                    2.0 * w * vy + a * y + (w2 - O2) * x - h2 * (vx - w * y) + q * w2,
                    -2.0 * w * vx - a * x + (w2 - O2) * y - h2 * (vy + w * x) - q * a)
    else:
        def f(t, x, y, vx, vy):
            w = omega_0 + a * t
            b = (omega_0 + epsilon * t) * t
            cb, sb = cos(b), sin(b)
            w2 = w * w
            return (vx, vy, -h2 * vx - O2 * x + q * (w2 * cb + a * sb),
                    -h2 * vy - O2 * y + q * (w2 * sb - a * cb))
    x, y, vx, vy = (float(v) for v in y0)
    ts, ys = [t0], [(x, y, vx, vy)]
    half, sixth = 0.5 * dt, dt / 6.0
    for k in range(1, n_steps + 1):
        t = t0 + (k - 1) * dt
        a1, b1, c1, d1 = f(t, x, y, vx, vy)
        a2, b2, c2, d2 = f(t + half, x + half * a1, y + half * b1, vx + half * c1, vy + half * d1)
        a3, b3, c3, d3 = f(t + half, x + half * a2, y + half * b2, vx + half * c2, vy + half * d2)
        a4, b4, c4, d4 = f(t + dt, x + dt * a3, y + dt * b3, vx + dt * c3, vy + dt * d3)
        x += sixth * (a1 + 2.0 * (a2 + a3) + a4)
        y += sixth * (b1 + 2.0 * (b2 + b3) + b4)
        vx += sixth * (c1 + 2.0 * (c2 + c3) + c4)
        vy += sixth * (d1 + 2.0 * (d2 + d3) + d4)
        if k % record_every == 0 or k == n_steps:
            ts.append(t0 + k * dt)
            ys.append((x, y, vx, vy))
    return np.array(ts), np.array(ys).T, 4 * n_steps


# ---------------------------------------------------------------------------
# simulation driver and outputs
# ---------------------------------------------------------------------------

@dataclass
class LiquidFloatRun:
    """Result of :func:`simulate`; all arrays have the length of ``t``.

    Attributes
    ----------
    t : time [s];  beta : rotation angle [rad];  omega : speed [rad/s]
    z : speed ratio ``omega/Omega_0`` [-] (l. 79)
    x, y, vx, vy : rotating-frame position [m] and velocity [m/s] of O1
    xi, eta, vxi, veta : fixed-frame position [m] and velocity [m/s] of O1
    delta : shaft deflection ``|Z|`` [m] (11);  d : system unbalance [-] (11)
    nfev : right-hand-side evaluations;  wall_time_s : integration time [s]
    """

    params: LiquidFloatParams
    frame: str
    method: str
    t: np.ndarray
    beta: np.ndarray
    omega: np.ndarray
    z: np.ndarray
    x: np.ndarray
    y: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    xi: np.ndarray
    eta: np.ndarray
    vxi: np.ndarray
    veta: np.ndarray
    delta: np.ndarray
    d: np.ndarray
    nfev: int
    wall_time_s: float

    @property
    def Z(self) -> np.ndarray:
        """Complex fixed-frame deflection ``xi + i eta`` [m]."""
        return self.xi + 1j * self.eta

    @property
    def Zdot(self) -> np.ndarray:
        """Complex fixed-frame velocity [m/s]."""
        return self.vxi + 1j * self.veta

    @property
    def W(self) -> np.ndarray:
        """COM variable ``Z + psi e e^{i beta}`` [m] (digest 1.2)."""
        return self.Z + self.params.q * np.exp(1j * self.beta)

    @property
    def Wdot(self) -> np.ndarray:
        """``W'`` [m/s]."""
        return self.Zdot + 1j * self.params.q * self.omega * np.exp(1j * self.beta)


def _outputs(params, speed, t, Z, Zd, frame, method, nfev, wall):
    beta = np.asarray(speed.beta(t), float) + 0.0 * t
    omega = np.asarray(speed.omega(t), float) + 0.0 * t
    rot = np.exp(-1j * beta)
    zr = Z * rot
    zrd = (Zd - 1j * omega * Z) * rot
    return LiquidFloatRun(
        params=params, frame=frame, method=method, t=t, beta=beta, omega=omega,
        z=omega / params.Omega_0, x=zr.real, y=zr.imag, vx=zrd.real, vy=zrd.imag,
        xi=Z.real, eta=Z.imag, vxi=Zd.real, veta=Zd.imag, delta=np.abs(Z),
        d=np.abs(zr / params.q + 1.0), nfev=int(nfev), wall_time_s=float(wall))


def outputs_from_rotating(params, t, state, speed=None, *, method="", nfev=0, wall=0.0):
    """All outputs from a rotating-frame state history ``state`` (4, k) at ``t`` [s]."""
    sp = _speed_for(params, speed)
    t = np.asarray(t, float)
    beta, omega = np.asarray(sp.beta(t)) + 0.0 * t, np.asarray(sp.omega(t)) + 0.0 * t
    zr, zrd = state[0] + 1j * state[1], state[2] + 1j * state[3]
    e = np.exp(1j * beta)
    return _outputs(params, sp, t, zr * e, (zrd + 1j * omega * zr) * e, "rotating",
                    method, nfev, wall)


def outputs_from_fixed(params, t, state, speed=None, *, method="", nfev=0, wall=0.0):
    """All outputs from a fixed-frame state history ``state`` (4, k) at ``t`` [s]."""
    sp = _speed_for(params, speed)
    t = np.asarray(t, float)
    return _outputs(params, sp, t, state[0] + 1j * state[1], state[2] + 1j * state[3],
                    "fixed", method, nfev, wall)


def _apply_speed_jump(params, frame, speed, t, y, d_omega):
    """State just after an instantaneous speed change ``d_omega`` [rad/s] at ``t``:
    ``W'`` is continuous, so ``Z'`` jumps by ``-i psi e d_omega e^{i beta}``
    (rotating frame: ``z'`` jumps by ``-i d_omega (z + psi e)``)."""
    y = np.array(y, float)
    if frame == "fixed":
        b = float(speed.beta(t))
        dv = -1j * params.q * d_omega * complex(math.cos(b), math.sin(b))
    else:
        dv = -1j * d_omega * (complex(y[0], y[1]) + params.q)
    y[2] += dv.real
    y[3] += dv.imag
    return y


def simulate(params: LiquidFloatParams, t_end: float | None = None, *, t_eval=None,
             frame: str = "rotating", method: str = "DOP853", rtol: float = 1e-10,
             atol=None, step: float | None = None, speed=None, t0: float = 0.0,
             y0=None, record_every: int = 1, max_step: float = np.inf) -> LiquidFloatRun:
    """Integrate model M1 in the fixed (corrected (4)) or rotating ((9)) frame.

    Parameters
    ----------
    params : LiquidFloatParams
    t_end : float, optional
        Final time [s]; default ``t_eval[-1]``.
    t_eval : array_like, optional
        Output times [s] for the scipy methods (default: the solver's steps).
        Ignored by ``"RK4"``, which returns every ``record_every``-th step.
    frame : {"rotating", "fixed"}
    method : str
        A :func:`scipy.integrate.solve_ivp` method (``"RK45"``, ``"DOP853"``,
        ``"Radau"``, ``"LSODA"``, ...) or ``"RK4"`` (fixed step ``step``).
    rtol : float
        Relative tolerance (scipy methods).
    atol : float or array_like, optional
        Absolute tolerance; default ``rtol * e * [1, 1, Omega_0, Omega_0]``
        (the state is in m and m/s).
    step : float, optional
        RK4 step [s] (required for ``"RK4"``).
    speed : LinearSpeed, StepSpeed or GeneralSpeed, optional
        Default: the linear law (6) of ``params``.
    t0 : float
        Start time [s] (the speed law is evaluated at absolute times).
    y0 : array_like, optional
        Initial state in ``frame``; default (7)/(10) (stationary orbit at
        ``speed.omega(t0)``).
    record_every : int
        RK4 output decimation.
    max_step : float
        Passed to solve_ivp [s].

    Returns
    -------
    LiquidFloatRun
        Outputs in both frames plus ``nfev`` and the wall time.
    """
    frame = _check_frame(frame)
    sp = _speed_for(params, speed)
    t0 = _check_finite("t0", t0, "s")
    if t_eval is not None:
        t_eval = np.asarray(t_eval, float)
        if t_eval.ndim != 1 or t_eval.size < 1:
            raise ValueError("t_eval must be a non-empty 1-D array of times [s]")
        if t_end is None:
            t_end = float(t_eval[-1])
    if t_end is None:
        raise ValueError("t_end [s] or t_eval must be given")
    t_end = _check_finite("t_end", t_end, "s")
    if t_end <= t0:
        raise ValueError(f"t_end = {t_end!r} [s]: must be > t0 = {t0!r} s")
    if y0 is None:
        # stationary orbit at the speed just before t0 (a step at t0 is applied after)
        w_pre = float(sp.omega(t0)) - sum(dw for tj, dw in sp.jumps if tj == t0)
        y0 = initial_state(params, frame, omega=w_pre)
    y0 = np.asarray(y0, float)
    if y0.shape != (4,):
        raise ValueError(f"y0 has shape {y0.shape}: must be (4,) [m, m, m/s, m/s]")
    if atol is None:
        atol = rtol * params.e * np.array([1.0, 1.0, params.Omega_0, params.Omega_0])
    fun = rhs_rotating(params, sp) if frame == "rotating" else rhs_fixed(params, sp)

    # split at speed steps; the jump at a segment start is applied before it
    jumps = {tj: dw for tj, dw in sp.jumps if t0 <= tj < t_end}
    edges = sorted(set([t0, t_end] + list(jumps)))
    ts, ys, nfev = [], [], 0
    y = y0.copy()
    tic = time.perf_counter()
    for i, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        if a in jumps:
            y = _apply_speed_jump(params, frame, sp, a, y, jumps[a])
        if method == "RK4":
            if step is None:
                raise ValueError("step [s] is required for method = 'RK4'")
            _check_positive("step", step, "s")
            n = max(1, int(round((b - a) / step)))
            dt = (b - a) / n
            if isinstance(sp, LinearSpeed):
                tt, yy, nf = _rk4_linear_m1(params, frame, sp.omega_0, sp.epsilon, a, y, dt, n,
                                            record_every)
            else:
                tt, yy, nf = rk4_fixed_step(fun, a, y, dt, n, record_every)
            keep = np.ones(tt.size, bool)
        elif method in SCIPY_METHODS:
            te, keep = None, None
            if t_eval is not None:
                last = i == len(edges) - 2
                sel = t_eval[(t_eval >= a) & ((t_eval <= b) if last else (t_eval < b))]
                te = np.unique(np.concatenate([[a], sel, [b]]))
                keep = np.isin(te, sel)
            extra = {}
            if method in ("Radau", "BDF", "LSODA"):
                extra["jac"] = (jac_rotating if frame == "rotating" else jac_fixed)(params, sp)
            sol = solve_ivp(fun, (a, b), y, method=method, t_eval=te, rtol=rtol, atol=atol,
                            max_step=max_step, **extra)
            if sol.status != 0:
                raise RuntimeError(f"solve_ivp({method}) failed: {sol.message}")
            tt, yy, nf = sol.t, sol.y, sol.nfev
            if keep is None:
                keep = np.ones(tt.size, bool)
        else:
            raise ValueError(f"method = {method!r}: must be 'RK4' or one of {SCIPY_METHODS}")
        nfev += nf
        y = yy[:, -1].copy()
        if i < len(edges) - 2:
            keep[-1] = False          # the next segment reports this time (after the jump)
        ts.append(tt[keep])
        ys.append(yy[:, keep])
    wall = time.perf_counter() - tic
    t = np.concatenate(ts)
    Y = np.concatenate(ys, axis=1)
    out = outputs_from_rotating if frame == "rotating" else outputs_from_fixed
    return out(params, t, Y, sp, method=method, nfev=nfev, wall=wall)
