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
lists the valid ones.  Units are those of the builder's docstring (SI), except
angles: as everywhere in a scene file, **every angle is in degrees**
(``unbalance_angle``, grinding's ``alpha``, the angle of flexible's
``unbalances = { plane = [s, angle] }``; :data:`ANGLE_KEYS`), and a string with
its unit may say otherwise (``unbalance_angle = "0.7 rad"``).  They are
converted to rad here, once (:func:`structure_angles`); the builders stay SI.
Scene texts of scene language 1 (recordings written before this rule) gave
these angles in rad: ``language=1`` reads them so.  A file declares its language with
``[scene] language``; undeclared, it is the current language (degrees).
"""
from __future__ import annotations

import inspect
import math
from typing import Mapping

import numpy as np

from stand.io.validate import _Table, _angle, _fmt, _kind, _number
from stand.model.rotors.structure import LinearRotor
from stand.scene.instrument_tables import instrument_tables
from stand.scene.limits import MAX_CYCLES
from stand.scene.model import SCENE_LANGUAGE, RotorStructure, Scene, SceneError
from stand.scene.tables import (FRICTION_KEYS, check_programme_slope,  # noqa: F401 (re-exported)
                                check_tables, drive_table,
                                run_table, scene_header, weight_tables)

__all__ = ["ROTOR_TYPES", "ANGLE_KEYS", "parse_family_scene", "build_rotor", "check_cycles",
           "structure_angles", "angle_keys"]

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
#: the builders' angle keywords ([rad] in their docstrings), read in degrees from a scene file:
#: key -> rotor types (None: every type whose builder takes it); ``unbalances`` (flexible) is a
#: table {plane = s} or {plane = [s, angle]} whose angles are read so
ANGLE_KEYS = {"unbalance_angle": None, "alpha": ("grinding",), "unbalances": ("flexible",)}


def _structure_angle(name: str, value, language) -> float:
    """One ``[structure]`` angle [rad]: a unit string as it says; a bare number in rad in
    scene language 1 (recordings written before issue 39), in degrees otherwise."""
    return _angle(name, value, "rad" if language == 1 else "deg")


def angle_keys(kind: str, params: Mapping) -> list:
    """The angle keys (:data:`ANGLE_KEYS`) a ``[structure]`` table of type ``kind`` gives (and
    its builder takes)."""
    takes = inspect.signature(_builder(kind)).parameters
    return [k for k, kinds in ANGLE_KEYS.items()
            if k in params and k in takes and (kinds is None or kind in kinds)]


def structure_angles(kind: str, params: Mapping, language: int = SCENE_LANGUAGE) -> dict:
    """The ``[structure]`` keywords with every angle (:data:`ANGLE_KEYS`) converted to rad: a
    number is in degrees (rad in scene language 1), a
    string carries its unit (``"0.7 rad"``,
    ``"40 deg"``; :func:`stand.io.validate.angle`).  Other keys are returned as given."""
    unit = "rad" if language == 1 else "deg"
    out = dict(params)
    for key in angle_keys(kind, params):
        name, v = f"structure.{key}", params[key]
        if key != "unbalances":
            out[key] = _structure_angle(name, v, language)
            continue
        if not isinstance(v, Mapping):
            continue        # the builder's own forms (a list of tuples) are Python-only
        table = {}
        for plane, u in v.items():
            where = f"{name}.{plane}"
            if isinstance(u, list) and len(u) in (1, 2):
                table[plane] = [_number(f"{where}[0]", u[0], "kg m")] + (
                    [_structure_angle(f"{where}[1]", u[1], language)] if len(u) == 2 else [])
            elif isinstance(u, (list, dict, str, bool)) or u is None:
                raise SceneError(f"{where} = {_fmt(u)}: must be s (kg m) or [s (kg m), angle "
                                 f"({unit}, or a string with its unit such as \"0.7 rad\")]")
            else:
                table[plane] = _number(where, u, "kg m")
        out[key] = table
    return out


def _builder(kind: str):
    from stand.model.registry import resolve

    return resolve(ROTOR_TYPES, kind, "structure.type", "rotor type")


def build_rotor(kind: str, params: Mapping) -> LinearRotor:
    """Build a LinearRotor of type ``kind`` from keyword parameters (SI)."""
    fn = _builder(kind)
    unit = f"SI units, see the builder {fn.__module__}.{fn.__name__}"
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
                             f"{'a list of numbers' if seq else 'a number'} ({unit}), not {_kind(v)}")
        for i, x in enumerate(v if isinstance(v, list) else [v]):   # switches pass as given
            if not isinstance(x, (bool, str, dict)):
                _number(f"structure.{k}" + (f"[{i}]" if isinstance(v, list) else ""), x, unit)
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


def check_cycles(rotor: LinearRotor, run, programme) -> None:
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
    check_programme_slope(programme)


def parse_family_scene(data: Mapping, text: str = "", stem: str = "",
                       language: int = SCENE_LANGUAGE) -> Scene:
    """Validate a ``[structure]`` document and build the :class:`Scene` (SI).

    ``language``: the scene language of the text (:data:`stand.scene.model.SCENE_LANGUAGE`;
    1 reads the ``[structure]`` angles of a recording written before the degrees rule in rad).
    """
    check_tables(data, TABLES, "rotor-family")
    for key in ("structure", "drive", "run"):
        if key not in data:
            raise SceneError(f"missing table [{key}] (required)")
    name, desc = scene_header(data, stem)
    st = dict(_Table(data["structure"], "structure").data)
    kind = st.pop("type", None)
    if not isinstance(kind, str):
        raise SceneError(f"structure.type = {kind!r}: required, one of {', '.join(ROTOR_TYPES)}")
    st = structure_angles(kind, st, language)
    if kind == "planar" and "eccentricity" in st:     # the key of [rotor]: s = M e
        e = _number("structure.eccentricity", st.pop("eccentricity"), "m", ge=0)
        if "unbalance" in st:
            raise SceneError("structure.eccentricity and structure.unbalance are both given: use "
                             "either eccentricity (m) or unbalance (kg*m, = mass * eccentricity)")
        m = st.get("mass")
        st["unbalance"] = m * e if isinstance(m, (int, float)) and not isinstance(m, bool) else e
    rotor = build_rotor(kind, st)
    weights = weight_tables(data.get("weights", []), rotor, kind)
    drive = drive_table(_Table(data["drive"], "drive"), 1.0, structure=True)
    if drive.kind == "torque":
        for w in weights:       # the race's kinematics need phi'' known (model.rotors.weight_table)
            for key, unit in (("race_eccentricity", "m"), ("race_out_of_roundness", "dimensionless")):
                if getattr(getattr(w, "balancer", None), key, 0.0) > 0:
                    raise SceneError(f"weights (plane {w.plane}).{key} = {getattr(w.balancer, key):g} "
                                     f'({unit}): with a speed programme only (drive.type = "speed"), '
                                     "not a torque drive")
        programme = np.array([[0.0, max(drive.initial_speed, drive.target_speed)]])
    else:
        programme = drive.programme
    run = run_table(_Table(data["run"], "run"))
    check_cycles(rotor, run, programme)
    instruments = {}
    if "instruments" in data:   # the planar scenes' parser (plane / axial_position included)
        instruments = instrument_tables(_Table(data["instruments"], "instruments"),
                                        tuple(rotor.planes), kind)
    scene = Scene(drive=drive, run=run, name=name, text=text, description=desc,
                  structure=RotorStructure(kind, st, rotor, ROTOR_TYPES[kind][1]),
                  plane_weights=weights, instruments=instruments,
                  language=language or SCENE_LANGUAGE)
    if instruments:
        from stand.scene.placement import check_instruments

        check_instruments(scene)
    return scene
