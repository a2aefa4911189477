"""Dry friction of correction weights: Coulomb / rolling resistance with
sticking after a dwell (issue 8 item 5).

A weight j moving relative to the rotor (relative speed alpha_j' [rad/s]) on
its track feels the moment ::

    M_f = mu(t) N_j l_j sat(alpha_j' / v_s),   sat(x) = x / sqrt(1 + x^2)

with N_j = m_j max(l_j psi_j'^2 + e_j . g, 0) the track's normal force (the
centripetal part and gravity; the shaft's own acceleration, of order
omega^2 x deflection, is neglected beside l psi'^2) and ``sat`` a smooth sign
(regularised Coulomb: below the slip speed v_s the moment grows linearly --
a stiff viscous "stick" that approximates static friction).  For balls mu is
the rolling-resistance coefficient (rolling-resistance length / ball radius),
typically 1e-3 ... 5e-3 for steel on steel.

Sticking: the coefficient rises from the kinetic mu_k towards the static mu_s
while the weight rests on the track (|alpha'| < v_s) with time constant
``dwell_time``, and drops back within ``release_time`` once it slides::

    z' = s (1 - z) / dwell_time - (1 - s) z / release_time,   s = exp(-(alpha'/v_s)^2)
    mu = mu_k + (mu_s - mu_k) z

(one extra state per weight, only when mu_s > mu_k).

Consequence for balancing (the "circle shrinking only 5-6 times" of the
experiments): the weights stop where the driving moment m l |a_p . n| of the
shaft's acceleration falls below mu N l; above the critical speed a_p ~
omega^2 r, N ~ m l omega^2, so the residual whirl radius is about mu l (track
radius times the coefficient), against e without the balancer: a reduction
e / (mu l).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Friction", "ROLLING_BALL_J"]

ROLLING_BALL_J = 5.0 / 7.0   #: j of a ball rolling without slip: J = m l^2 / j (digest ch5)


@dataclass(frozen=True)
class Friction:
    """Dry-friction parameters of the weights of one plane.

    Attributes
    ----------
    kinetic : float        mu_k, dimensionless (rolling resistance for balls)
    static : float         mu_s >= mu_k (breakaway after a dwell); default = kinetic (no sticking)
    slip_speed : float     v_s [rad/s], regularisation of the sign
    dwell_time : float     [s], time constant of the rise towards mu_s
    release_time : float   [s], time constant of the drop back to mu_k
    """

    kinetic: float = 0.0
    static: float | None = None
    slip_speed: float = 0.02
    dwell_time: float = 1.0
    release_time: float = 0.01

    def __post_init__(self):
        def chk(name, v, unit, positive=False):
            v = float(v)
            if not math.isfinite(v) or v < 0 or (positive and v == 0):
                raise ValueError(f"friction.{name} = {v!r}: must be {'> 0' if positive else '>= 0'} ({unit})")
            return v
        object.__setattr__(self, "kinetic", chk("kinetic", self.kinetic, "dimensionless"))
        st = self.kinetic if self.static is None else chk("static", self.static, "dimensionless")
        if st < self.kinetic:
            raise ValueError(f"friction.static = {st!r}: must be >= friction.kinetic = {self.kinetic!r}")
        object.__setattr__(self, "static", st)
        object.__setattr__(self, "slip_speed", chk("slip_speed", self.slip_speed, "rad/s", True))
        object.__setattr__(self, "dwell_time", chk("dwell_time", self.dwell_time, "s", True))
        object.__setattr__(self, "release_time", chk("release_time", self.release_time, "s", True))

    @property
    def sticks(self) -> bool:
        return self.static > self.kinetic
