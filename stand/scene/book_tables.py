"""The ``[weight_model]`` form of a scene: a book weight model with its own rotor.

The weights of chapters 6-7 and the liquid balancers are written in the
books' dimensionless forms (their own rotor models); a scene selects one and
gives its parameters by the names of the module's parameter dataclass::

    [scene]
    name = "abd"
    [weight_model]
    type = "damper"            # two_axis | gravity_pair | damper | liquid_float | liquid_chamber
    R_m = 0.05                 # the dataclass's fields (dimensionless, or SI for the liquids)
    R_omega = 3.0
    [run]                      # optional
    duration = 200.0           # dimensionless time tau = omega_0 t (s for the liquids)
    samples = 2001
    initial = [...]            # optional state vector (stand.model.balancers.book_run.STATE_COLUMNS)
    speed = 30.0               # liquid_chamber: the run's constant speed [rad/s]

:func:`stand.load` builds one :class:`stand.scene.model.Scene` whose ``structure`` is a
:class:`stand.scene.model.BookModel`; ``stand theory`` prints the model's steady
motions (with stability), its quasi-periodic motions or efficiency, or the
closed-form run-up extrema (:func:`model_theory`); ``stand run`` integrates it
(:mod:`stand.model.balancers.book_run`) into the common recording.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from stand.io.jsonable import to_jsonable
from stand.scene.model import BookModel, RunSettings, Scene, SceneError, SpeedDrive

__all__ = ["MODEL_TYPES", "parse_weight_model", "model_theory"]

MODEL_TYPES = {
    "two_axis": ("stand.model.balancers.two_axis:TwoAxisParams", "ch. 6"),
    "gravity_pair": ("stand.model.balancers.gravity_pair:GravityPairParams", "ch. 7.1"),
    "damper": ("stand.model.balancers.damper:DamperParams", "ch. 7.2"),
    "liquid_float": ("stand.model.balancers.liquid_float:LiquidFloatParams", "paper 001"),
    "liquid_chamber": ("stand.model.balancers.liquid_chamber:LiquidChamberParams", "thesis 002"),
}
RUN_KEYS = ("duration", "samples", "initial", "rtol", "speed")
#: the models written in dimensionless ratios, and the largest |ratio| accepted
DIMENSIONLESS_MODELS = ("two_axis", "gravity_pair", "damper")
MAX_RATIO = 1e6
MAX_REVOLUTIONS = 1e8   #: as the planar scenes (stand.scene.parse.MAX_CYCLES)


def _module(kind):
    """(module, parameter class) of a book model."""
    import importlib

    from stand.model.registry import resolve

    cls = resolve(MODEL_TYPES, kind, "weight_model.type", "weight model")
    return importlib.import_module(cls.__module__), cls


def _number(key, v, unit=""):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
        raise SceneError(f"{key} = {v!r}: must be a finite number{f' ({unit})' if unit else ''}")
    return float(v)


def parse_weight_model(data, text="", stem="") -> Scene:
    """Validate a ``[weight_model]`` document and build the :class:`Scene`."""
    for k in data:
        if k not in ("scene", "weight_model", "run"):
            raise SceneError(f"unknown table [{k}] in a weight-model scene; valid: scene, weight_model, run")
    if not isinstance(data.get("weight_model"), dict):
        raise SceneError("missing table [weight_model]")
    wm = dict(data["weight_model"])
    kind = wm.pop("type", None)
    if kind not in MODEL_TYPES:
        raise SceneError(f"weight_model.type = {kind!r}: valid: {', '.join(MODEL_TYPES)}")
    _, cls = _module(kind)
    names = [f.name for f in dataclasses.fields(cls)]
    for k, v in wm.items():
        if k not in names:
            raise SceneError(f"weight_model.{k}: not a parameter of {kind}; valid: {', '.join(names)}")
        _number(f"weight_model.{k}", v)
    try:
        params = cls(**{k: float(v) for k, v in wm.items()})
    except (TypeError, ValueError) as exc:
        raise SceneError(f"[weight_model] ({kind}): {exc}") from None
    if kind in DIMENSIONLESS_MODELS:
        for k, v in wm.items():
            if abs(float(v)) > MAX_RATIO:
                raise SceneError(f"weight_model.{k} = {v!r}: out of the model's range (a dimensionless "
                                 f"ratio, |value| <= {MAX_RATIO:g}: beyond it the model's time scales "
                                 "differ too much for a run to end)")
    run = data.get("run", {})
    if not isinstance(run, dict):
        raise SceneError("[run] must be a table")
    run = dict(run)
    for k in run:
        if k not in RUN_KEYS:
            raise SceneError(f"run.{k}: unknown; valid: {', '.join(RUN_KEYS)}")
    si = kind in ("liquid_float", "liquid_chamber")
    T = _number("run.duration", run.get("duration", 100.0 if not si else 10.0),
                "s" if si else "tau = omega_0 t")
    k = run.get("samples", 1001)
    if isinstance(k, bool) or not isinstance(k, int) or not 2 <= k <= 10_000_000 or not T > 0:
        raise SceneError(f"run.duration = {T!r} (> 0) and run.samples = {k!r} (an integer "
                         "2..1e7) required")
    rtol = _number("run.rtol", run.get("rtol", 1e-9))
    if not 0 < rtol < 1:
        raise SceneError(f"run.rtol = {rtol!r}: must be in (0, 1)")
    if "speed" in run:
        _number("run.speed", run["speed"], "rad/s")
    top = abs(_speed(kind, params, run)) + (2 * abs(params.epsilon) * T if kind == "liquid_float" else 0)
    if T * top / (2 * math.pi) > MAX_REVOLUTIONS:
        raise SceneError(f"run.duration = {T!r}: {T * top / (2 * math.pi):.3g} revolutions at the "
                         f"model's speed; at most {MAX_REVOLUTIONS:g}")
    scene = data.get("scene", {})
    name = scene.get("name", stem) if isinstance(scene, dict) else stem
    desc = scene.get("description", "") if isinstance(scene, dict) else ""
    settings = RunSettings(duration=T, sample_rate=(k - 1) / T, rtol=rtol, atol=1e-12,
                           method="DOP853")
    return Scene(drive=SpeedDrive(np.array([[0.0, _speed(kind, params, run)]])), run=settings,
                 name=str(name), text=text, description=str(desc),
                 structure=BookModel(kind, params, MODEL_TYPES[kind][1], run))


def _speed(kind, p, run) -> float:
    """The model's (initial) spin in its own units (information; the model sets its own)."""
    if kind == "liquid_float":
        return float(p.omega_0)
    if kind == "liquid_chamber":
        return float(run.get("speed", 0.5 * p.critical_speed))
    return float(p.R_omega)


def model_theory(scene: Scene) -> dict:
    """Steady motions (with stability) and the model's characteristic numbers.

    The content is :func:`stand.model.balancers.weight_theory.weight_theory` of the
    scene's model at the scene's speed (the parameters' own speed; for the
    liquid chamber ``run.speed``, default half the critical speed), merged
    under ``scene``, ``type``, ``source`` and ``parameters``.  The earlier keys
    stay: ``quasi_periodic_frequency`` and ``quasi_periodic_family_limit``
    (gravity pair) and ``efficiency`` (damper, (7.54)).
    """
    from stand.model.balancers.weight_theory import weight_theory

    bm = scene.structure
    kind, p = bm.type, bm.params
    speed = _speed(kind, p, bm.options) if kind == "liquid_chamber" else None
    wt = weight_theory(kind, p, speed)
    out = {"scene": scene.name, "type": kind, "source": MODEL_TYPES[kind][1],
           "parameters": to_jsonable(p)}
    out |= {k: v for k, v in wt.items() if k not in ("model", "source", "parameters")}
    if kind == "gravity_pair":
        out["quasi_periodic_frequency"] = wt["quasi_periodic"].get("frequency_Omega")
        out["quasi_periodic_family_limit"] = wt["quasi_periodic"].get("family_limit_R_omega")
    elif kind == "damper":
        out["efficiency"] = wt["balancing_efficiency"].get("value")
    return out
