"""Scene files: TOML in, one validated :class:`stand.scene.model.Scene` out (:func:`load`).

Three file forms build the same Scene: the planar tables (``[rotor]``,
``[supports]``, ``[balancer]``) or the book's ``[dimensionless]`` form (this
module), ``[structure]`` + ``[[weights]]`` (:mod:`stand.scene.structure_tables`) and
``[weight_model]`` (:mod:`stand.scene.book_tables`).

The schema is documented field by field in ``docs/scene.md``.  Every problem
raises :class:`stand.scene.model.SceneError` with one message that names the key as
a dotted path, the offending value and the expected unit, e.g.
``balancer.mass = -0.045: must be > 0 (kg)``.  No key is ignored silently.

Units in the file are SI except: angles in degrees, rotor and weight speeds in
rev/s.  They are converted here, once (to rad and rad/s).
"""
from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any, Mapping, Union

import numpy as np


from stand.scene.dimensionless import (DIMENSIONLESS_KEYS, _dimensionless_params,  # noqa: F401
                            scene_from_dimensionless)
from stand.io.validate import _Table, _fmt, _kind, _number, _suggest  # noqa: F401 (re-exported)
from stand.scene.limits import (MAX_CYCLES, MAX_IMAGE_PIXELS, MAX_SAMPLES,  # noqa: F401 (re-exported)
                                 MAX_STATE_BYTES, MAX_WEIGHTS)
from stand.scene.model import (
    METHODS,
    Impulse,
    SideForce,
    UnbalanceChange,
    Balancer,
    InitialState,
    Rotor,
    RunSettings,
    Scene,
    SceneError,
    SpeedDrive,
    Supports,
    TorqueDrive,
)

__all__ = ["load", "load_scene", "parse", "parse_scene", "scene_from_dimensionless", "MAX_SAMPLES"]

TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0

TABLES = ("scene", "rotor", "supports", "balancer", "drive", "run", "initial", "dimensionless",
          "instruments", "perturbation", "weights")
PERTURBATION_KEYS = {
    "unbalance": ("type", "time", "duration", "eccentricity", "unbalance_angle"),
    "impulse": ("type", "time", "velocity_x", "velocity_y"),
    "side_force": ("type", "start", "end", "force_x", "force_y", "stiffness_x", "stiffness_y"),
}
#: [instruments.<name>] -> ("module:settings class" with ``from_table``, section) (stand.model.registry)
INSTRUMENTS = dict(
    screen=("stand.instruments.screen:ScreenCamera", "4.3.2"),
    stroboscope=("stand.instruments.stroboscope:Stroboscope", "4.3"),
    photogate=("stand.instruments.photogate:PhotoGate", "4.3, FPM-09"),
    keyphasor=("stand.instruments.probes:Keyphasor", ""),
    tachometer=("stand.instruments.probes:Tachometer", ""),
    probes=("stand.instruments.probes:DisplacementProbes", ""),
)
SCENE_KEYS = ("name", "description")
ROTOR_KEYS = ("mass", "eccentricity", "unbalance_angle", "inertia")
SUPPORT_KEYS = ("stiffness", "stiffness_x", "stiffness_y", "damping", "damping_x", "damping_y")
BALANCER_KEYS = ("type", "count", "mass", "radius", "drag", "inertia",
                 "initial_angles", "initial_speeds")
SPEED_KEYS = ("type", "programme", "programme_dimensionless", "coast_down", "rotor_drag")
TORQUE_KEYS = ("type", "model", "rotor_drag", "initial_speed")
TORQUE_MODEL_KEYS = {
    "constant": ("torque",),
    "speed_feedback": ("c1", "target_speed"),
    "angle_feedback": ("c1", "c2", "target_speed"),
}
RUN_KEYS = ("duration", "sample_rate", "rtol", "atol", "method", "max_steps")
INITIAL_KEYS = ("x", "y", "vx", "vy")



def _rotor(t: _Table) -> Rotor:
    t.allow(ROTOR_KEYS)
    return Rotor(
        mass=t.number("mass", "kg", gt=0),
        eccentricity=t.number("eccentricity", "m", 0.0, ge=0),
        unbalance_angle=t.number("unbalance_angle", "deg", 0.0) * DEG,
        inertia=t.number("inertia", "kg*m^2", None, gt=0),
    )


def _supports(t: _Table) -> Supports:
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


def _balancer(t: _Table) -> Balancer:
    t.allow(BALANCER_KEYS)
    kind = t.string("type", ("balls", "pendulums", "none"))
    if kind == "none":
        t.allow(("type",), lambda k: f"{t.name(k)} = {_fmt(t.data[k])}: not allowed with "
                                     f'balancer.type = "none" (only type is allowed)')
        return Balancer()
    t.allow([k for k in BALANCER_KEYS if kind == "pendulums" or k != "inertia"],
            lambda k: f"{t.name(k)} = {_fmt(t.data[k])}: not allowed for balls (point "
                      f"masses: the inertia about the shaft is m l^2)")
    n = t.integer("count", minimum=1, maximum=MAX_WEIGHTS)
    count_key = t.name("count")
    m = t.per_weight("mass", n, count_key, "kg", gt=0)
    l = t.per_weight("radius", n, count_key, "m", gt=0)
    drag_unit = "N*s/m" if kind == "balls" else "N*m*s"
    drag = t.per_weight("drag", n, count_key, drag_unit, 0.0, ge=0)
    with np.errstate(all="ignore"):  # overflow is reported by check_derived
        point = m * l ** 2
    J = point
    if kind == "pendulums":
        J = t.per_weight("inertia", n, count_key, "kg*m^2", None, gt=0)
        if J is None:
            J = point
        for i in np.flatnonzero(J < point * (1.0 - 1e-12)):
            name = t.name("inertia") + (f"[{i}]" if isinstance(t.data["inertia"], list) else "")
            raise SceneError(f"{name} = {_fmt(float(J[i]))}: must be >= m l^2 = "
                             f"{float(point[i]):.6g} (kg*m^2, inertia about the shaft axis; "
                             f"parallel-axis theorem)")
    angles = t.per_weight("initial_angles", n, count_key, "deg", None, scalar=False)
    if angles is None:
        angles = 360.0 * np.arange(n) / n
    speeds = t.per_weight("initial_speeds", n, count_key, "rev/s", 0.0)
    return Balancer(type=kind, mass=m, radius=l, drag=drag, inertia=np.asarray(J, float),
                    initial_angles=angles * DEG, initial_speeds=speeds * TWO_PI)


def _programme(t: _Table, key: str, w1: float) -> np.ndarray:
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


def _drive(t: _Table, w1: float):
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
        return SpeedDrive(programme=_programme(t, given[0], w1), coast_down_start=start,
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


def _run(t: _Table) -> RunSettings:
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


def _initial(t: _Table) -> InitialState:
    t.allow(INITIAL_KEYS)
    units = {"x": "m", "y": "m", "vx": "m/s", "vy": "m/s"}
    return InitialState(**{k: t.number(k, u, 0.0) for k, u in units.items()})


def parse_scene(data: Mapping, text: str = "") -> Scene:
    """Validate a parsed TOML document and build the :class:`Scene`.

    Parameters
    ----------
    data : mapping
        As returned by ``tomllib.loads``.
    text : str
        Original TOML text, stored in ``Scene.text``.

    Raises
    ------
    SceneError
        One message naming the offending key, its value and the expected unit.
    """
    if not isinstance(data, Mapping):
        raise SceneError(f"a scene must be a table of tables, not {_kind(data)}")
    for key in data:
        if key not in TABLES:
            raise SceneError(f"unknown table [{key}]: {_suggest(key, TABLES)}"
                             f"valid tables: {', '.join(TABLES)}")
    tables = {key: _Table(value, key) for key, value in data.items()
              if key not in ("perturbation", "weights")}
    physical = [k for k in ("rotor", "supports", "balancer") if k in tables]
    if "dimensionless" in tables and physical:
        raise SceneError(f"[dimensionless] cannot be combined with [{physical[0]}]: a "
                         f"[dimensionless] scene defines rotor, supports and balancer itself")
    for key in ("drive", "run") + (() if "dimensionless" in tables else ("rotor", "supports")):
        if key not in tables:
            raise SceneError(f"missing table [{key}] (required)")

    name = desc = ""
    if "scene" in tables:
        tables["scene"].allow(SCENE_KEYS)
        name = tables["scene"].string("name", default="")
        desc = tables["scene"].string("description", default="")
    run = _run(tables["run"])
    initial = _initial(tables["initial"]) if "initial" in tables else InitialState()
    instruments = _instruments(tables["instruments"]) if "instruments" in tables else {}

    if "dimensionless" in tables:
        p = _dimensionless_params(tables["dimensionless"], "deg")
        p["unbalance_angle"] *= DEG
        if p["initial_angles"] is not None:
            p["initial_angles"] = p["initial_angles"] * DEG
        drive = _drive(tables["drive"], TWO_PI * p["natural_frequency"])
        sc = scene_from_dimensionless(**p, drive=drive, run=run, initial=initial)
        perturbations = (_perturbations(data["perturbation"], sc.rotor, run.duration)
                         if "perturbation" in data else ())
        return check_derived(dataclasses.replace(sc, name=name, text=text, instruments=instruments,
                                                 perturbations=perturbations, description=desc))

    rotor = _rotor(tables["rotor"])
    perturbations = (_perturbations(data["perturbation"], rotor, run.duration)
                     if "perturbation" in data else ())
    supports = _supports(tables["supports"])
    balancer = _balancer(tables["balancer"]) if "balancer" in tables else Balancer()
    w1 = math.sqrt(supports.stiffness_x / (rotor.mass + float(np.sum(balancer.mass))))
    drive = _drive(tables["drive"], w1)
    if isinstance(drive, TorqueDrive) and rotor.inertia is None:
        raise SceneError("rotor.inertia: missing; required with a torque drive "
                         '(drive.type = "torque") (kg*m^2, about the rotor\'s own centre of mass)')
    bodies = _bodies(data.get("weights"), rotor, supports, drive, perturbations)
    return check_derived(Scene(rotor=rotor, supports=supports, balancer=balancer, drive=drive,
                               run=run, initial=initial, name=name, text=text,
                               instruments=instruments, perturbations=perturbations,
                               description=desc, plane_weights=bodies))


def _bodies(items, rotor, supports, drive, perturbations) -> tuple:
    """``[[weights]]`` of body kinds on the planar rotor (stand.scene.body_tables)."""
    if items is None:
        return ()
    from stand.scene.body_tables import BODY_TYPES, parse_body
    from stand.model.rotors.planar_supports import planar_rotor

    if not isinstance(items, list):
        raise SceneError("[weights] must be an array of tables: write [[weights]]")
    lin = planar_rotor(rotor.mass, supports.stiffness_x, supports.stiffness_y,
                       supports.damping_x, supports.damping_y)
    out = []
    for i, item in enumerate(items):
        where = f"weights[{i}]"
        if not isinstance(item, Mapping):
            raise SceneError(f"{where}: must be a table")
        item = dict(item)
        plane = item.pop("plane", "balancer")
        if plane != "balancer":
            raise SceneError(f'{where}.plane = {_fmt(plane)}: the planar rotor has one plane, '
                             '"balancer"')
        if item.get("type") not in BODY_TYPES:
            raise SceneError(f"{where}.type = {_fmt(item.get('type'))}: one of "
                             f"{', '.join(BODY_TYPES)} (balls and pendulums go in [balancer])")
        out.append(parse_body(item, where, plane, lin))
    if out and (drive.kind != "speed" or drive.coast_down_start is not None
                or any(p.kind != "impulse" for p in perturbations)):
        raise SceneError("weights: body weights run on the generic kernel: a speed programme "
                         '(drive.type = "speed", no coast_down) and of the [[perturbation]]s '
                         'only impulses')
    return tuple(out)


def parse(data: Mapping, text: str = "", stem: str = "") -> Scene:
    """Build the :class:`Scene` of any scene document (the three file forms).

    A ``[structure]`` table selects :func:`stand.scene.structure_tables.parse_family_scene`,
    ``[weight_model]`` :func:`stand.scene.book_tables.parse_weight_model`, else the planar
    tables or ``[dimensionless]`` (:func:`parse_scene`).
    """
    if isinstance(data, Mapping) and "structure" in data:
        from stand.scene.structure_tables import parse_family_scene

        return parse_family_scene(data, text, stem)
    if isinstance(data, Mapping) and "weight_model" in data:
        from stand.scene.book_tables import parse_weight_model

        return parse_weight_model(data, text, stem)
    scene = parse_scene(data, text=text)
    return scene if scene.name else dataclasses.replace(scene, name=stem)


def _perturbations(items: Any, rotor: Rotor, duration: float) -> tuple:
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
                unbalance_angle=t.number("unbalance_angle", "deg", rotor.unbalance_angle / DEG) * DEG))
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


def _instruments(t: _Table, planes=("balancer",), kind: str = "planar") -> dict:
    """Parse ``[instruments.<name>]`` tables with each instrument's own validator.

    Shared by every scene form: ``plane`` / ``axial_position`` (where the instrument
    is attached, :mod:`stand.instruments.placement`) are taken out of each table and
    checked against the scene's ``planes`` and rotor ``kind``; the rest is the
    instrument's own settings.
    """
    from stand.instruments.placement import attach, check_placement, split_placement
    from stand.model.registry import resolve

    out = {}
    for key, value in t.data.items():
        if key not in INSTRUMENTS:
            raise SceneError(f"unknown instrument [instruments.{key}]: {_suggest(key, INSTRUMENTS)}"
                             f"valid instruments: {', '.join(INSTRUMENTS)}")
        settings_cls = resolve(INSTRUMENTS, key, f"[instruments.{key}]", "instrument")
        for name, table in _named_instances(key, value, t.name(key)):
            table, where = split_placement(table, t.name(name))
            out[name] = attach(settings_cls.from_table(_Table(table, t.name(name))), where)
            check_placement(out[name], planes, kind)
    return out


#: instruments of which a scene may hold several named instances, ``[instruments.<type>.<name>]``
NAMED_INSTRUMENTS = ("screen",)


def _named_instances(key: str, value, path: str) -> list:
    """``[(instrument name, table)]`` of one ``[instruments.<key>]`` table.

    One instance (``[instruments.screen]``, name ``"screen"``), or -- for the types of
    :data:`NAMED_INSTRUMENTS` -- named instances ``[instruments.screen.front]``,
    ``[instruments.screen.rear]`` (names ``"screen.front"``, ``"screen.rear"``): the
    sub-tables; the keys of ``[instruments.screen]`` itself are then the settings they
    share (each sub-table overrides them).
    """
    if not isinstance(value, dict):
        return [(key, value)]
    subs = {k: v for k, v in value.items() if isinstance(v, dict)}
    if not subs:
        return [(key, value)]
    if key not in NAMED_INSTRUMENTS:
        k = next(iter(subs))
        raise SceneError(f"[{path}.{k}]: [instruments.{key}] takes no named sub-tables (only "
                         f"{', '.join(NAMED_INSTRUMENTS)} may have several named instances)")
    shared = {k: v for k, v in value.items() if k not in subs}
    if "plane" in shared or "axial_position" in shared:
        raise SceneError(f"[{path}]: plane / axial_position belong to each named instance "
                         f"([{path}.<name>]), not to the shared settings")
    out = []
    for name, sub in subs.items():
        if not name.isidentifier():
            raise SceneError(f"[{path}.{name}]: the instance name must be a plain identifier "
                             "(letters, digits, _)")
        out.append((f"{key}.{name}", {**shared, **sub}))
    return out


def check_derived(scene: Scene) -> Scene:
    """Check the quantities the model derives from several fields.

    Each field may be valid alone while a combination overflows or leaves the
    model meaningless (e.g. a track radius of 1e200 m makes m l^2 infinite); the
    message names the fields involved.  Also bounds the run's size (memory for
    the samples, number of revolutions and natural periods) so that a scene can
    never ask for a run that exhausts memory or takes days.
    """
    b, r, s, run = scene.balancer, scene.rotor, scene.supports, scene.run
    with np.errstate(all="ignore"):
        Ms = scene.total_mass
        w1 = math.sqrt(s.stiffness_x / Ms) if Ms > 0 else math.nan
        checks = [("rotor.mass, balancer.mass (total mass, kg)", Ms),
                  ("supports.stiffness_x / total mass (natural frequency, rad/s)", w1),
                  ("rotor.mass * rotor.eccentricity (unbalance, kg*m)", r.unbalance)]
        if b.count:
            checks += [("balancer.mass * balancer.radius (capacity, kg*m)", b.capacity),
                       ("balancer.inertia (kg*m^2)", float(np.max(b.inertia))),
                       ("balancer.drag * radius^2 (moment drag, N*m*s)", float(np.max(b.moment_drag)))]
        L = scene.length_scale
        checks.append(("length scale (capacity or unbalance / total mass, m)", L))
        # the velocity scale L*w1 normalises initial.vx, vy; it can underflow to 0
        checks.append(("length scale * natural frequency (velocity scale, m/s; from rotor.mass, "
                       "supports.stiffness_x, balancer.mass and radius)", L * w1))
        for label, value in checks:
            if not (np.isfinite(value)) or (label.startswith(("rotor.mass,", "supports", "length"))
                                            and not value > 0):
                raise SceneError(f"{label} = {value!r}: out of floating-point range or zero; "
                                 "check the magnitudes of these fields")
        if b.count:
            J = np.asarray(b.inertia, float)
            coupled = np.asarray(b.mass * b.radius, float) * L / J
            if not np.all(np.isfinite(coupled)) or not np.all(J > 0):
                raise SceneError("balancer.mass, radius, inertia: the coupling m l L / J is out of "
                                 "floating-point range; check their magnitudes")
        d = scene.drive
        top = float(np.max(d.programme[:, 1])) if d.kind == "speed" else max(d.target_speed,
                                                                              d.initial_speed)
        for label, cycles in (("rotor revolutions", top * run.duration / (2 * math.pi)),
                              ("natural periods", w1 * run.duration / (2 * math.pi))):
            if not cycles <= MAX_CYCLES:
                raise SceneError(f"run.duration = {run.duration:g} s: the run spans {cycles:.3g} "
                                 f"{label}, more than {MAX_CYCLES:.0e}; shorten run.duration")
        width = 2 * (2 + b.count + (1 if d.kind == "torque" else 0))
        nbytes = (run.duration * run.sample_rate + 1) * width * 8 * 2  # samples + SI copies
        if nbytes > MAX_STATE_BYTES:
            raise SceneError(f"run.duration * run.sample_rate = {run.duration * run.sample_rate:.3g} "
                             f"samples of {width} state components need about {nbytes / 1e9:.3g} GB; "
                             f"the limit is {MAX_STATE_BYTES / 1e9:.0f} GB: lower run.sample_rate "
                             "or shorten run.duration")
        from stand.instruments.placement import check_instrument_budget

        check_instrument_budget(scene, width)
        ini = scene.initial
        if not all(np.isfinite(v / L) for v in (ini.x, ini.y)) or not all(
                np.isfinite(v / (L * w1)) for v in (ini.vx, ini.vy)):
            raise SceneError("initial.x, y, vx, vy: out of floating-point range relative to the "
                             "length scale; check their magnitudes")
    return scene


def load_scene(source: Union[str, Path]) -> Scene:
    """Read a scene (any file form) from a TOML file, or from TOML text.

    Parameters
    ----------
    source : str or pathlib.Path
        A path, or TOML text if it is a ``str`` containing a newline.

    Returns
    -------
    Scene
        With ``text`` the original TOML and ``name`` from ``[scene] name``,
        else the file stem (empty for TOML text).

    Raises
    ------
    SceneError
        Missing or unreadable file, TOML syntax error, or an invalid scene; for
        files the message starts with the file name.
    """
    from stand.io.tomlfile import read_toml

    data, text, label = read_toml(source, "scene file")
    stem = "" if not label else Path(source).stem
    try:
        return parse(data, text=text, stem=stem)
    except SceneError as exc:
        if label:
            raise SceneError(f"{label}{exc}") from None
        raise


#: :func:`stand.load`
load = load_scene


#: public name of the validating table reader, for instrument settings
Table = _Table
