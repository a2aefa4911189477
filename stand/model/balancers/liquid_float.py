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

Runs: the one model (``stand run`` of a ``[weight_model]`` scene,
:mod:`.book_run`).  The paper's own integrators -- ``solve_ivp`` and the fixed-step
Runge-Kutta 4 (the paper's class of method, l. 77) that shows the numerical damping of
the free whirl (digest 1.6 / 5.2 item 4) -- are the test oracle's.

Modules
-------
This module re-exports the parameters (:mod:`.liquid_float_params`) and the model's functions from
:mod:`.liquid_float_motion` (speed laws (6), stationary orbit (5), initial
conditions (7)/(10)), so ``stand.model.balancers.liquid_float.<name>`` keeps working
for them.  The closed-form run-up is in :mod:`.runup_closed_form`.  The model runs on
the one model (planar rotor x liquid float body, :mod:`.composition`); the paper's own
right-hand sides (4)/(9), their integrators (RK4, ``simulate``, outputs (11)) are the
test oracle ``tests/oracles/liquid_float.py``.
"""
from __future__ import annotations

from stand.model.balancers.liquid_float_params import LiquidFloatParams
from stand.model.balancers.liquid_float_motion import (FRAMES, GeneralSpeed, LinearSpeed, StepSpeed, initial_state,
                                                       stationary_amplitude, steady_amplitudes)

__all__ = [
    "LiquidFloatParams", "LinearSpeed", "StepSpeed", "GeneralSpeed",
    "stationary_amplitude", "initial_state", "steady_amplitudes", "FRAMES",
]
