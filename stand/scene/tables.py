"""Every table of a scene file, each read by one function whatever the scene's form.

The three forms (:mod:`stand.scene.parse`: the planar tables or ``[dimensionless]``;
:mod:`stand.scene.structure_tables`: ``[structure]`` + ``[[weights]]``;
:mod:`stand.scene.book_tables`: ``[weight_model]``) assemble their Scene from these
readers: ``[scene]`` (:func:`scene_header`), ``[run]`` (:func:`run_table`), ``[drive]``
(:func:`drive_table`), ``[[weights]]`` (:func:`weight_tables`), ``[balancer]``,
``[rotor]``, ``[supports]``, ``[initial]``, ``[[perturbation]]``; the instruments are
read by :mod:`stand.scene.instrument_tables`.  Every value goes through the getters of
:mod:`stand.io.validate`, so every message names the key as a dotted path, the value
and the unit.  Units in the file are SI except angles (degrees) and rotor and weight
speeds (rev/s); they are converted here, once.
"""
from __future__ import annotations

import math
from typing import Any, Mapping, Optional

import numpy as np

from stand.io.validate import _Table, _angle, _fmt, _kind, _number, _suggest
from stand.model.balancers.friction import ROLLING_BALL_J, Friction
from stand.scene.body_tables import BODY_TYPES, parse_body
from stand.scene.limits import MAX_SAMPLES, MAX_WEIGHTS
from stand.scene.model import (METHODS, SCENE_LANGUAGE, Balancer, Impulse, InitialState, PlaneWeights, Rotor,
                               RotorTorqueDrive, RunSettings, SceneError, SideForce, SpeedDrive,
                               Supports, TorqueDrive, UnbalanceChange)

__all__ = ["check_tables", "scene_header", "rotor_table", "supports_table", "balancer_table",
           "friction_table",
           "programme_table", "drive_table", "run_table", "initial_table",
           "perturbation_tables", "weight_tables"]

TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0

#: tables of a planar (or ``[dimensionless]``) scene
TABLES = ("scene", "rotor", "supports", "balancer", "drive", "run", "initial", "dimensionless",
          "instruments", "perturbation", "weights")
PERTURBATION_KEYS = {
    "unbalance": ("type", "time", "duration", "eccentricity", "unbalance_angle"),
    "impulse": ("type", "time", "velocity_x", "velocity_y"),
    "side_force": ("type", "start", "end", "force_x", "force_y", "stiffness_x", "stiffness_y"),
}
SCENE_KEYS = ("name", "description", "language")
ROTOR_KEYS = ("mass", "eccentricity", "unbalance_angle", "inertia")
SUPPORT_KEYS = ("stiffness", "stiffness_x", "stiffness_y", "damping", "damping_x", "damping_y")
#: dry-friction keys of the weights' table (:func:`friction_table`,
#: stand.model.balancers.friction): key -> (Friction field, unit, default, strictly positive)
FRICTION_FIELDS = {
    "friction": ("kinetic", "dimensionless, mu_k (balls: rolling resistance)", 0.0, False),
    "static_friction": ("static", "dimensionless, mu_s >= friction", None, False),
    "slip_speed": ("slip_speed", "rad/s", 0.02, True),
    "dwell_time": ("dwell_time", "s", 1.0, True),
    "release_time": ("release_time", "s", 0.01, True),
}
FRICTION_KEYS = tuple(FRICTION_FIELDS)
#: keys of the planar ``[balancer]`` and of a ball/pendulum ``[[weights]]`` table (+ ``plane``)
CONTACT_KEYS = ("ball_radius", "contact_stiffness", "contact_damping", "race_eccentricity",
                "race_eccentricity_angle", "race_out_of_roundness", "race_lobes",
                "race_out_of_roundness_angle")
BALANCER_KEYS = ("type", "count", "mass", "radius", "drag", "inertia",
                 "initial_angles", "initial_speeds") + FRICTION_KEYS + ("rolling",) + CONTACT_KEYS
SPEED_KEYS = ("type", "programme", "programme_dimensionless", "coast_down", "rotor_drag")
TORQUE_KEYS = ("type", "model", "rotor_drag", "initial_speed")
TORQUE_MODEL_KEYS = {
    "constant": ("torque",),
    "speed_feedback": ("c1", "target_speed"),
    "angle_feedback": ("c1", "c2", "target_speed"),
}
RUN_KEYS = ("duration", "sample_rate", "rtol", "atol", "method", "max_steps")
INITIAL_KEYS = ("x", "y", "vx", "vy")
#: ``[run]`` of a book weight model (:mod:`stand.scene.book_tables`)
BOOK_RUN_KEYS = ("duration", "samples", "initial", "rtol", "speed")
#: book weight models written in SI (time in s); the others in tau = omega_0 t
SI_MODELS = ("liquid_float", "liquid_chamber")
#: the keys a ``[structure]`` scene's torque drive does not share with a speed drive
_TORQUE_ONLY = ("model", "torque", "c1", "c2", "target_speed", "rotor_drag", "initial_speed",
                "inertia")


def check_tables(data: Any, valid, form: str = "") -> None:
    """A scene document is a table of tables, each one of ``valid`` (``form`` names the
    scene's form in the messages, e.g. ``"rotor-family"``)."""
    a = f"a {form} scene" if form else "a scene"
    if not isinstance(data, Mapping):
        raise SceneError(f"{a} must be a table of tables, not {_kind(data)}")
    for key in data:
        if key not in valid:
            raise SceneError(f"unknown table [{key}]{f' in {a}' if form else ''}: "
                             f"{_suggest(key, valid)}valid tables: {', '.join(valid)}")


def scene_header(data: Mapping, default_name: str = "") -> tuple:
    """``(name, description)`` from the optional ``[scene]`` table (every form)."""
    if "scene" not in data:
        return default_name, ""
    t = _Table(data["scene"], "scene")
    t.allow(SCENE_KEYS)
    return t.string("name", default=default_name), t.string("description", default="")


def scene_language(data: Mapping, given: Optional[int] = None) -> Optional[int]:
    """The scene language of a document: ``[scene] language`` when the file declares it (the
    key is younger than language 1, so it wins), else ``given`` (a recording's
    ``scene_language`` attribute), else the current language (every bare angle in degrees,
    the rule since issue 39; a recording written before it carries language 1)."""
    scene = data.get("scene") if isinstance(data, Mapping) else None
    if isinstance(scene, Mapping) and "language" in scene:
        return _Table(scene, "scene").integer("language", minimum=1, maximum=SCENE_LANGUAGE)
    if given is not None and given not in (1, SCENE_LANGUAGE):
        raise SceneError(f"scene language {given!r}: this reader knows 1 ([structure] angles "
                         f"in rad) and {SCENE_LANGUAGE} (every angle of a scene file in degrees)")
    return SCENE_LANGUAGE if given is None else given


def rotor_table(t: _Table) -> Rotor:
    """``[rotor]`` of a planar scene (SI; the unbalance angle in degrees or a unit string)."""
    t.allow(ROTOR_KEYS)
    return Rotor(
        mass=t.number("mass", "kg", gt=0),
        eccentricity=t.number("eccentricity", "m", 0.0, ge=0),
        unbalance_angle=_angle(t.name("unbalance_angle"), t.data.get("unbalance_angle", 0.0)),
        inertia=t.number("inertia", "kg*m^2", None, gt=0),
    )


def supports_table(t: _Table) -> Supports:
    """``[supports]``: stiffness and damping per axis, or one value for both."""
    t.allow(SUPPORT_KEYS)
    values = {}
    for what, unit, bounds in (("stiffness", "N/m", {"gt": 0}), ("damping", "N*s/m", {"ge": 0})):
        both = t.number(what, unit, None, **bounds)
        for axis in ("x", "y"):
            key = f"{what}_{axis}"
            if both is not None and key in t:
                raise SceneError(f"{t.name(what)} and {t.name(key)} are both given: use either "
                                 f"{what} (both axes) or {what}_x and {what}_y")
            if both is not None:
                values[key] = both
            elif what == "stiffness" and key not in t:
                raise SceneError(f"{t.name(key)}: missing required key ({unit}); give "
                                 f"stiffness_x and stiffness_y, or stiffness for both axes")
            else:
                values[key] = t.number(key, unit, 0.0, **bounds)
    return Supports(**values)


def balancer_table(t: _Table) -> Balancer:
    """Balls or pendulums: the planar ``[balancer]`` and each ball/pendulum ``[[weights]]``
    (one reader, one meaning).  ``rolling = true`` (balls only): balls rolling without slip,
    inertia 7/5 m l^2 (j = 5/7), of it 2/5 m l^2 on the angle relative to the rotor
    (:attr:`Balancer.spin_inertia`, stand.model.weights).  Their dry friction is :func:`friction_table`."""
    t.allow(BALANCER_KEYS)
    kind = t.string("type", ("balls", "pendulums", "none"))
    if kind == "none":
        t.allow(("type",), lambda k: f"{t.name(k)} = {_fmt(t.data[k])}: not allowed with "
                                     f'{t.name("type")} = "none" (only type is allowed)')
        return Balancer()
    t.allow([k for k in BALANCER_KEYS if kind == "pendulums" or k != "inertia"],
            lambda k: f"{t.name(k)} = {_fmt(t.data[k])}: not allowed for balls (point "
                      f"masses: the inertia about the shaft is m l^2; rolling balls: "
                      f"rolling = true)")
    rolling = t.data.get("rolling", False)
    if not isinstance(rolling, (bool, np.bool_)):
        raise SceneError(f"{t.name('rolling')} = {_fmt(rolling)}: must be true or false (balls "
                         "rolling without slip: inertia 7/5 m l^2, j = 5/7)")
    if rolling and kind != "balls":
        raise SceneError(f"{t.name('rolling')} = true: only for balls ({t.name('type')} = "
                         f'"{kind}"; give a pendulum\'s inertia)')
    for k in CONTACT_KEYS:
        if k in t and kind != "balls":
            raise SceneError(f"{t.name(k)} = {_fmt(t.data[k])}: only for balls (contact, race)")
    r = t.number("ball_radius", "m", 0.0, gt=0)
    if r == 0.0 and any(k in t for k in CONTACT_KEYS[1:3]):
        raise SceneError(f"{t.name('ball_radius')}: missing (m, the balls' own radius): the "
                         f"contact keys need it")
    if r and "contact_stiffness" not in t:
        raise SceneError(f"{t.name('contact_stiffness')}: missing (N/m, the contact's spring; "
                         f"{t.name('ball_radius')} = {_fmt(r)} turns the contact on)")
    contact = dict(ball_radius=r, contact_stiffness=t.number("contact_stiffness", "N/m", 0.0, gt=0),
                   contact_damping=t.number("contact_damping", "N*s/m", 0.0, ge=0),
                   race_eccentricity=t.number("race_eccentricity", "m", 0.0, ge=0),
                   race_eccentricity_angle=_angle(t.name("race_eccentricity_angle"),
                                                  t.data.get("race_eccentricity_angle", 0.0)),
                   **_out_of_roundness(t, bool(rolling)))
    n = t.integer("count", minimum=1, maximum=MAX_WEIGHTS)
    count_key = t.name("count")
    m = t.per_weight("mass", n, count_key, "kg", gt=0)
    l = t.per_weight("radius", n, count_key, "m", gt=0)
    drag_unit = "N*s/m" if kind == "balls" else "N*m*s"
    drag = t.per_weight("drag", n, count_key, drag_unit, 0.0, ge=0)
    with np.errstate(all="ignore"):  # overflow is reported by check_derived
        point = m * l ** 2
    J = point / ROLLING_BALL_J if rolling else point
    if kind == "pendulums":
        J = t.per_weight("inertia", n, count_key, "kg*m^2", None, gt=0)
        if J is None:
            J = point
        for i in np.flatnonzero(J < point * (1.0 - 1e-12)):
            name = t.name("inertia") + (f"[{i}]" if isinstance(t.data["inertia"], list) else "")
            raise SceneError(f"{name} = {_fmt(float(J[i]))}: must be >= m l^2 = "
                             f"{float(point[i]):.6g} (kg*m^2, inertia about the shaft axis; "
                             f"parallel-axis theorem)")
    given = t.data.get("initial_angles")
    if isinstance(given, list) and any(isinstance(a, str) for a in given) and len(given) == n:
        # a unit string per angle ("0.5 rad"), the others in degrees
        angles = np.array([_angle(f"{t.name('initial_angles')}[{i}]", a)
                           for i, a in enumerate(given)])
    else:
        angles = t.per_weight("initial_angles", n, count_key, "deg", None, scalar=False)
        angles = (360.0 * np.arange(n) / n if angles is None else angles) * DEG
    speeds = t.per_weight("initial_speeds", n, count_key, "rev/s", 0.0)
    return Balancer(type=kind, mass=m, radius=l, drag=drag, inertia=np.asarray(J, float),
                    initial_angles=angles, initial_speeds=speeds * TWO_PI, rolling=bool(rolling), **contact)


def _out_of_roundness(t: _Table, rolling: bool) -> dict:
    """The race's out-of-roundness of a ball table: radius l [1 + eps cos k (a - theta_o)]
    (stand.model.rotors.weight_table); point balls with viscous drag (and contact) only."""
    key = "race_out_of_roundness"
    if key not in t:
        for k in ("race_lobes", "race_out_of_roundness_angle"):
            if k in t:
                raise SceneError(f"{t.name(k)} = {_fmt(t.data[k])}: needs {t.name(key)} "
                                 "(dimensionless, the race's relative out-of-roundness eps)")
    eps = t.number(key, "dimensionless, relative out-of-roundness of the race", 0.0, ge=0, lt=0.2)
    if eps > 0:
        other = ([t.name("rolling") + " = true"] if rolling else []) + \
            [t.name(k) for k in FRICTION_KEYS if k in t]
        if other:
            raise SceneError(f"{t.name(key)} = {_fmt(eps)} (dimensionless) with {other[0]}: not "
                             "modelled together (a rolling ball's spin and the friction's normal "
                             "force on an out-of-round race); point balls with viscous drag only")
    return dict(race_out_of_roundness=eps,
                race_lobes=t.integer("race_lobes", minimum=2, default=2),
                race_out_of_roundness_angle=_angle(t.name("race_out_of_roundness_angle"),
                                                   t.data.get("race_out_of_roundness_angle", 0.0)))


def friction_table(t: _Table) -> Optional[Friction]:
    """The dry friction of the weights of a ``[balancer]`` or ball/pendulum ``[[weights]]``
    table (:data:`FRICTION_FIELDS`; :mod:`stand.model.balancers.friction`), None without
    friction keys.  Call it after :func:`balancer_table` (which refuses them with type
    ``"none"``)."""
    if not any(k in t for k in FRICTION_KEYS):
        return None
    kw = {}
    for key, (field, unit, default, positive) in FRICTION_FIELDS.items():
        if key == "static_friction" and key in t:
            mu_k = kw["kinetic"]
            kw[field] = t.number(key, unit, ge=mu_k)
        else:
            kw[field] = t.number(key, unit, default, **({"gt": 0} if positive else {"ge": 0}))
    try:
        return Friction(**kw)
    except ValueError as exc:   # (the checks above are Friction's own)
        raise SceneError(f"{t.path}: {exc}") from None


#: steepest speed change between two programme nodes accepted [rev/s per s]: a step of
#: 1e6 rev/s in a nanosecond (a dimensionless ramp of R 1 in tau 0.03 on a stiff rotor is
#: 1e7); steeper ones (a step in 1e-300 s) overflow the rotor's angular acceleration
#: (a programme of one node is a constant speed)
MAX_PROGRAMME_SLOPE = 1e15


def check_programme_slope(programme: np.ndarray) -> None:
    """Refuse a speed programme (k, 2) [s, rad/s] whose speed changes faster than
    :data:`MAX_PROGRAMME_SLOPE` between two nodes (checked after the run's length, so that
    an absurd speed is named by the run's bounds first)."""
    t, w = programme[:, 0], programme[:, 1] / TWO_PI
    with np.errstate(all="ignore"):
        slope = np.abs(np.diff(w)) / np.diff(t)
    bad = np.nonzero(~(slope <= MAX_PROGRAMME_SLOPE))[0]
    if bad.size:
        i = int(bad[0]) + 1
        raise SceneError(f"drive.programme[{i}] = [{t[i]:g} s, {w[i]:g} rev/s]: the speed changes "
                         f"from {w[i - 1]:g} rev/s at {t[i - 1]:g} s faster than "
                         f"{MAX_PROGRAMME_SLOPE:.0e} rev/s per s; space the times further apart")


def programme_table(t: _Table, key: str, w1: float) -> np.ndarray:
    """[[t, speed], ...] -> ndarray (k, 2) in s and rad/s."""
    name, value = t.name(key), t.data[key]
    dimless = key == "programme_dimensionless"
    units = ("tau = omega_1 t", "R_omega = omega/omega_1") if dimless else ("s", "rev/s")
    if not isinstance(value, (list, tuple)) or not value:
        raise SceneError(f"{name} = {_fmt(value)}: must be a non-empty list of "
                         f"[time ({units[0]}), speed ({units[1]})] pairs")
    rows = []
    for i, pair in enumerate(value):
        if not isinstance(pair, (list, tuple)) or len(pair) != 2:
            raise SceneError(f"{name}[{i}] = {_fmt(pair)}: must be a "
                             f"[time ({units[0]}), speed ({units[1]})] pair")
        time = _number(f"{name}[{i}][0]", pair[0], units[0], ge=0)
        speed = _number(f"{name}[{i}][1]", pair[1], units[1], ge=0)
        if rows and time <= rows[-1][0]:
            raise SceneError(f"{name}[{i}][0] = {_fmt(pair[0])}: times must be strictly "
                             f"increasing ({units[0]}); the previous time is {_fmt(rows[-1][0])}")
        rows.append((time, speed))
    prog = np.array(rows, dtype=float)
    if dimless:
        prog[:, 0] /= w1
        prog[:, 1] *= w1
    else:
        prog[:, 1] *= TWO_PI
    return prog


def drive_table(t: _Table, w1: float, structure: bool = False):
    """``[drive]``: a :class:`SpeedDrive` (programme in s and rev/s, or dimensionless with
    ``w1`` = omega_1 [rad/s]) or a :class:`TorqueDrive` (the book's models 1-3).

    With ``structure`` (a ``[structure]`` scene, no single omega_1): ``type`` defaults to
    ``"speed"``, a speed drive is a plain ``programme``, and a torque drive also takes the
    rotor's polar moment of inertia ``inertia`` (:class:`RotorTorqueDrive`).
    """
    if structure:
        return _structure_drive(t)
    t.allow(SPEED_KEYS + TORQUE_KEYS + ("torque", "c1", "c2", "target_speed"))
    kind = t.string("type", ("speed", "torque"))
    other = "torque" if kind == "speed" else "speed"
    if kind == "speed":
        t.allow(SPEED_KEYS, lambda k: f"{t.name(k)} = {_fmt(t.data[k])}: only valid with "
                                      f'drive.type = "{other}"')
        given = [k for k in ("programme", "programme_dimensionless") if k in t]
        if len(given) != 1:
            raise SceneError(f"{t.name('programme')}: give exactly one of drive.programme "
                             f"[[t (s), speed (rev/s)], ...] and drive.programme_dimensionless "
                             f"[[tau, R_omega], ...] (got {len(given)})")
        start = T = None
        if "coast_down" in t:
            cd = _Table(t.data["coast_down"], t.name("coast_down"))
            cd.allow(("start", "time_constant"))
            start = cd.number("start", "s", gt=0)
            T = cd.number("time_constant", "s", gt=0)
        return SpeedDrive(programme=programme_table(t, given[0], w1), coast_down_start=start,
                          coast_down_time_constant=T,
                          rotor_drag=t.number("rotor_drag", "N*m*s", 0.0, ge=0))
    model = t.string("model", tuple(TORQUE_MODEL_KEYS))
    used = TORQUE_MODEL_KEYS[model]

    def why(k):
        if k in SPEED_KEYS:
            return f'{t.name(k)} = {_fmt(t.data[k])}: only valid with drive.type = "speed"'
        users = [m for m, keys in TORQUE_MODEL_KEYS.items() if k in keys]
        return (f'{t.name(k)} = {_fmt(t.data[k])}: not used by drive.model = "{model}" '
                f"(used by: {', '.join(users)})")

    t.allow(TORQUE_KEYS + used, why)
    get = {
        "torque": lambda: t.number("torque", "N*m"),
        "c1": lambda: t.number("c1", "N*m*s", ge=0),
        "c2": lambda: t.number("c2", "N*m/rad", ge=0),
        "target_speed": lambda: t.number("target_speed", "rev/s", ge=0) * TWO_PI,
    }
    return TorqueDrive(model=model, **{k: get[k]() for k in used},
                       rotor_drag=t.number("rotor_drag", "N*m*s", 0.0, ge=0),
                       initial_speed=t.number("initial_speed", "rev/s", 0.0, ge=0) * TWO_PI)


def run_table(t: _Table, model: Optional[str] = None) -> RunSettings:
    """``[run]``: duration, sample rate, tolerances, method.

    For a book weight model (``model`` its type, :mod:`stand.scene.book_tables`) the
    model's own form: ``duration`` in its time unit (s for the liquids, else
    tau = omega_0 t), ``samples``, ``rtol``, ``speed`` [rad/s] and ``initial`` (checked
    by the model's run); the model's integration is always DOP853 with atol 1e-12.
    """
    if model is not None:
        return _book_run(t, model)
    t.allow(RUN_KEYS)
    run = RunSettings(
        duration=t.number("duration", "s", gt=0),
        sample_rate=t.number("sample_rate", "Hz", gt=0),
        rtol=t.number("rtol", "relative tolerance", 1e-8, gt=0, lt=0.1),
        atol=t.number("atol", "absolute tolerance, dimensionless state", 1e-10, gt=0, lt=1),
        method=t.string("method", METHODS, "auto"),
        max_steps=t.integer("max_steps", 1, 10_000_000),
    )
    samples = run.duration * run.sample_rate
    if samples > MAX_SAMPLES:
        raise SceneError(f"run.duration * run.sample_rate = {run.duration:g} s * "
                         f"{run.sample_rate:g} Hz = {samples:.3g} samples: more than "
                         f"{MAX_SAMPLES:.0e} (memory); shorten run.duration or lower "
                         f"run.sample_rate")
    return run


def initial_table(t: _Table) -> InitialState:
    """``[initial]``: the shaft's initial displacement [m] and velocity [m/s]."""
    t.allow(INITIAL_KEYS)
    units = {"x": "m", "y": "m", "vx": "m/s", "vy": "m/s"}
    return InitialState(**{k: t.number(k, u, 0.0) for k, u in units.items()})


def perturbation_tables(items: Any, rotor: Rotor, duration: float) -> tuple:
    """Parse ``[[perturbation]]`` (tables 4.5-4.6): unbalance change, impulse, side force."""
    if not isinstance(items, list):
        raise SceneError("perturbation: must be an array of tables [[perturbation]], not "
                         f"{_kind(items)}")
    out = []
    for i, item in enumerate(items):
        t = _Table(item, f"perturbation[{i}]")
        kind = t.string("type", tuple(PERTURBATION_KEYS))
        t.allow(PERTURBATION_KEYS[kind], lambda k, kind=kind: (
            f"{t.name(k)}: not a key of a perturbation of type \"{kind}\" (valid: "
            f"{', '.join(PERTURBATION_KEYS[kind])})"))
        if kind == "unbalance":
            start = t.number("time", "s", ge=0)
            out.append(UnbalanceChange(
                start=start, duration=t.number("duration", "s", 0.0, ge=0),
                eccentricity=t.number("eccentricity", "m", rotor.eccentricity, ge=0),
                unbalance_angle=_angle(t.name("unbalance_angle"), t.data["unbalance_angle"])
                if "unbalance_angle" in t else rotor.unbalance_angle))
        elif kind == "impulse":
            out.append(Impulse(start=t.number("time", "s", gt=0),
                               velocity_x=t.number("velocity_x", "m/s", 0.0),
                               velocity_y=t.number("velocity_y", "m/s", 0.0)))
        else:
            start = t.number("start", "s", ge=0)
            end = t.number("end", "s", math.inf, gt=start) if "end" in t else math.inf
            out.append(SideForce(start=start, end=end, force_x=t.number("force_x", "N", 0.0),
                                 force_y=t.number("force_y", "N", 0.0),
                                 stiffness_x=t.number("stiffness_x", "N/m", 0.0, ge=0),
                                 stiffness_y=t.number("stiffness_y", "N/m", 0.0, ge=0)))
        if out[-1].start > duration:
            raise SceneError(f"{t.name('time' if kind != 'side_force' else 'start')} = "
                             f"{out[-1].start:g}: after the end of the run (run.duration = {duration:g} s)")
    return tuple(out)


def _book_run(t: _Table, model: str) -> RunSettings:
    """``[run]`` of a book weight model (:func:`run_table`)."""
    t.allow(BOOK_RUN_KEYS)
    si = model in SI_MODELS
    duration = t.number("duration", "s" if si else "tau = omega_0 t", 10.0 if si else 100.0,
                        gt=0)
    samples = t.integer("samples", minimum=2, default=1001, maximum=10_000_000)
    rtol = t.number("rtol", "relative tolerance", 1e-9, gt=0, lt=1)
    if "speed" in t:
        t.number("speed", "rad/s")
    return RunSettings(duration=float(duration), sample_rate=(samples - 1) / duration,
                       rtol=float(rtol), atol=1e-12, method="DOP853")


def _structure_drive(t: _Table):
    """``[drive]`` of a ``[structure]`` scene (:func:`drive_table`)."""
    if t.string("type", ("speed", "torque"), "speed") == "torque":
        # the planar scenes' torque models (section 5.1.1) plus the rotor's polar moment of
        # inertia about the shaft J_p (stand.model.rotors.coupled_kernel: phi and Omega are states)
        rest = {k: v for k, v in t.data.items() if k != "inertia"}
        inertia = t.number("inertia", "kg*m^2, the rotor's polar moment of inertia about the "
                           "shaft; required with a torque drive", gt=0)
        td = drive_table(_Table(rest, t.path), 1.0)
        return RotorTorqueDrive(**{f: getattr(td, f) for f in _TORQUE_ONLY[:-1]}, inertia=inertia)
    t.allow(("type", "programme"),
            lambda k: f'{t.name(k)}: only valid with drive.type = "torque"'
            if k in _TORQUE_ONLY else None)
    if "programme" not in t:
        raise SceneError(f"{t.name('programme')}: missing required key ([[t (s), speed (rev/s)], ...])")
    return SpeedDrive(programme_table(t, "programme", 1.0))


def weight_tables(items: Any, rotor, kind: str, planar: bool = False) -> tuple:
    """``[[weights]]``: weights in named planes of ``rotor`` (a LinearRotor of type ``kind``).

    Body kinds (:data:`stand.scene.body_tables.BODY_TYPES`) become
    :class:`stand.model.rotors.bodies.PlaneBody`; balls and pendulums (the keys of
    ``[balancer]``: :data:`BALANCER_KEYS`, dry friction and ``rolling`` included) become
    :class:`PlaneWeights`.  On a ``planar`` scene the one plane is ``"balancer"`` and balls
    and pendulums belong in ``[balancer]``.
    """
    if not isinstance(items, list):
        raise SceneError("[weights] must be an array of tables: write [[weights]]")
    out = []
    for i, item in enumerate(items):
        where = f"weights[{i}]"
        if not isinstance(item, Mapping):
            raise SceneError(f"{where}: must be a table")
        item = dict(item)
        plane = item.pop("plane", "balancer")
        if planar and plane != "balancer":
            raise SceneError(f'{where}.plane = {_fmt(plane)}: the planar rotor has one plane, '
                             '"balancer"')
        if not isinstance(plane, str):
            raise SceneError(f"{where}.plane = {_fmt(plane)}: must be a string, one of "
                             f"{', '.join(rotor.planes)}")
        if plane not in rotor.planes:
            raise SceneError(f'{where}.plane = "{plane}": not a plane of rotor type "{kind}"; '
                             f"planes: {', '.join(rotor.planes)}")
        if item.get("type") in BODY_TYPES:
            out.append(parse_body(item, where, plane, rotor))
        elif planar:
            raise SceneError(f"{where}.type = {_fmt(item.get('type'))}: one of "
                             f"{', '.join(BODY_TYPES)} (balls and pendulums go in [balancer])")
        else:
            weights = _plane_weights(item, where, plane)
            if weights.balancer.count:
                out.append(weights)
    return tuple(out)


def _plane_weights(item: dict, where: str, plane: str) -> PlaneWeights:
    """Balls or pendulums of one ``[[weights]]`` table, with their friction (SI): the keys
    and meaning of the planar ``[balancer]`` (:func:`balancer_table`, :func:`friction_table`)."""
    t = _Table(item, where)
    return PlaneWeights(plane, balancer_table(t), friction_table(t))
