"""Influence-coefficient balancing from recordings (issue 17, part 3).

The field balancer's procedure on the stand's recordings: a reference run and
one trial-weight run per correction plane, each at the same steady speed with
the rotor angle (keyphasor) and the displacements of the measurement planes
recorded.  The 1X phasor of every measurement plane in every run comes from
:func:`dsp.unbalance.synchronous_component` over the steady part of the run;
:func:`dsp.influence.influence_balance` turns them into the influence matrix,
the correction unbalances and the correction masses and angles.

    >>> import stand
    >>> from stand.analysis.influence import influence_from_recordings, TrialWeight
    >>> res = influence_from_recordings(
    ...     "ref.h5", ["trial1.h5", "trial2.h5"],
    ...     [TrialWeight("balancer1", 10.0, 0.0, 100.0), TrialWeight("balancer2", 10.0, 90.0, 100.0)],
    ...     sensors=["probe1", "probe2"])                                     # doctest: +SKIP
    >>> res.to_frame()                                                        # doctest: +SKIP

:func:`model_correction` gives the exact correction of a simulated rotor (the
negated unbalance of each correction plane) to compare with.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from dsp.influence import influence_balance
from dsp.unbalance import synchronous_component

__all__ = ["TrialWeight", "parse_trial", "steady_window", "run_phasors",
           "influence_from_recordings", "model_correction"]


@dataclass(frozen=True)
class TrialWeight:
    """A trial weight: ``mass_g`` [g] at ``angle_deg`` [deg] from the reference
    mark (direction of rotation) on radius ``radius_mm`` [mm] in ``plane``."""

    plane: str
    mass_g: float
    angle_deg: float
    radius_mm: float

    @property
    def unbalance_kg_m(self) -> complex:
        """m r e^{i angle} [kg m]."""
        return (self.mass_g * 1e-3 * self.radius_mm * 1e-3
                * complex(math.cos(math.radians(self.angle_deg)),
                          math.sin(math.radians(self.angle_deg))))


def parse_trial(text: str) -> TrialWeight:
    """``"plane:mass_g:angle_deg:radius_mm"`` -> :class:`TrialWeight`."""
    parts = str(text).split(":")
    if len(parts) != 4:
        raise ValueError(f"--trial {text!r}: expected plane:mass_g:angle_deg:radius_mm")
    try:
        m, a, r = (float(p) for p in parts[1:])
    except ValueError:
        raise ValueError(f"--trial {text!r}: mass, angle and radius must be numbers "
                         "(plane:mass_g:angle_deg:radius_mm)") from None
    if not (math.isfinite(m) and m > 0 and math.isfinite(r) and r > 0 and math.isfinite(a)):
        raise ValueError(f"--trial {text!r}: mass and radius must be positive, the angle finite")
    return TrialWeight(parts[0], m, a, r)


def _load(run, what):
    if isinstance(run, (str, os.PathLike)):
        from stand.recording.hdf5 import read_recording as read

        name = f"{os.fspath(run)!r}"
        return read(run), what if name in what else f"{what} {name}"
    return run, what


def steady_window(run, rtol: float = 1e-3, settle: float = 0.5):
    """Sample mask of the steady part of a run: the last stretch whose speed is
    within ``rtol`` of the final speed, without its first ``settle`` fraction
    (the free vibration of the run-up decays there)."""
    w = np.asarray(run.rotor_speed, dtype=float)
    t = np.asarray(run.t, dtype=float)
    ok = np.abs(w - w[-1]) <= rtol * max(abs(w[-1]), 1e-12)
    if not ok[-1] or w[-1] <= 0:
        raise ValueError("the run does not end at a steady positive speed")
    i0 = len(ok) - int(np.argmin(ok[::-1])) if not ok.all() else 0
    t0 = t[i0] + settle * (t[-1] - t[i0])
    return t >= t0


def run_phasors(run, sensors: Sequence[str], *, t_start: Optional[float] = None,
                name: str = "run") -> list:
    """The 1X :class:`~dsp.unbalance.SynchronousComponent` of each sensor plane
    over the steady part of ``run`` (or from ``t_start`` [s] on)."""
    run, name = _load(run, name)
    for s in sensors:
        if s not in run.planes:
            raise ValueError(f"{name}: no plane {s!r}; its planes: {', '.join(run.planes)}")
    t = np.asarray(run.t, dtype=float)
    try:
        sel = steady_window(run) if t_start is None else t >= float(t_start)
    except ValueError as exc:
        raise ValueError(f"{name}: {exc}") from None
    out = []
    for s in sensors:
        xy = np.asarray(run.planes[s], dtype=float)
        try:
            out.append(synchronous_component(t[sel], xy[sel, 0], xy[sel, 1],
                                             rotor_angle=np.asarray(run.rotor_angle)[sel]))
        except ValueError as exc:
            raise ValueError(f"{name}, plane {s!r}: {exc}") from None
    return out


def influence_from_recordings(reference, trials: Sequence, trial_weights: Sequence,
                              sensors: Sequence[str], *, radii_mm=None,
                              t_start: Optional[float] = None,
                              speed_rtol: float = 0.01):
    """Correction masses and angles from a reference run and one trial run per plane.

    Parameters
    ----------
    reference : path or Run
        The run without trial weights.
    trials : sequence of path or Run
        ``trials[j]``: the run with ``trial_weights[j]`` added (one per plane).
    trial_weights : sequence of TrialWeight or "plane:mass_g:angle_deg:radius_mm"
    sensors : sequence of str
        Measurement planes of the recordings (at least as many as trial runs).
    radii_mm : sequence of float, optional
        Correction radii [mm] (default: the trial weights' radii).
    t_start : float, optional
        Analyse from this time [s] on (default: the second half of each run's
        final steady-speed stretch).
    speed_rtol : float
        Largest relative speed difference of a trial run from the reference.

    Returns
    -------
    stand.analysis.results.Influence
        The :class:`dsp.influence.InfluenceBalance` as a result object: masses in g
        (``mass_g``), angles in deg from the reference mark (``angle_deg``), with
        uncertainties from the phasors' scatter; ``to_dict()`` (``stand influence --json``),
        ``to_frame()``, ``plot(ax=)``.
    """
    from stand.analysis.results import Influence

    tw = [w if isinstance(w, TrialWeight) else parse_trial(w) for w in trial_weights]
    trials = list(trials)
    if len(trials) != len(tw):
        raise ValueError(f"{len(trials)} trial run(s) for {len(tw)} trial weight(s): give one "
                         "trial run per correction plane, in the order of the trial weights")
    planes = [w.plane for w in tw]
    if len(set(planes)) != len(planes):
        raise ValueError(f"trial weights: planes {planes} repeat; one trial run per plane")
    sensors = list(sensors)
    names = [f"reference run {os.fspath(reference)!r}" if isinstance(reference, (str, os.PathLike))
             else "reference run"]
    names += [f"trial run {j + 1} {os.fspath(r)!r} (plane {p})"
              if isinstance(r, (str, os.PathLike)) else f"trial run {j + 1} (plane {p})"
              for j, (r, p) in enumerate(zip(trials, planes))]
    comps = [run_phasors(r, sensors, t_start=t_start, name=n)
             for r, n in zip([reference] + trials, names)]
    V0 = np.array([c.vector_m for c in comps[0]])
    V = np.array([[c.vector_m for c in cs] for cs in comps[1:]])
    s0 = np.array([c.vector_std_m for c in comps[0]])
    sV = np.array([[c.vector_std_m for c in cs] for cs in comps[1:]])
    speeds = [float(np.mean([c.speed_rad_s for c in cs])) for cs in comps]
    r = [w.radius_mm for w in tw] if radii_mm is None else list(radii_mm)
    return Influence(influence_balance(V0, V, [w.unbalance_kg_m for w in tw],
                                       np.asarray(r, dtype=float) * 1e-3, reference_std=s0,
                                       trials_std=sV, speeds=speeds, speed_rtol=speed_rtol,
                                       planes=planes, sensors=sensors, runs=names))


def model_correction(scene, planes: Sequence[str]) -> np.ndarray:
    """Exact correction unbalances [kg m] (complex, angle from the reference
    mark) of a simulated rotor: minus the sum of its unbalances in each plane.

    ``scene``: a Scene, a scene file, a Run or a recording (its scene)."""
    from stand.scene.model import Scene

    if isinstance(scene, (str, os.PathLike)):
        p = os.fspath(scene)
        if p.endswith((".h5", ".hdf5")):
            from stand.recording.hdf5 import read_recording as read

            scene = read(p).scene
        else:
            from stand.scene.parse import load_scene as load

            scene = load(p)
    elif not isinstance(scene, Scene):
        scene = scene.scene
    rotor = getattr(getattr(scene, "structure", None), "rotor", None)
    if rotor is None or not hasattr(rotor, "unbalances"):
        raise ValueError("model_correction: the scene has no rotor structure with listed "
                         "unbalances (a [structure] family scene)")
    out = np.zeros(len(planes), dtype=complex)
    for j, p in enumerate(planes):
        if p not in rotor.planes:
            raise ValueError(f"model_correction: no plane {p!r}; planes: {', '.join(rotor.planes)}")
        out[j] = -sum(u.s * complex(math.cos(u.angle), math.sin(u.angle))
                      for u in rotor.unbalances if u.plane == p)
    return out
