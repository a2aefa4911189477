"""Theory against simulation: run the simulator on both sides of each predicted threshold.

For every critical speed of :func:`stand.theories.planar.speedmap.scene_theory` the
scene is simulated at constant speeds a little below and a little above it
(after a gentle run-up from rest, like the stand's own experiments), the final
regime is classified (:func:`stand.analysis.regime.classify`), and compared with the
motions the theory predicts to be stable there (a test helper: tests/test_theory_scene.py).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from stand.analysis.regime import classify
from stand.scene.model import Scene, SpeedDrive
from stand.integrate.simulate import simulate
from stand.theories.planar.speedmap import SceneTheory, scene_theory


@dataclass
class ThresholdCheck:
    """One simulated point beside a threshold."""

    threshold_R: float
    threshold_motion: str
    side: str            #: "below" or "above"
    R: float             #: simulated speed, units of omega_1
    predicted: list      #: motions stable at R according to the theory
    observed: str        #: regime at the end of the run
    residual: float      #: final |psi| / S
    match: bool


def _regime_family(label: str) -> str:
    if label.startswith("side"):
        return "side"
    if label.startswith("main"):
        return "main"
    return label


def at_speed(scene: Scene, R: float, ramp_tau: float = 300.0, hold_tau: float = 1200.0,
             sample_rate_per_tau: float = 0.5) -> Scene:
    """The scene run up linearly from rest to speed ``R`` (units of omega_1) and held."""
    w1 = scene.natural_frequency
    drive = SpeedDrive(np.array([[0.0, 0.0], [ramp_tau / w1, R * w1]]))
    run = dataclasses.replace(scene.run, duration=(ramp_tau + hold_tau) / w1,
                              sample_rate=sample_rate_per_tau * w1)
    return dataclasses.replace(scene, drive=drive, run=run)


def check_thresholds(scene: Scene, theory: SceneTheory | None = None, margin: float = 0.15,
                     hold_tau: float = 1200.0) -> list:
    """Simulate at ``R_c (1 -+ margin)`` for each critical speed R_c.

    Returns
    -------
    list of ThresholdCheck
        ``match`` is True when the observed regime is one of the predicted
        stable motions, or when it is "transient" and nothing is predicted
        stable (the simulation cannot settle).
    """
    th = theory or scene_theory(scene)
    out = []
    for c in th.critical_speeds:
        for side, R in (("below", c.R * (1 - margin)), ("above", c.R * (1 + margin))):
            pred = next((b.motions for b in th.bands if b.R_from <= R <= b.R_to), [])
            tr = simulate(at_speed(scene, R, hold_tau=hold_tau))
            reg = classify(tr)
            fam = {_regime_family(m) for m in pred}
            ok = reg.name in fam or (reg.name == "transient" and not fam)
            out.append(ThresholdCheck(c.R, c.motion, side, R, list(pred), reg.name, reg.residual, ok))
    return out
