"""Run a scene with its instruments: what they output is on the run, in memory.

Only what the scene asks for is computed: a scene without ``[instruments.*]``
tables renders nothing and samples nothing extra.  The screen camera's
exposure sub-samples are requested from the simulator in the same run
(``simulate(extra_times=...)``); the stroboscope, photo-gate, keyphasor,
tachometer and probes interpolate the recorded samples (cubic Hermite with the
recorded speeds, :mod:`stand.instruments.timing`).  Their output is
``run.instruments`` (:mod:`stand.instruments.outputs`); the recording layer stores it
(:func:`stand.recording.write.write_recording`, ``stand.save``).
"""
from __future__ import annotations

import dataclasses
import json
import math

import numpy as np

from stand.scene.model import Scene, SceneError
from stand.integrate.simulate import simulate
from stand.instruments.outputs import InstrumentOutputs, screen_plans
from stand.scene.placement import with_axis_planes

__all__ = ["run_with_instruments", "settings_dict"]


def settings_dict(settings) -> dict:
    """An instrument's settings (a dataclass or a mapping) as plain JSON values, as the
    recording stores them (non-finite floats as strings)."""
    def plain(v):
        if isinstance(v, np.ndarray):
            return v.tolist()
        if isinstance(v, (np.floating, np.integer)):
            return v.item()
        if isinstance(v, float) and not math.isfinite(v):
            return str(v)
        return v
    d = dataclasses.asdict(settings) if dataclasses.is_dataclass(settings) else dict(settings)
    return json.loads(json.dumps({k: plain(v) for k, v in d.items()}, default=str))


def run_with_instruments(scene: Scene, method: str | None = None, progress: bool = False,
                         checkpoint=None, rtol: float | None = None, atol: float | None = None):
    """Simulate ``scene`` and prepare its instruments.

    Returns
    -------
    Run
        The recording-grid run (``run.extra`` holds the camera's exposure samples when
        there is a screen camera); ``run.instruments`` the instruments' output in memory
        (:class:`stand.instruments.outputs.InstrumentOutputs`, empty without instruments).
    """
    if not scene.instruments:
        return simulate(scene, method=method, progress=progress, checkpoint=checkpoint,
                        rtol=rtol, atol=atol)
    if scene.kind == "book":
        raise SceneError(f"[instruments]: not available on a book weight model (the scene's "
                         f"structure is {scene.structure_type}); write it with [structure] + "
                         "[[weights]] to attach instruments")
    if scene.kind == "rotor":   # the instruments' axis points become planes of the run
        scene = with_axis_planes(scene)
    plans, extra = screen_plans(scene)
    run = simulate(scene, method=method, progress=progress, extra_times=extra, checkpoint=checkpoint,
                   rtol=rtol, atol=atol)
    run.instruments = InstrumentOutputs(scene, run, plans)
    return run
