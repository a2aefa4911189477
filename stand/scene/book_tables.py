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
    initial = [...]            # optional state vector (stand.integrate.book_run.STATE_COLUMNS)
    speed = 30.0               # liquid_chamber: the run's constant speed [rad/s]

:func:`stand.load` builds one :class:`stand.scene.model.Scene` whose ``structure`` is a
:class:`stand.scene.model.BookModel`; ``stand theory`` prints the model's steady
motions (with stability), its quasi-periodic motions or efficiency, or the
closed-form run-up extrema (:func:`stand.theories.scene.model_theory`); ``stand run`` integrates it
(:mod:`stand.integrate.book_run`) into the common recording.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from stand.io.validate import _Table, _fmt, _number
from stand.scene.limits import MAX_CYCLES
from stand.scene.model import BookModel, Scene, SceneError, SpeedDrive
from stand.scene.tables import BOOK_RUN_KEYS, SI_MODELS, check_tables, run_table, scene_header

__all__ = ["MODEL_TYPES", "parse_weight_model"]

MODEL_TYPES = {
    "two_axis": ("stand.model.balancers.two_axis:TwoAxisParams", "ch. 6"),
    "gravity_pair": ("stand.model.balancers.gravity_pair:GravityPairParams", "ch. 7.1"),
    "damper": ("stand.model.balancers.damper:DamperParams", "ch. 7.2"),
    "liquid_float": ("stand.model.balancers.liquid_float:LiquidFloatParams", "paper 001"),
    "liquid_chamber": ("stand.model.balancers.liquid_chamber:LiquidChamberParams", "thesis 002"),
}
RUN_KEYS = BOOK_RUN_KEYS
TABLES = ("scene", "weight_model", "run")
#: the models written in dimensionless ratios, and the largest |ratio| accepted
DIMENSIONLESS_MODELS = tuple(k for k in MODEL_TYPES if k not in SI_MODELS)
MAX_RATIO = 1e6
MAX_REVOLUTIONS = MAX_CYCLES   #: as the planar scenes


def _module(kind):
    """(module, parameter class) of a book model."""
    import importlib

    from stand.model.registry import resolve

    cls = resolve(MODEL_TYPES, kind, "weight_model.type", "weight model")
    return importlib.import_module(cls.__module__), cls


def parse_weight_model(data, text="", stem="") -> Scene:
    """Validate a ``[weight_model]`` document and build the :class:`Scene`."""
    check_tables(data, TABLES, "weight-model")
    if "weight_model" not in data:
        raise SceneError("missing table [weight_model]")
    wm = dict(_Table(data["weight_model"], "weight_model").data)
    kind = wm.pop("type", None)
    if kind not in MODEL_TYPES:
        raise SceneError(f"weight_model.type = {_fmt(kind)}: valid: {', '.join(MODEL_TYPES)}")
    _, cls = _module(kind)
    names = [f.name for f in dataclasses.fields(cls)]
    unit = ("dimensionless" if kind in DIMENSIONLESS_MODELS
            else f"SI units, see {cls.__module__}.{cls.__name__}")
    for k, v in wm.items():
        if k not in names:
            raise SceneError(f"weight_model.{k}: not a parameter of {kind}; valid: {', '.join(names)}")
        wm[k] = _number(f"weight_model.{k}", v, unit)
    try:
        params = cls(**wm)
    except (TypeError, ValueError) as exc:
        raise SceneError(f"[weight_model] ({kind}): {exc}") from None
    if kind in DIMENSIONLESS_MODELS:
        for k, v in wm.items():
            if abs(v) > MAX_RATIO:
                raise SceneError(f"weight_model.{k} = {_fmt(data['weight_model'][k])}: out of the "
                                 f"model's range (a dimensionless ratio, |value| <= {MAX_RATIO:g}: "
                                 "beyond it the model's time scales differ too much for a run to end)")
    rt = _Table(data.get("run", {}), "run")
    settings = run_table(rt, kind)
    run = dict(rt.data)
    T = settings.duration
    top = abs(_speed(kind, params, run)) + (2 * abs(params.epsilon) * T if kind == "liquid_float" else 0)
    if T * top / (2 * math.pi) > MAX_REVOLUTIONS:
        raise SceneError(f"run.duration = {T!r}: {T * top / (2 * math.pi):.3g} revolutions at the "
                         f"model's speed; at most {MAX_REVOLUTIONS:g}")
    name, desc = scene_header(data, stem)
    return Scene(drive=SpeedDrive(np.array([[0.0, _speed(kind, params, run)]])), run=settings,
                 name=name, text=text, description=desc,
                 structure=BookModel(kind, params, MODEL_TYPES[kind][1], run))


def _speed(kind, p, run) -> float:
    """The model's (initial) spin in its own units (information; the model sets its own)."""
    if kind == "liquid_float":
        return float(p.omega_0)
    if kind == "liquid_chamber":
        return float(run.get("speed", 0.5 * p.critical_speed))
    return float(p.R_omega)
