"""Classify the motion regime at the end of a simulated run.

Regimes (digest ch5 section 0.1 and ch2_ch3 section 7.2 item 3):

* ``"main"``   -- weights fixed relative to the rotor and the rotor balanced
  (residual unbalance small compared with the capacity, or, beyond capacity,
  the weights together on the light side: "maximally balanced");
* ``"side"``   -- weights fixed relative to the rotor, rotor left unbalanced;
* ``"quasi-periodic"`` -- weights slip relative to the rotor at a steady mean
  speed Omega (stuck balls), close to the natural frequency;
* ``"transient"`` -- none of the above within the window (still settling).

The rule itself is :func:`dsp.regime.motion_regime` (shared with the
windowed classifier of recordings, :func:`dsp.regime.classify_windows`); this
module supplies what only the simulator knows: mean speeds in units of
omega_1 and the residual unbalance against its target (the theory's maximally
balanced motion beyond capacity).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dsp.regime import motion_regime

#: relative spread of the weights' speeds of a stuck group at the end of a
#: simulated run (mean speeds of the samples; stricter than dsp's default for
#: measured windows)
QP_SPREAD_TOL = 1e-3


@dataclass
class Regime:
    """Outcome of :func:`classify`.

    Attributes
    ----------
    name : str
        "main", "side", "quasi-periodic", "transient" or "no weights".
    residual : float
        Final |psi| / S (total unbalance in units of the capacity).
    weight_speed : ndarray
        Mean absolute weight speeds over the window, in units of omega_1.
    rotor_speed : float
        Mean rotor speed over the window, in units of omega_1.
    spread : float
        Largest change of a weight's angle relative to the rotor over the window [rad].
    """

    name: str
    residual: float
    weight_speed: np.ndarray
    rotor_speed: float
    spread: float


def _maximally_balanced_residual(scene, R: float, e0: float) -> float:
    """|psi| of the e0 > 1 main motion at speed R (weights together on the light
    side, lagging by the damping angle of the corrected (5.64)); e0 - 1 when the
    theory does not apply (non-identical weights) or the motion does not exist."""
    from stand.theories.planar.steady import maximally_balanced_motion

    try:
        from stand.scene.dimensionless import dimensionless as _dimless
        p = _dimless(scene)
        m = maximally_balanced_motion(R, e0, p.H_x, p.n, p.e)
    except (ValueError, ArithmeticError):
        m = None
    return abs(m.psi) if m is not None else e0 - 1.0


def classify(traj, window: float = 0.2, sync_tol: float = 1e-3, balance_tol: float = 1e-2) -> Regime:
    """Classify the last ``window`` fraction of a :class:`stand.integrate.simulate.Trajectory`.

    Parameters
    ----------
    window : float
        Fraction of the run (at the end) to examine.
    sync_tol : float
        Weights are synchronous when their mean speed relative to the rotor is
        below ``sync_tol`` times the rotor speed.
    balance_tol : float
        "main" when |psi|/S < balance_tol (within capacity) or when, beyond
        capacity, |psi|/S is within balance_tol of e0 - 1.

    Returns
    -------
    Regime
        The weights are quasi-periodic when they all run slower than the rotor
        with speeds within ``QP_SPREAD_TOL`` x the rotor speed of each other
        (:func:`dsp.regime.motion_regime`).
    """
    sc = traj.scene
    w1 = sc.natural_frequency
    sel = traj.t >= traj.t[0] + (1 - window) * (traj.t[-1] - traj.t[0])
    rotor = float(np.mean(traj.rotor_speed[sel])) / w1
    S = sc.balancer.capacity        # the balls' alone, deliberately: the book's planar ball rule
    if sc.balancer.count == 0 or S == 0:
        return Regime("no weights", float("nan"), np.zeros(0), rotor, 0.0)
    ws = np.mean(traj.weight_speed[sel], axis=0) / w1
    rel = traj.weight_angle[sel] - traj.rotor_angle[sel, None]
    spread = float(np.max(np.ptp(rel, axis=0)))
    psi = float(abs(traj.residual_unbalance()[-1])) / S
    from stand.model.planar import rotor_unbalance

    e0 = float(abs(rotor_unbalance(sc, traj.t[-1:])[0])) / S

    def balanced():
        target = _maximally_balanced_residual(sc, rotor, e0) if e0 > 1 else 0.0
        return abs(psi - target) < balance_tol

    name = motion_regime(rotor, ws - rotor, balanced, sync_tol=sync_tol,
                         spread_tol=QP_SPREAD_TOL)
    return Regime(name, psi, ws, rotor, spread)
