"""What the axis keys of a sweep mean, for every scene kind.

* :func:`check_key` -- whether a key can be swept on a base scene (early, at
  :func:`stand.sweep.load_sweep`), with a message naming the key and why not;
* :func:`point_scene_dict` -- a point's scene document: the base with the
  axes' values applied;
* :func:`with_speed` -- the same for a speed key, on a validated scene.

Keys by base scene kind (:attr:`stand.scene.model.Scene.kind`):

* every kind: dotted scene keys ``table.key`` (the balls' dry friction too:
  ``balancer.friction``, ``weights[0].static_friction``, ...); ``[[weights]]`` tables by index,
  ``weights[0].drag``; a body weight's keys by its ``type`` (:func:`body_keys`:
  ``weights[0].fill_volume``, ``weights[0].arm``, ``weights[0].tilt_drag``, ...;
  its dimensionless sugar as ``weights[0].dimensionless.R_m``) on the planar
  rotor and on ``[structure]`` rotors;
* ``"planar"`` (``[rotor]``/``[supports]``/``[balancer]`` or ``[dimensionless]``):
  also ``R_omega`` (speed in units of omega_1), the bare dimensionless names
  and, on a physical scene, the conversions of ``e0``, ``h`` and ``H``;
* ``"rotor"`` (``[structure]`` + ``[[weights]]``): ``structure.<builder
  parameter>`` (angles in degrees, as in the scene file), ``weights[i].<key>``,
  ``run.<key>`` and ``speed`` (rev/s: the speed programme is scaled); no ``R_omega``
  (a structure has no single omega_1);
* ``"book"`` (``[weight_model]``): ``weight_model.<parameter>`` and ``run.<key>``
  (the model holds its own speed, ``weight_model.R_omega``).
"""
from __future__ import annotations

import copy
import math
import re
from typing import Any, Optional

import numpy as np

from stand.scene import parse as sf
from stand.errors import SceneError
from stand.sweep.checks import SweepSpecError, _fmt, _suggest

__all__ = ["SPECIAL_KEYS", "RATIO_KEYS", "DIMENSIONLESS_NAMES", "SCENE_TABLE_KEYS", "BODY_TYPES",
           "body_keys", "scene_kind", "check_key", "point_scene_dict", "with_speed"]

TWO_PI = 2.0 * math.pi
#: speed keys handled by the sweep itself (not scene-file keys)
SPECIAL_KEYS = ("R_omega", "dimensionless.R_omega", "speed", "drive.speed")
#: the speed keys in units of omega_1 (planar rotor only)
RATIO_KEYS = ("R_omega", "dimensionless.R_omega")
#: bare dimensionless names accepted as axis keys (planar rotor)
DIMENSIONLESS_NAMES = ("n", "Rt", "h", "H", "e0", "R_omega2", "unbalance_angle")
#: known keys of each planar scene table (second level), for early messages
SCENE_TABLE_KEYS = {
    "scene": sf.SCENE_KEYS, "rotor": sf.ROTOR_KEYS, "supports": sf.SUPPORT_KEYS,
    "balancer": tuple(k for k in sf.BALANCER_KEYS if k != "rolling"), "run": sf.RUN_KEYS,
    "initial": sf.INITIAL_KEYS,
    "dimensionless": sf.DIMENSIONLESS_KEYS,
    "drive": tuple(dict.fromkeys(sf.SPEED_KEYS + sf.TORQUE_KEYS + ("torque", "c1", "c2", "target_speed"))),
}
#: the body weights' ``type`` values (:data:`stand.scene.body_tables.BODY_TYPES`)
BODY_TYPES = ("two_axis_pendulum", "coupled_pair", "damper", "liquid_float", "liquid_chamber")
#: keys of the ``dimensionless`` sugar table of a body weight (``weights[i].dimensionless.<name>``)
BODY_SUGAR_KEYS = {"two_axis_pendulum": ("R_m", "R_rho", "R_g", "h1", "h2"),
                   "coupled_pair": ("R_m", "R_rho", "R_g", "h1", "h2"),
                   "damper": ("R_m", "R_g", "h")}
#: key endings whose values must be integers
INTEGER_KEYS = (".count", ".samples", ".max_steps")
_PART = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)((?:\[\d+\])*)$")


def scene_kind(doc: dict) -> str:
    """Kind of a scene document: ``"rotor"`` (``[structure]``), ``"book"``
    (``[weight_model]``) or ``"planar"``."""
    if "structure" in doc:
        return "rotor"
    return "book" if "weight_model" in doc else "planar"


def _describe(doc: dict) -> str:
    kind = scene_kind(doc)
    if kind == "rotor":
        return f"a [structure] scene (rotor type {doc['structure'].get('type')!r})"
    if kind == "book":
        return f"a [weight_model] scene (book model {doc['weight_model'].get('type')!r})"
    return "a planar scene"


def _path(key: str) -> list:
    """``"weights[0].drag"`` -> ``["weights", 0, "drag"]``; None if not a scene path."""
    out: list = []
    for part in key.split("."):
        m = _PART.match(part)
        if m is None:
            return None
        out.append(m.group(1))
        out += [int(i) for i in re.findall(r"\[(\d+)\]", m.group(2))]
    return out


# ---------------------------------------------------------------- checks
def check_key(name: str, key: str, base: dict) -> None:
    """Reject a key that no point of ``base`` could use.

    Parameters
    ----------
    name : str
        The field, for messages (``axis[1].key``).
    key : str
        The axis key.
    base : dict
        The base scene document (already validated).

    Raises
    ------
    SweepSpecError
        The message names the key and why it cannot be swept on this base.
    """
    kind = scene_kind(base)
    if key in SPECIAL_KEYS:
        if "drive" not in base:
            why = (" (its speed is a model parameter: sweep weight_model.R_omega or run.speed)"
                   if kind == "book" else "")
            raise SweepSpecError(f"{name} = {_fmt(key)}: the base scene has no [drive] table{why}")
        if key in RATIO_KEYS and kind != "planar":
            raise SweepSpecError(f"{name} = {_fmt(key)}: a speed in units of omega_1, the natural "
                                 f"frequency of the planar rotor of chapter 5; the base scene is "
                                 f"{_describe(base)}, which has no single omega_1: sweep \"speed\" "
                                 "(rev/s) instead")
        return
    if "." not in key and "[" not in key:
        _check_bare(name, key, base, kind)
        return
    path = _path(key)
    if path is None or isinstance(path[1], int) and len(path) < 3:
        raise SweepSpecError(f"{name} = {_fmt(key)}: not a scene key; write table.key, or "
                             "weights[i].key for an array of tables")
    {"planar": _check_planar, "rotor": _check_rotor, "book": _check_book}[kind](name, key, path, base)


def _check_bare(name: str, key: str, base: dict, kind: str) -> None:
    dimless = "dimensionless" in base
    if key not in DIMENSIONLESS_NAMES:
        valid = SPECIAL_KEYS[::2] + DIMENSIONLESS_NAMES
        raise SweepSpecError(f"{name} = {_fmt(key)}: {_suggest(key, valid)}not a dimensionless "
                             f"parameter ({', '.join(valid)}) nor a dotted scene key "
                             "such as \"rotor.eccentricity\"")
    if kind != "planar":
        example = "structure.unbalance" if kind == "rotor" else "weight_model.e0"
        raise SweepSpecError(f"{name} = {_fmt(key)}: the bare names ({', '.join(DIMENSIONLESS_NAMES)}) "
                             "are the book's parameters of the planar rotor of chapter 5; the base "
                             f"scene is {_describe(base)}: sweep a dotted scene key such as "
                             f"\"{example}\" instead")
    if not dimless and key not in ("e0", "h", "H"):
        raise SweepSpecError(f"{name} = {_fmt(key)}: needs a [dimensionless] base scene (with a "
                             "physical base scene only e0, h, H, R_omega, speed are converted); "
                             "sweep the physical scene key instead")
    if not dimless and key == "e0" and base.get("balancer", {}).get("type", "none") == "none":
        raise SweepSpecError(f"{name} = \"e0\": converted to rotor.eccentricity with the capacity "
                             "of the [balancer] balls, and the base scene has none"
                             + (" (its body weights' capacity depends on their kind)"
                                if base.get("weights") else "")
                             + "; sweep rotor.eccentricity instead")
    if not dimless and key == "h" and base.get("balancer", {}).get("type") != "balls":
        raise SweepSpecError(f"{name} = \"h\": converted to balancer.drag only for "
                             "balancer.type = \"balls\"; sweep balancer.drag instead")


def _unknown_key(name: str, key: str, table: str, first: str, known) -> SweepSpecError:
    return SweepSpecError(f"{name} = {_fmt(key)}: unknown key {table}.{first}: "
                          f"{_suggest(first, known)}valid keys in [{table}]: {', '.join(known)}")


def _unknown_table(name: str, key: str, table: str, valid, base: dict) -> SweepSpecError:
    return SweepSpecError(f"{name} = {_fmt(key)}: unknown scene table [{table}] of "
                          f"{_describe(base)}: {_suggest(table, valid)}valid tables: {', '.join(valid)}")


def _check_planar(name: str, key: str, path: list, base: dict) -> None:
    dimless = "dimensionless" in base
    table, first = path[0], path[1]
    valid = [t for t in sf.TABLES if t != "perturbation"]
    if table not in valid:
        raise _unknown_table(name, key, table, valid, base)
    if table == "weights":
        _check_weights(name, key, path, base, ())
        return
    known = SCENE_TABLE_KEYS.get(table)
    if known is not None and first not in known:
        raise _unknown_key(name, key, table, first, known)
    if table == "dimensionless" and not dimless:
        raise SweepSpecError(f"{name} = {_fmt(key)}: the base scene has no [dimensionless] table")
    if table in ("rotor", "supports", "balancer") and dimless:
        raise SweepSpecError(f"{name} = {_fmt(key)}: the base scene is [dimensionless]; it has no "
                             f"[{table}] table (sweep dimensionless.* instead)")


def _check_rotor(name: str, key: str, path: list, base: dict) -> None:
    from stand.scene.structure_tables import _builder

    table, first = path[0], path[1]
    if table == "structure":
        import inspect

        params = [p for p in inspect.signature(_builder(base["structure"]["type"])).parameters]
        if first not in params:
            raise _unknown_key(name, key, table, first, params)
    elif table == "weights":
        _check_weights(name, key, path, base,
                       tuple(k for k in sf.BALANCER_KEYS if k not in ("type", "rolling")))
    elif table == "run":
        known = tuple(k for k in sf.RUN_KEYS if k != "method")
        if first not in known:
            raise _unknown_key(name, key, table, first, known)
    elif table == "drive":
        raise SweepSpecError(f"{name} = {_fmt(key)}: the drive of {_describe(base)} is a speed "
                             "programme [[t (s), speed (rev/s)], ...]; sweep \"speed\" (rev/s), "
                             "which scales it")
    else:
        raise _unknown_table(name, key, table, ("structure", "weights", "run"), base)


def body_keys(kind: str) -> tuple:
    """The keys of a body weight's ``[[weights]]`` table of type ``kind`` (empty if not a body;
    :mod:`stand.scene.body_tables`, imported here only: ``stand --help`` loads this module)."""
    from stand.scene import body_tables as bs

    return {"two_axis_pendulum": bs._TILT_KEYS, "coupled_pair": bs._TILT_KEYS,
            "damper": bs._DAMPER_KEYS, "liquid_float": bs._FLOAT_KEYS,
            "liquid_chamber": bs._CHAMBER_KEYS}.get(kind, ())


def _check_weights(name: str, key: str, path: list, base: dict, ball_keys: tuple) -> None:
    """``weights[i].<key>``: ``i`` within the base's ``[[weights]]`` tables and ``<key>`` a
    numeric key of that table's ``type`` (balls: ``ball_keys``; a body: :func:`body_keys`)."""
    items = base.get("weights", [])
    first = path[1]
    if not isinstance(first, int) or first >= len(items):
        raise SweepSpecError(f"{name} = {_fmt(key)}: the base scene has {len(items)} [[weights]] "
                             f"table(s); write weights[i].key with i < {len(items)}")
    item = items[first] if isinstance(items[first], dict) else {}
    kind = item.get("type", "balls")
    where = f"weights[{first}]"
    if kind in BODY_TYPES:
        known = tuple(k for k in body_keys(kind) if k != "dimensionless")
        sugar = BODY_SUGAR_KEYS.get(kind, ())
        if len(path) == 4 and path[2] == "dimensionless" and sugar:
            if path[3] not in sugar:
                raise _unknown_key(name, key, f"{where}.dimensionless", path[3], sugar)
            if "dimensionless" not in item:
                raise SweepSpecError(f"{name} = {_fmt(key)}: {where} (type {kind!r}) of the base "
                                     "scene gives SI keys, not the dimensionless sugar; sweep its "
                                     f"SI keys ({', '.join(known)})")
            return
        if len(path) != 3 or path[2] not in known:
            raise SweepSpecError(f"{name} = {_fmt(key)}: unknown key of {where} (type {kind!r}): "
                                 f"{_suggest(str(path[2]) if len(path) > 2 else '', known)}"
                                 f"valid keys: {', '.join(known)}"
                                 + (f"; or {where}.dimensionless.<{'|'.join(sugar)}>"
                                    if sugar else ""))
        if "dimensionless" in item and path[2] in ("inertia_tilt", "inertia_axial", "tilt_drag",
                                                   "turn_drag", "inertia", "drag", "axial_gravity"):
            raise SweepSpecError(f"{name} = {_fmt(key)}: {where} of the base scene gives the "
                                 f"dimensionless sugar; sweep {where}.dimensionless.<name> instead")
        return
    if not ball_keys:
        raise SweepSpecError(f"{name} = {_fmt(key)}: {where} has type {kind!r}; on the planar "
                             "rotor the balls are swept as balancer.<key>, [[weights]] holds the "
                             f"body weights ({', '.join(BODY_TYPES)})")
    if len(path) != 3 or path[2] not in ball_keys:
        raise _unknown_key(name, key, where, path[2] if len(path) > 2 else "", ball_keys)


def _check_book(name: str, key: str, path: list, base: dict) -> None:
    import dataclasses

    from stand.scene.book_tables import MODEL_TYPES, RUN_KEYS

    table, first = path[0], path[1]
    if table == "weight_model":
        from stand.model.registry import resolve

        cls = resolve(MODEL_TYPES, base["weight_model"]["type"], "weight_model.type", "weight model")
        fields = [f.name for f in dataclasses.fields(cls)]
        if first not in fields:
            raise _unknown_key(name, key, table, first, fields)
    elif table == "run":
        known = tuple(k for k in RUN_KEYS if k != "initial")
        if first not in known:
            raise _unknown_key(name, key, table, first, known)
    else:
        raise _unknown_table(name, key, table, ("weight_model", "run"), base)


# ---------------------------------------------------------------- point scenes
def _set(doc: dict, key: str, value: Any) -> None:
    parts = _path(key) if "[" in key else key.split(".")
    t = doc
    for i, p in enumerate(parts[:-1]):
        if isinstance(p, int):
            t = t[p] if isinstance(t, list) and p < len(t) else None
        else:
            t = t.setdefault(p, {}) if isinstance(t, dict) else None
        if not isinstance(t, (dict, list)):
            where = ".".join(str(q) for q in parts[:i + 1])
            raise SceneError(f"{key}: {where} is not a table in the base scene")
    if not isinstance(t, dict):
        raise SceneError(f"{key}: not a key of a table in the base scene")
    t[parts[-1]] = value


def _natural_frequency(doc: dict) -> float:
    """omega_1 [rad/s] of a planar scene document (before validation)."""
    if "dimensionless" in doc:
        return TWO_PI * float(doc["dimensionless"].get("natural_frequency", 1.0 / TWO_PI))
    s, r, b = doc.get("supports", {}), doc.get("rotor", {}), doc.get("balancer", {})
    c = float(s.get("stiffness", s.get("stiffness_x", math.nan)))
    return math.sqrt(c / (float(r.get("mass", math.nan)) + _weights_mass(b)
                          + _bodies_mass(doc.get("weights", []))))


def _bodies_mass(items) -> float:
    """Mass [kg] of the body weights of a planar document (as ``Scene.total_mass`` counts them)."""
    total = 0.0
    for w in items if isinstance(items, list) else []:
        if not isinstance(w, dict):
            continue
        kind = w.get("type")
        if kind in ("two_axis_pendulum", "coupled_pair", "damper"):
            total += float(w.get("mass", 0.0))
        elif kind == "liquid_float":
            total += float(w.get("liquid_mass", 0.0))
        elif kind == "liquid_chamber":
            total += float(w.get("density", 1000.0)) * float(w.get("fill_volume", 0.0))
    return total


def _per_weight(b: dict, key: str) -> np.ndarray:
    n = int(b.get("count", 0))
    v = b.get(key, 0.0)
    return np.asarray(v, float) if isinstance(v, list) else np.full(n, float(v))


def _weights_mass(b: dict) -> float:
    if b.get("type", "none") == "none":
        return 0.0
    return float(np.sum(_per_weight(b, "mass")))


def _scaled_programme(prog, target: float, key: str, value: float) -> list:
    """A speed programme scaled so that its last point is ``target`` (a one-point
    programme is set to it)."""
    if not len(prog):
        raise SceneError(f"{key}: the base scene's drive has no programme to scale")
    last = float(prog[-1][1])
    if len(prog) == 1:
        return [[float(prog[0][0]), target]]
    if last == 0.0:
        raise SceneError(f"{key}: the base programme ends at speed 0; cannot scale it to {value:g}")
    return [[float(t), float(v) * target / last] for t, v in prog]


def _set_speed(doc: dict, speed_rev_s: float, key: str) -> None:
    d = doc["drive"]
    if d.get("type") == "torque":
        d["target_speed"] = speed_rev_s
        return
    if "programme_dimensionless" in d:
        target = speed_rev_s * TWO_PI / _natural_frequency(doc)
        d["programme_dimensionless"] = _scaled_programme(d["programme_dimensionless"], target, key,
                                                         target)
    else:
        prog = d.get("programme")
        d["programme"] = _scaled_programme(prog if isinstance(prog, list) else [], speed_rev_s,
                                           key, speed_rev_s)


def point_scene_dict(base: dict, keys, values) -> dict:
    """The scene document of one point: the base with the axes' values applied.

    Parameters
    ----------
    base : dict
        Base scene document (TOML tables), any scene kind.
    keys : sequence of str
        Axis keys (see the module notes).
    values : sequence of float
        One value per key, in that key's unit.

    Returns
    -------
    dict
        A new document; validate it with :func:`stand.scene.parse.parse`.

    Raises
    ------
    SceneError
        A value cannot be applied (e.g. scaling a programme that ends at 0).
    """
    doc = copy.deepcopy(base)
    speed = None
    for key, v in zip(keys, values):
        v = float(v)
        if key in ("n", "dimensionless.n") or key.endswith(INTEGER_KEYS):
            if v != int(v):
                raise SceneError(f"{key} = {v!r}: must be an integer")
            v = int(v)
        if key in SPECIAL_KEYS:
            speed = (key, v)
        elif "." in key:
            _set(doc, key, v)
        elif "dimensionless" in doc:
            _set(doc, f"dimensionless.{key}", v)
        else:
            _set(doc, f"__physical__.{key}", v)
    phys = doc.pop("__physical__", {})
    if phys:
        _physical(doc, phys)
    if speed is not None:
        key, v = speed
        rev_s = v * _natural_frequency(doc) / TWO_PI if key in RATIO_KEYS else v
        _set_speed(doc, rev_s, key)
    return doc


def _physical(doc: dict, phys: dict) -> None:
    """The bare names e0, H, h on a physical planar scene: rotor, support and
    balancer fields (module notes of :mod:`stand.sweep.spec`)."""
    r, b, s = doc["rotor"], doc.get("balancer", {}), doc["supports"]
    w1 = _natural_frequency(doc)
    if "e0" in phys:
        S = float(np.sum(_per_weight(b, "mass") * _per_weight(b, "radius")))
        r["eccentricity"] = phys["e0"] * S / float(r["mass"])
    if "H" in phys:
        Ms = float(r["mass"]) + _weights_mass(b) + _bodies_mass(doc.get("weights", []))
        for k in ("damping_x", "damping_y"):
            s.pop(k, None)
        s["damping"] = phys["H"] * w1 * Ms
    if "h" in phys:
        m = _per_weight(b, "mass")
        b["drag"] = [float(x) for x in phys["h"] * w1 * m]


def with_speed(scene, key: str, value: float, omega_1: Optional[float] = None):
    """The validated scene at another held speed: :func:`point_scene_dict`'s scaling
    of the programme (or the torque drive's target speed), on the dataclass.

    Parameters
    ----------
    scene : stand.scene.model.Scene
    key : str
        A speed key (:data:`SPECIAL_KEYS`).
    value : float
        The speed: rev/s, or units of omega_1 for :data:`RATIO_KEYS`.
    omega_1 : float, optional
        omega_1 [rad/s] for a ratio key (default ``scene.natural_frequency``).
    """
    import dataclasses

    if key in RATIO_KEYS:
        target = value * (omega_1 if omega_1 is not None else scene.natural_frequency)
    else:
        target = value * TWO_PI
    if not (math.isfinite(target) and target >= 0):
        raise SceneError(f"{key} = {value!r}: must be a finite speed >= 0")
    d = scene.drive
    if d.kind == "torque":
        return dataclasses.replace(scene, drive=dataclasses.replace(d, target_speed=target))
    prog = np.array(_scaled_programme(np.asarray(d.programme, float), target, key, value), float)
    return dataclasses.replace(scene, drive=dataclasses.replace(d, programme=prog))
