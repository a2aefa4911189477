"""The ``[structure]`` + ``[[weights]]`` form of a scene (any rotor of the family).

:func:`stand.load` reads every scene file form into one :class:`stand.scene.model.Scene`;
a file with a ``[structure]`` table is parsed here into a Scene whose
``structure`` is a :class:`stand.scene.model.RotorStructure` and whose weights sit in
named planes (``plane_weights``)::

    [scene]
    name = "two_mass"
    [structure]
    type = "two_mass"          # one of ROTOR_TYPES
    body_mass = 2.0            # keyword arguments of the type's builder, SI units
    ...
    [[weights]]
    plane = "balancer"         # a plane of the rotor (the builder's docstring lists them)
    type = "balls"             # then the keys of the planar [balancer] table
    count = 2
    mass = 0.01
    radius = 0.05
    drag = 0.5
    friction = 2.5e-3          # optional: Coulomb / rolling resistance (stand.model.balancers.friction)
    static_friction = 0.01     #   breakaway after a dwell (dwell_time, release_time [s])
    slip_speed = 0.02          #   rad/s, regularisation
    rolling = true             # optional: rolling balls, inertia 7/5 m l^2 (j = 5/7)
    [drive]
    type = "speed"
    programme = [[0.0, 0.0], [10.0, 20.0]]   # [s, rev/s]
    [run]
    duration = 30.0
    sample_rate = 200.0

The builder's keyword arguments are taken by name; a value may be a number,
a list of numbers, or a string (for switches); unknown keys are an error that
lists the valid ones.  Units are those of the builder's docstring (SI).
"""
from __future__ import annotations

import inspect
import math
from typing import Mapping

import numpy as np

from stand.model.balancers.friction import ROLLING_BALL_J, Friction
from stand.scene.model import PlaneWeights, RotorStructure, RotorTorqueDrive, Scene, SceneError, SpeedDrive
from stand.scene.body_tables import BODY_TYPES, parse_body
from stand.scene.limits import MAX_CYCLES
from stand.model.rotors.structure import LinearRotor

__all__ = ["ROTOR_TYPES", "parse_family_scene", "build_rotor"]

#: rotor type -> ("module:builder", book section) (stand.model.registry)
ROTOR_TYPES = {
    "planar": ("stand.model.rotors.planar_supports:planar_rotor", "2.5.1"),
    "two_mass": ("stand.model.rotors.two_mass:two_mass", "2.5.2"),
    "grinding": ("stand.model.rotors.grinding:grinding_rotor", "2.5.3"),
    "spherical_hinge": ("stand.model.rotors.fixed_point:spherical_hinge", "2.6.1"),
    "cylindrical_hinge": ("stand.model.rotors.fixed_point:cylindrical_hinge", "2.6.2"),
    "fixed_point_stand": ("stand.model.rotors.fixed_point:fixed_point_stand", "2.6.2, stand of section 4.4"),
    "spatial": ("stand.model.rotors.spatial:spatial_scene_rotor", "2.7.2-2.7.3"),
    "flexible": ("stand.model.rotors.flexible:flexible_shaft", "2.8"),
    "platform": ("stand.model.rotors.platform:platform_rotor", "paper 004"),
}
TABLES = ("scene", "structure", "weights", "drive", "run", "instruments")
#: dry-friction keys of a [[weights]] table (stand.model.balancers.friction)
FRICTION_KEYS = ("friction", "static_friction", "slip_speed", "dwell_time", "release_time")


def _body(item, where, plane, rotor, kind):
    """A body weight (stand.scene.body_tables) in a plane of the rotor."""
    if not isinstance(plane, str) or plane not in rotor.planes:
        raise SceneError(f"{where}.plane = {plane!r}: not a plane of rotor type \"{kind}\"; "
                         f"planes: {', '.join(rotor.planes)}")
    return parse_body(item, where, plane, rotor)


def _builder(kind: str):
    from stand.model.registry import resolve

    return resolve(ROTOR_TYPES, kind, "structure.type", "rotor type")


def build_rotor(kind: str, params: Mapping) -> LinearRotor:
    """Build a LinearRotor of type ``kind`` from keyword parameters (SI)."""
    from stand.scene.parse import _fmt, _kind

    fn = _builder(kind)
    sig = inspect.signature(fn)
    names = [p for p, v in sig.parameters.items()
             if v.kind in (v.POSITIONAL_OR_KEYWORD, v.KEYWORD_ONLY)]
    for k, v in params.items():
        if k not in names:
            raise SceneError(f"structure.{k}: not a parameter of rotor type \"{kind}\"; valid: "
                             f"{', '.join(names)}")
        default, ann = sig.parameters[k].default, sig.parameters[k].annotation
        # a parameter without a default, with a numeric one, or an unannotated / float
        # one defaulting to None, takes a number only (a boolean or a string would be
        # converted silently or fail without naming the key)
        numeric = default is inspect.Parameter.empty or (
            isinstance(default, (int, float)) and not isinstance(default, bool)) or (
            default is None and ann in (inspect.Parameter.empty, "float", "Optional[float]"))
        # e.g. g = (gx, gy): a list of numbers (an empty default may take tables)
        seq = isinstance(default, (tuple, list)) and len(default) > 0 and all(
            isinstance(x, (int, float)) and not isinstance(x, bool) for x in default)
        if (numeric or seq) and (isinstance(v, (bool, str, dict)) or v is None
                                 or (numeric and isinstance(v, list))):
            raise SceneError(f"structure.{k} = {_fmt(v)}: must be "
                             f"{'a list of numbers' if seq else 'a number'} (SI units, see the "
                             f"builder {fn.__module__}.{fn.__name__}), not {_kind(v)}")
        vals = v if isinstance(v, list) else [v]
        for x in vals:
            if isinstance(x, bool) or isinstance(x, str):
                continue
            if isinstance(x, dict):
                continue
            try:
                finite = isinstance(x, (int, float)) and math.isfinite(float(x))
            except OverflowError:
                finite = False
            if not finite:
                raise SceneError(f"structure.{k} = {_fmt(v)}: must be a finite number (SI units, see "
                                 f"the builder {fn.__module__}.{fn.__name__})")
    missing = [p for p, v in sig.parameters.items()
               if v.default is inspect.Parameter.empty and p not in params
               and v.kind in (v.POSITIONAL_OR_KEYWORD, v.KEYWORD_ONLY)]
    if missing:
        raise SceneError(f"[structure] type = \"{kind}\": missing {', '.join(missing)}")
    try:
        rotor = fn(**params)
        wn = rotor.natural_frequencies(0.0)
    except (ValueError, TypeError, np.linalg.LinAlgError) as exc:
        raise SceneError(f"[structure] ({kind}): {exc}") from None
    if not np.all(np.isfinite(wn)):
        raise SceneError(f"[structure] ({kind}): the natural frequencies are out of floating-point "
                         "range: a parameter's magnitude is absurd (check masses, stiffnesses, "
                         "lengths in SI units)")
    return rotor


def _check_cycles(rotor: LinearRotor, run, programme) -> None:
    """Bound the run as the planar scenes are (stand.scene.parse.MAX_CYCLES): periods of the
    fastest natural frequency and rotor revolutions, so that no scene asks for a run
    that never ends (e.g. an absurd stiffness)."""
    wn = rotor.natural_frequencies(0.0)
    fastest = float(np.max(wn)) if wn.size else 0.0
    for label, w in (("periods of the fastest natural frequency "
                      f"({fastest / (2 * math.pi):.3g} Hz)", fastest),
                     ("rotor revolutions", float(np.max(np.abs(programme[:, 1])))
                      if len(programme) else 0.0)):
        cycles = run.duration * w / (2 * math.pi)
        if not cycles <= MAX_CYCLES:
            raise SceneError(f"run.duration = {run.duration:g} s: the run spans {cycles:.3g} "
                             f"{label}, more than {MAX_CYCLES:.0e}; shorten run.duration or "
                             "check the structure's stiffnesses and masses (SI units)")


def parse_family_scene(data: Mapping, text: str = "", stem: str = "") -> Scene:
    """Validate a ``[structure]`` document and build the :class:`Scene` (SI)."""
    from stand.scene.parse import _Table, _balancer, _programme, _run

    if not isinstance(data, Mapping):
        raise SceneError(f"a rotor-family scene must be a table of tables, not {type(data).__name__}")
    for key in data:
        if key not in TABLES:
            raise SceneError(f"unknown table [{key}] in a rotor-family scene; valid: {', '.join(TABLES)}")
    for key in ("structure", "drive", "run"):
        if key not in data:
            raise SceneError(f"missing table [{key}] (required)")
    name, desc = stem, ""
    if "scene" in data:
        sc = _Table(data["scene"], "scene")
        sc.allow(("name", "description"))
        name = sc.string("name", default=stem)
        desc = sc.string("description", default="")
    st = dict(_Table(data["structure"], "structure").data)
    kind = st.pop("type", None)
    if not isinstance(kind, str):
        raise SceneError(f"structure.type = {kind!r}: required, one of {', '.join(ROTOR_TYPES)}")
    rotor = build_rotor(kind, st)
    weights = []
    items = data.get("weights", [])
    if not isinstance(items, list):
        raise SceneError("[weights] must be an array of tables: write [[weights]]")
    for i, item in enumerate(items):
        if not isinstance(item, Mapping):
            raise SceneError(f"weights[{i}]: must be a table")
        item = dict(item)
        plane = item.pop("plane", "balancer")
        if item.get("type") in BODY_TYPES:
            weights.append(_body(item, f"weights[{i}]", plane, rotor, kind))
            continue
        fkeys = {k: item.pop(k) for k in list(item) if k in FRICTION_KEYS}
        rolling = item.pop("rolling", False)
        if not isinstance(rolling, bool):
            raise SceneError(f"weights[{i}].rolling = {rolling!r}: must be true or false (balls "
                             "rolling without slip: inertia 7/5 m l^2, j = 5/7)")
        if not isinstance(plane, str):
            raise SceneError(f"weights[{i}].plane = {plane!r}: must be a string, one of "
                             f"{', '.join(rotor.planes)}")
        if plane not in rotor.planes:
            raise SceneError(f'weights[{i}].plane = "{plane}": not a plane of rotor type "{kind}"; '
                             f"planes: {', '.join(rotor.planes)}")
        bal = _balancer(_Table(item, f"weights[{i}]"))
        if rolling:
            if bal.type != "balls":
                raise SceneError(f"weights[{i}].rolling: only for balls")
            import dataclasses

            bal = dataclasses.replace(bal, inertia=bal.inertia / ROLLING_BALL_J)
        fr = None
        if fkeys:
            from stand.scene.parse import _number

            for k, v in fkeys.items():  # finite numbers (Friction checks the signs)
                fkeys[k] = _number(f"weights[{i}].{k}", v, "see stand.model.balancers.friction")
            try:
                fr = Friction(kinetic=fkeys.get("friction", 0.0),
                              static=fkeys.get("static_friction"),
                              slip_speed=fkeys.get("slip_speed", 0.02),
                              dwell_time=fkeys.get("dwell_time", 1.0),
                              release_time=fkeys.get("release_time", 0.01))
            except ValueError as exc:
                raise SceneError(f"weights[{i}]: {exc}") from None
        if bal.count:
            weights.append(PlaneWeights(plane, bal, fr))
    dt = _Table(data["drive"], "drive")
    if dt.string("type", ("speed", "torque"), "speed") == "torque":
        # the planar scenes' torque models (section 5.1.1) plus the rotor's polar moment of
        # inertia about the shaft J_p (stand.model.rotors.coupled_kernel: phi and Omega are states)
        from stand.scene.parse import _drive

        rest = {k: v for k, v in dt.data.items() if k != "inertia"}
        inertia = dt.number("inertia", "kg*m^2, the rotor's polar moment of inertia about the "
                            "shaft; required with a torque drive", gt=0)
        td = _drive(_Table(rest, "drive"), 1.0)
        drive = RotorTorqueDrive(**{f: getattr(td, f) for f in
                                    ("model", "torque", "c1", "c2", "target_speed",
                                     "rotor_drag", "initial_speed")}, inertia=inertia)
        programme = np.array([[0.0, max(drive.initial_speed, drive.target_speed)]])
    else:
        dt.allow(("type", "programme"),
                 lambda k: f'drive.{k}: only valid with drive.type = "torque"'
                 if k in ("model", "torque", "c1", "c2", "target_speed", "rotor_drag",
                          "initial_speed", "inertia") else None)
        if "programme" not in dt:
            raise SceneError("drive.programme: missing required key ([[t (s), speed (rev/s)], ...])")
        programme = _programme(dt, "programme", 1.0)
        drive = SpeedDrive(programme)
    run = _run(_Table(data["run"], "run"))
    _check_cycles(rotor, run, programme)
    instruments = {}
    if "instruments" in data:   # the planar scenes' parser (plane / axial_position included)
        from stand.scene.parse import _instruments

        instruments = _instruments(_Table(data["instruments"], "instruments"),
                                   tuple(rotor.planes), kind)
    scene = Scene(drive=drive, run=run, name=name, text=text, description=desc,
                  structure=RotorStructure(kind, st, rotor, ROTOR_TYPES[kind][1]),
                  plane_weights=tuple(weights), instruments=instruments)
    if instruments:
        from stand.instruments.placement import check_instruments

        check_instruments(scene)
    return scene
