"""Scene files: TOML in, one validated :class:`stand.scene.model.Scene` out (:func:`load`).

Three file forms build the same Scene: the planar tables (``[rotor]``,
``[supports]``, ``[balancer]``) or the book's ``[dimensionless]`` form (this
module), ``[structure]`` + ``[[weights]]`` (:mod:`stand.scene.structure_tables`) and
``[weight_model]`` (:mod:`stand.scene.book_tables`); ``[structure] type = "planar"`` is read
into the Scene of the planar tables (:func:`planar_structure`).  Each table is read by one
function of :mod:`stand.scene.tables` (instruments: :mod:`stand.scene.instrument_tables`)
whatever the form it appears in; the forms only assemble them.

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
from typing import Mapping, Optional, Union

import numpy as np

from stand.io.validate import _Table, _fmt, _kind, _number, _suggest  # noqa: F401 (re-exported)
from stand.scene.book_tables import parse_weight_model
from stand.scene.conditioning import check_conditioning
from stand.scene.dimensionless import (DIMENSIONLESS_KEYS, _dimensionless_params,  # noqa: F401
                                       scene_from_dimensionless)
from stand.scene.instrument_tables import INSTRUMENTS, NAMED_INSTRUMENTS, instrument_tables  # noqa: F401
from stand.scene.limits import (MAX_CYCLES, MAX_IMAGE_PIXELS, MAX_SAMPLES,  # noqa: F401 (re-exported)
                                MAX_STATE_BYTES, MAX_WEIGHTS)
from stand.scene.model import (SCENE_LANGUAGE, Balancer, InitialState, Rotor, Scene,
                               SceneError, Supports, TorqueDrive)
from stand.scene.structure_tables import parse_family_scene
from stand.scene.tables import (BALANCER_KEYS, INITIAL_KEYS, PERTURBATION_KEYS,  # noqa: F401
                                ROTOR_KEYS, RUN_KEYS, SCENE_KEYS, SPEED_KEYS, SUPPORT_KEYS, TABLES,
                                TORQUE_KEYS, TORQUE_MODEL_KEYS, balancer_table, check_programme_slope,
                                check_tables, drive_table, friction_table, initial_table, perturbation_tables, rotor_table,
                                run_table, scene_header, scene_language, supports_table,
                                weight_tables)

__all__ = ["load", "load_scene", "parse", "parse_scene", "scene_from_dimensionless", "MAX_SAMPLES"]

TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0


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
    check_tables(data, TABLES)
    tables = {key: _Table(value, key) for key, value in data.items()
              if key not in ("perturbation", "weights")}
    physical = [k for k in ("rotor", "supports", "balancer") if k in tables]
    if "dimensionless" in tables and physical:
        raise SceneError(f"[dimensionless] cannot be combined with [{physical[0]}]: a "
                         f"[dimensionless] scene defines rotor, supports and balancer itself")
    for key in ("drive", "run") + (() if "dimensionless" in tables else ("rotor", "supports")):
        if key not in tables:
            raise SceneError(f"missing table [{key}] (required)")

    name, desc = scene_header(data)
    run = run_table(tables["run"])
    initial = initial_table(tables["initial"]) if "initial" in tables else InitialState()
    instruments = instrument_tables(tables["instruments"]) if "instruments" in tables else {}

    if "dimensionless" in tables:
        p = _dimensionless_params(tables["dimensionless"], "deg")
        p["unbalance_angle"] *= DEG
        if p["initial_angles"] is not None:
            p["initial_angles"] = p["initial_angles"] * DEG
        drive = drive_table(tables["drive"], TWO_PI * p["natural_frequency"])
        sc = scene_from_dimensionless(**p, drive=drive, run=run, initial=initial)
        perturbations = (perturbation_tables(data["perturbation"], sc.rotor, run.duration)
                         if "perturbation" in data else ())
        return check_derived(dataclasses.replace(sc, name=name, text=text, instruments=instruments,
                                                 perturbations=perturbations, description=desc))

    rotor = rotor_table(tables["rotor"])
    perturbations = (perturbation_tables(data["perturbation"], rotor, run.duration)
                     if "perturbation" in data else ())
    supports = supports_table(tables["supports"])
    balancer = balancer_table(tables["balancer"]) if "balancer" in tables else Balancer()
    friction = friction_table(tables["balancer"]) if "balancer" in tables else None
    w1 = math.sqrt(supports.stiffness_x / (rotor.mass + float(np.sum(balancer.mass))))
    drive = drive_table(tables["drive"], w1)
    if isinstance(drive, TorqueDrive) and rotor.inertia is None:
        raise SceneError("rotor.inertia: missing; required with a torque drive "
                         '(drive.type = "torque") (kg*m^2, about the rotor\'s own centre of mass)')
    bodies = _bodies(data.get("weights"), rotor, supports, drive, perturbations)
    if friction is not None:
        _generic_kernel_limits("balancer.friction (dry friction of the weights)", drive,
                               perturbations, torque=True)
    if balancer.ball_radius > 0:
        _generic_kernel_limits("balancer.ball_radius (ball-ball contact)", drive, perturbations,
                               torque=True)
    for key in ("race_eccentricity", "race_out_of_roundness"):
        if getattr(balancer, key) > 0:
            _generic_kernel_limits(f"balancer.{key}", drive, perturbations, torque=False)
    return check_derived(Scene(rotor=rotor, supports=supports, balancer=balancer, drive=drive,
                               run=run, initial=initial, name=name, text=text,
                               instruments=instruments, perturbations=perturbations,
                               description=desc, plane_weights=bodies, friction=friction))


def _bodies(items, rotor, supports, drive, perturbations) -> tuple:
    """``[[weights]]`` of body kinds on the planar rotor (:func:`stand.scene.tables.weight_tables`)."""
    if items is None:
        return ()
    from stand.model.rotors.planar_supports import planar_rotor

    lin = planar_rotor(rotor.mass, supports.stiffness_x, supports.stiffness_y,
                       supports.damping_x, supports.damping_y)
    out = weight_tables(items, lin, "planar", planar=True)
    if out:
        _generic_kernel_limits("weights: body weights", drive, perturbations, torque=False)
    return out


def _generic_kernel_limits(what: str, drive, perturbations, torque: bool) -> None:
    """What the generic kernel (stand.model.rotors.coupled_kernel) runs of a planar scene: a
    speed programme without the exponential coast-down (or, with ``torque``, a torque drive)
    and, of the ``[[perturbation]]``s, the blows to the housing."""
    if ((drive.kind != "speed" and not torque)
            or (drive.kind == "speed" and drive.coast_down_start is not None)
            or any(p.kind != "impulse" for p in perturbations)):
        drives = ('a speed programme (drive.type = "speed", no coast_down) or a torque drive'
                  if torque else 'a speed programme (drive.type = "speed", no coast_down)')
        raise SceneError(f"{what} run on the generic kernel: {drives} and of the "
                         "[[perturbation]]s only impulses")


def parse(data: Mapping, text: str = "", stem: str = "", language: Optional[int] = None) -> Scene:
    """Build the :class:`Scene` of any scene document (the three file forms).

    A ``[structure]`` table selects :func:`stand.scene.structure_tables.parse_family_scene`
    (``type = "planar"`` is then read into the Scene of the ``[rotor]`` form,
    :func:`planar_structure`), ``[weight_model]`` :func:`stand.scene.book_tables.parse_weight_model`,
    else the planar tables or ``[dimensionless]`` (:func:`parse_scene`).  Every form's linear
    structure is held to the conditioning limits (:func:`stand.scene.conditioning.check_conditioning`).
    ``language``: the scene-file language of a stored text without ``[scene] language``
    (:data:`SCENE_LANGUAGE`: every angle in degrees; 1, of recordings written before it, reads
    the ``[structure]`` angles in rad; the other tables read the same in both); None (a file):
    as ``[scene] language`` declares, else :data:`SCENE_LANGUAGE`
    (:func:`stand.scene.tables.scene_language`).
    """
    language = scene_language(data, language)
    if isinstance(data, Mapping) and "structure" in data:
        return planar_structure(check_conditioning(parse_family_scene(data, text, stem, language)),
                                data)
    if isinstance(data, Mapping) and "weight_model" in data:
        return parse_weight_model(data, text, stem)
    scene = check_conditioning(parse_scene(data, text=text))
    return dataclasses.replace(scene, name=scene.name or stem,
                               language=language or SCENE_LANGUAGE)


def planar_structure(sc: Scene, data: Mapping) -> Scene:
    """A ``[structure] type = "planar"`` scene as the Scene of its ``[rotor]``, ``[supports]``,
    ``[balancer]`` form (one representation of the planar rotor, so that both spellings run
    alike, bit for bit, on the kernel the content picks: :attr:`Scene.generic_kernel`).

    The structure's M, K, D and unbalance are taken exactly (``eccentricity`` as written, else
    unbalance / mass), its one ball or pendulum ``[[weights]]`` table is the balancer (with
    its friction), body weights stay ``plane_weights``; a torque drive's ``inertia`` about
    the shaft J_p gives ``rotor.inertia`` J_C = J_p - M e^2.  A scene the planar form cannot
    say stays a rotor-family scene: transverse gravity ``g``, several weight tables, body
    weights with a torque drive.
    """
    if sc.kind != "rotor" or sc.structure.type != "planar":
        return sc
    lin, st = sc.structure.rotor, data["structure"]
    tables = [w for w in sc.plane_weights if hasattr(w, "balancer")]
    torque = sc.drive.kind == "torque"
    if np.any(lin.gravity_plane) or len(tables) > 1 or (torque and sc.bodies):
        return sc
    (u,) = lin.unbalances
    M = float(lin.M[0, 0])
    e = float(st["eccentricity"]) if "eccentricity" in st else u.s / M
    inertia, drive = None, sc.drive
    if torque:
        inertia = drive.inertia - M * e * e
        if not inertia > 0:
            raise SceneError(f"drive.inertia = {drive.inertia:g}: must be > M e^2 = {M * e * e:g} "
                             "(kg*m^2, the rotor's polar moment of inertia about the shaft)")
        drive = TorqueDrive(**{f.name: getattr(drive, f.name) for f in
                               dataclasses.fields(TorqueDrive)})
    pw = tables[0] if tables else None
    rotor = Rotor(mass=M, eccentricity=e, unbalance_angle=u.angle, inertia=inertia)
    supports = Supports(float(lin.K[0, 0]), float(lin.K[1, 1]), float(lin.D[0, 0]),
                        float(lin.D[1, 1]))
    return check_derived(Scene(
        rotor=rotor, supports=supports, balancer=pw.balancer if pw else Balancer(), drive=drive,
        run=sc.run, name=sc.name, text=sc.text, instruments=sc.instruments,
        description=sc.description, plane_weights=sc.bodies,
        friction=pw.friction if pw else None, language=sc.language))


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
        if d.kind == "speed":
            check_programme_slope(d.programme)
        width = 2 * (2 + b.count + (1 if d.kind == "torque" else 0))
        if scene.friction is not None and scene.friction.sticks:
            width += b.count        # the generic kernel's adhesion state per weight
        nbytes = (run.duration * run.sample_rate + 1) * width * 8 * 2  # samples + SI copies
        if nbytes > MAX_STATE_BYTES:
            raise SceneError(f"run.duration * run.sample_rate = {run.duration * run.sample_rate:.3g} "
                             f"samples of {width} state components need about {nbytes / 1e9:.3g} GB; "
                             f"the limit is {MAX_STATE_BYTES / 1e9:.0f} GB: lower run.sample_rate "
                             "or shorten run.duration")
        from stand.scene.placement import check_instrument_budget

        check_instrument_budget(scene, width)
        ini = scene.initial
        if not all(np.isfinite(v / L) for v in (ini.x, ini.y)) or not all(
                np.isfinite(v / (L * w1)) for v in (ini.vx, ini.vy)):
            raise SceneError("initial.x, y, vx, vy: out of floating-point range relative to the "
                             "length scale; check their magnitudes")
    return scene


def load_scene(source: Union[str, Path], language: Optional[int] = None) -> Scene:
    """Read a scene (any file form) from a TOML file, or from TOML text.

    Parameters
    ----------
    source : str or pathlib.Path
        A path, or TOML text if it is a ``str`` containing a newline.
    language : int or None
        The scene-file language of a text without ``[scene] language``
        (:data:`stand.scene.model.SCENE_LANGUAGE`, every angle in degrees; 1 reads a text stored
        in a recording written before it, ``[structure]`` angles in rad:
        :func:`stand.recording.layout.scene_language`).  None: the file's own declaration, or
        :data:`stand.scene.model.SCENE_LANGUAGE` without one.

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
        return parse(data, text=text, stem=stem, language=language)
    except SceneError as exc:
        if label:
            raise SceneError(f"{label}{exc}") from None
        raise


#: :func:`stand.load`
load = load_scene


#: public name of the validating table reader, for instrument settings
Table = _Table
