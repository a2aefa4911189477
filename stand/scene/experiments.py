"""Experiment programmes of the monograph's chapter 4 (tables 4.1-4.7) built from a scene.

Each programme takes a base scene (the stand: rotor, supports, balancer,
instruments) and returns a new scene whose drive, duration and perturbations
carry out one experiment; ``stand experiment`` runs it and writes one
recording.  Speeds are in rev/s and times in s at this edge, converted once.

* ``constant``   -- constant speed in a band of table 4.2: "sub" (< 0.9 f0),
  "near" (0.9-1.1 f0), "super" (> 1.1 f0), or a given speed;
* ``run-up``     -- table 4.3: from rest (or a speed) to a speed at a rate, then hold;
* ``run-down``   -- table 4.4: from a speed to rest, linearly in a given time
  (the fixed-point stand coasts from 1800 rpm in 175 +- 3 s) or exponentially;
* ``unbalance``  -- table 4.5: discrete or continuous change of the unbalance at speed;
* ``impact``     -- table 4.6: a blow to the housing (shaft velocity jump) at speed;
* ``pressure``   -- table 4.6: one-directional side pressure (force + stiffness) at speed;
* ``natural-frequency`` -- the photo-gate test: no rotation, release from a deflection.

Orientation changes (gravity direction, table 4.6) need the rotor models with
gravity (the rotor-family issue); the planar vertical-axis model has none.

Body weights (two-axis pendulum, coupled pair, damper, liquids in ``[[weights]]``
of a planar scene), dry friction of the ``[balancer]`` weights and every ``[structure]``
rotor run on the generic kernel, which takes a speed programme
and an initial state but no perturbations: ``constant``, ``run-up``,
``run-down`` (the exponential coast-down as a piecewise-linear programme of
:data:`EXP_NODES` nodes, relative error below 1e-4) and ``natural-frequency``
and ``impact`` (a jump of the scaled state at the blow) run; ``unbalance`` and ``pressure`` are not applicable
(:func:`not_applicable` says why; :func:`programme` raises :class:`NotApplicable`).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from stand.scene.model import (Impulse, InitialState, Scene, SceneError, SideForce, SpeedDrive,
                    UnbalanceChange)

TWO_PI = 2 * math.pi
#: table 4.2 speed bands (fractions of f0) and the speed used in each
BANDS = {"sub": 0.7, "near": 1.0, "super": 1.5}
#: nodes of the piecewise-linear exponential coast-down on the generic kernel (body weights):
#: steps of time/EXP_NODES = tau/40 (tau = time/5), interpolation error < (1/40)^2/8 < 1e-4
EXP_NODES = 200
#: programmes that need a perturbation of the planar kernel, and why they do not apply to
#: a scene with body weights (the generic kernel runs a speed programme and an initial state)
GENERIC_KERNEL_WHY = {
    "unbalance": "an unbalance change at speed (table 4.5) is a perturbation of the planar "
                 "kernel; the generic kernel that runs body weights keeps the rotor's unbalance "
                 "fixed",
    "pressure": "a side pressure (table 4.6) adds a force and a stiffness during the run, a "
                "perturbation of the planar kernel; the generic kernel that runs body weights "
                "has fixed supports",
}


class NotApplicable(ValueError):
    """A programme that does not apply to the scene; the message says why."""


def _f0(scene: Scene) -> float:
    """f0 [Hz]: (5.12) on the planar rotor; the lowest natural frequency of the structure
    with its weights locked otherwise."""
    if scene.kind == "planar":
        return scene.natural_frequency / TWO_PI
    from stand.model.rotors.coupled_kernel import with_locked_weights

    wn = with_locked_weights(scene.linear_rotor(), scene.weights,
                             scene.bodies).natural_frequencies(0.0)
    wn = wn[wn > 0]
    if not wn.size:
        raise SceneError("the structure has no natural frequency at rest (no stiffness): "
                         "give the programme a --speed")
    return float(wn[0]) / TWO_PI


def _positive(name, value, unit):
    if not (value is not None and math.isfinite(value) and value > 0):
        raise SceneError(f"{name} = {value!r}: must be > 0 ({unit})")
    return float(value)


def _with(scene: Scene, programme, duration: float, perturbations=(), initial=None,
          coast=None) -> Scene:
    prog = np.asarray(programme, float)
    prog[:, 1] *= TWO_PI
    drive = SpeedDrive(prog, coast_down_start=None if coast is None else coast[0],
                       coast_down_time_constant=None if coast is None else coast[1])
    run = dataclasses.replace(scene.run, duration=float(duration))
    return dataclasses.replace(scene, drive=drive, run=run,
                               perturbations=tuple(scene.perturbations) + tuple(perturbations),
                               initial=initial or scene.initial)


def constant(scene: Scene, band: str | None = "super", speed: float | None = None,
             duration: float = 60.0, ramp: float = 5.0) -> Scene:
    """Constant speed [rev/s] (table 4.2), reached by a short ramp of ``ramp`` s."""
    if speed is None:
        if band not in BANDS:
            raise SceneError(f"band = {band!r}: must be one of {', '.join(BANDS)} (table 4.2)")
        speed = BANDS[band] * _f0(scene)
    speed = _positive("speed", speed, "rev/s")
    return _with(scene, [[0.0, 0.0], [ramp, speed]], _positive("duration", duration, "s"))


def run_up(scene: Scene, speed: float, rate: float, hold: float = 20.0, start_speed: float = 0.0) -> Scene:
    """Run-up (table 4.3) from ``start_speed`` to ``speed`` [rev/s] at ``rate`` [rev/s^2], then hold."""
    speed = _positive("speed", speed, "rev/s")
    rate = _positive("rate", rate, "rev/s^2")
    t1 = abs(speed - start_speed) / rate
    return _with(scene, [[0.0, start_speed], [t1, speed]], t1 + max(hold, 0.0))


def run_down(scene: Scene, speed: float, time: float = 175.0, exponential: bool = False,
             settle: float = 10.0) -> Scene:
    """Run-down (table 4.4) from ``speed`` [rev/s] after ``settle`` s at that speed.

    Linear to rest in ``time`` s, or exponential with time constant ``time``/5.
    The fixed-point stand coasts from 1800 rpm (30 rev/s) in 175 +- 3 s.
    """
    speed = _positive("speed", speed, "rev/s")
    time = _positive("time", time, "s")
    if exponential and scene.generic_kernel:
        # the generic kernel has no coast-down law: the exponential as a programme
        tk = np.linspace(0.0, time, EXP_NODES + 1)
        rows = [[0.0, speed]] + [[settle + t, speed * math.exp(-5.0 * t / time)] for t in tk]
        return _with(scene, rows, settle + time)
    if exponential:
        return _with(scene, [[0.0, speed]], settle + time, coast=(settle, time / 5.0))
    return _with(scene, [[0.0, speed], [settle, speed], [settle + time, 0.0]], settle + time)


def unbalance(scene: Scene, speed: float, at: float, eccentricity: float, angle_deg: float = 0.0,
              duration: float = 0.0, after: float = 60.0) -> Scene:
    """Unbalance change (table 4.5) at constant ``speed``: discrete (duration 0) or continuous."""
    base = constant(scene, speed=speed, duration=at + duration + after)
    ch = UnbalanceChange(start=at, duration=max(duration, 0.0), eccentricity=eccentricity,
                         unbalance_angle=math.radians(angle_deg))
    return dataclasses.replace(base, perturbations=tuple(base.perturbations) + (ch,))


def impact(scene: Scene, speed: float, at: float, velocity: float, angle_deg: float = 0.0,
           after: float = 30.0) -> Scene:
    """A blow to the housing (table 4.6): the shaft velocity jumps by ``velocity`` [m/s]."""
    base = constant(scene, speed=speed, duration=at + after)
    a = math.radians(angle_deg)
    imp = Impulse(start=_positive("at", at, "s"), velocity_x=velocity * math.cos(a),
                  velocity_y=velocity * math.sin(a))
    return dataclasses.replace(base, perturbations=tuple(base.perturbations) + (imp,))


def pressure(scene: Scene, speed: float, start: float, end: float, force: float,
             stiffness: float = 0.0, angle_deg: float = 0.0, after: float = 30.0) -> Scene:
    """One-directional side pressure (table 4.6): force [N] and extra stiffness [N/m]."""
    if not end > start:
        raise SceneError(f"end = {end!r}: must be > start = {start!r} (s)")
    base = constant(scene, speed=speed, duration=end + after)
    a = math.radians(angle_deg)
    sf = SideForce(start=start, end=end, force_x=force * math.cos(a), force_y=force * math.sin(a),
                   stiffness_x=stiffness * abs(math.cos(a)), stiffness_y=stiffness * abs(math.sin(a)))
    return dataclasses.replace(base, perturbations=tuple(base.perturbations) + (sf,))


def natural_frequency(scene: Scene, deflection: float, periods: float = 5.0) -> Scene:
    """The photo-gate test: not spinning, shaft released from ``deflection`` [m] along x."""
    T = 1.0 / _f0(scene)
    run = dataclasses.replace(scene.run, sample_rate=max(scene.run.sample_rate, 400.0 / T))
    sc = _with(scene, [[0.0, 0.0]], periods * T, initial=InitialState(x=float(deflection)))
    return dataclasses.replace(sc, run=run)


PROGRAMMES = {"constant": constant, "run-up": run_up, "run-down": run_down, "unbalance": unbalance,
              "impact": impact, "pressure": pressure, "natural-frequency": natural_frequency}


#: programme name -> (builder, required options, optional options with their defaults)
PROGRAMMES = {
    "constant": (constant, (), {"band": "super", "speed": None, "duration": 60.0}),
    "run-up": (run_up, ("speed", "rate"), {"hold": 20.0}),
    "run-down": (run_down, ("speed",), {"time": 175.0, "exponential": False}),
    "unbalance": (unbalance, ("speed", "at", "eccentricity"), {"angle_deg": 0.0, "duration": 0.0}),
    "impact": (impact, ("speed", "at", "velocity"), {"angle_deg": 0.0}),
    "pressure": (pressure, ("speed", "start", "end", "force"), {"stiffness": 0.0, "angle_deg": 0.0}),
    "natural-frequency": (natural_frequency, ("deflection",), {}),
}


def not_applicable(scene: Scene, name: str):
    """Why programme ``name`` does not apply to ``scene`` (a sentence), or None when it does.

    The programmes drive the planar rotor of chapter 5; with body weights it runs on
    the generic kernel, which carries out no perturbation (:data:`GENERIC_KERNEL_WHY`).
    """
    if scene.kind == "book":
        return ("a [weight_model] scene is the book's model in its own units; write the stand as "
                "an SI scene with the body weight (data_samples/scenes/body_*.toml) to run the "
                "programmes of tables 4.2-4.6")
    if scene.kind == "rotor" and name in GENERIC_KERNEL_WHY:
        return (f"programme {name} on a {scene.structure_type} rotor: "
                f"{GENERIC_KERNEL_WHY[name].replace('that runs body weights', 'of the rotor family')}")
    if scene.bodies and name in GENERIC_KERNEL_WHY:
        kinds = ", ".join(dict.fromkeys(pb.kind for pb in scene.bodies))
        return (f"programme {name} on a scene with body weights ({kinds}): "
                f"{GENERIC_KERNEL_WHY[name]}")
    if scene.generic_kernel and name in GENERIC_KERNEL_WHY:
        return (f"programme {name} on a scene with {scene.generic_kernel}: "
                f"{GENERIC_KERNEL_WHY[name].replace('that runs body weights', 'that runs them')}")
    return None


def programme(scene: Scene, name: str, **options) -> Scene:
    """The scene of experiment programme ``name`` (:data:`PROGRAMMES`) on the stand ``scene``.

    ``options`` are the builder's arguments by name (None = not given); a missing required
    one raises ValueError naming it.  The planar rotor runs every programme; with body
    weights, and on every ``[structure]`` rotor (the generic kernel), only those without a
    perturbation (:class:`NotApplicable`, a ValueError, otherwise, with the reason:
    :func:`not_applicable`).
    """
    from stand.scene.parse import check_derived

    if name not in PROGRAMMES:
        raise ValueError(f"programme {name!r}: one of {', '.join(PROGRAMMES)}")
    why = not_applicable(scene, name)
    if why:
        raise NotApplicable(why)
    build, required, optional = PROGRAMMES[name]
    missing = [k for k in required if options.get(k) is None]
    if missing:
        raise ValueError(f"programme {name}: {', '.join(missing)} required")
    kw = {k: options[k] for k in required}
    kw.update({k: options[k] if options.get(k) is not None else d for k, d in optional.items()})
    sc = build(scene, **kw)
    if sc.kind == "planar":
        return check_derived(sc)
    from stand.scene.structure_tables import check_cycles

    check_cycles(sc.linear_rotor(), sc.run, sc.drive.programme)
    return sc
