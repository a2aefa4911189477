"""The ``SWEEP.toml`` format: a base scene, parameter axes, what to compute.

A sweep file has four kinds of tables (all documented in ``docs/sweep.md``)::

    [sweep]                      # optional
    name = "ball_map"
    compute = ["theory"]         # "theory", "simulate" or both
    combine = "product"          # "product" (default) or "zip" of the axes
    chunk_size = 500             # points per task; default: automatic
    seed = 0                     # default seed of random axes

    [base]                       # the scene every point starts from
    scene = "../scenes/ball_runup.toml"   # a path (relative to this file) ...
    # ... or inline scene tables: [base.dimensionless], [base.drive], [base.run] ...

    [[axis]]
    key = "R_omega"              # a dimensionless parameter or a dotted scene key
    start = 0.5                  # a grid: start, stop, num, spacing = "linear" | "log"
    stop = 8.0
    num = 100

    [[axis]]
    key = "rotor.eccentricity"   # SI units of the scene file (m here)
    values = [1e-4, 2e-4]        # a list ...
    # random = "uniform" | "log-uniform", low, high, count, seed   # ... or random samples

    [theory]                     # options of compute = "theory"
    side = false                 # also the side motions (about 20 ms per point)
    critical_speeds = true

    [simulate]                   # options of compute = "simulate"
    window = 0.2                 # fraction of the run classified (stand.regime.classify)

Every problem raises :class:`SweepSpecError` naming the field, its value and
what is expected, e.g. ``axis[1].num = 1: must be an integer >= 2``.  Nothing
is evaluated (no ``eval``) and nothing is unpickled: the file is TOML only.

Axis keys
---------
* Dotted scene keys, ``table.key`` (``rotor.eccentricity``,
  ``dimensionless.e0``, ``supports.damping``, ``drive.coast_down.start`` ...):
  the value replaces that key of the base scene, in the scene file's units.
* ``R_omega`` (alias ``dimensionless.R_omega``): the held rotor speed in units
  of omega_1.  For a speed drive the programme's speeds are scaled so that its
  last point equals it (a one-point programme is a constant speed); for a
  torque drive it sets ``drive.target_speed``.
* ``speed`` (alias ``drive.speed``): the same in rev/s.
* Bare dimensionless names ``n``, ``Rt``, ``h``, ``H``, ``e0``, ``R_omega2``,
  ``unbalance_angle`` (deg): ``dimensionless.<name>`` for a ``[dimensionless]``
  base scene.  For a physical base scene ``e0`` sets ``rotor.eccentricity`` =
  e0 S / M (S the balancer capacity, M the rotor mass), ``H`` sets
  ``supports.damping`` = H omega_1 M_Sigma and ``h`` (balls) sets
  ``balancer.drag`` = h omega_1 m; the others need a ``[dimensionless]`` base.
"""
from __future__ import annotations

import copy
import difflib
import hashlib
import json
import math
import numbers
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping, Optional, Union

import numpy as np

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

from .. import scene_file as sf
from ..scene import SceneError

__all__ = ["SweepSpecError", "Axis", "SweepSpec", "load_sweep", "parse_sweep", "point_scene_dict",
           "COMPUTE", "SPECIAL_KEYS", "DIMENSIONLESS_NAMES"]

TWO_PI = 2.0 * math.pi
COMPUTE = ("theory", "simulate")
SWEEP_TABLES = ("sweep", "base", "axis", "theory", "simulate")
SWEEP_KEYS = ("name", "description", "compute", "combine", "chunk_size", "seed")
AXIS_KEYS = ("key", "values", "start", "stop", "num", "spacing", "random", "low", "high",
             "count", "seed", "name")
THEORY_KEYS = ("side", "critical_speeds", "R_max")
SIMULATE_KEYS = ("window", "sync_tol", "balance_tol", "method")
#: speed keys handled by the sweep itself (not scene-file keys)
SPECIAL_KEYS = ("R_omega", "dimensionless.R_omega", "speed", "drive.speed")
#: bare dimensionless names accepted as axis keys
DIMENSIONLESS_NAMES = ("n", "Rt", "h", "H", "e0", "R_omega2", "unbalance_angle")
#: known keys of each scene table (second level), for early messages
SCENE_TABLE_KEYS = {
    "scene": sf.SCENE_KEYS, "rotor": sf.ROTOR_KEYS, "supports": sf.SUPPORT_KEYS,
    "balancer": sf.BALANCER_KEYS, "run": sf.RUN_KEYS, "initial": sf.INITIAL_KEYS,
    "dimensionless": sf.DIMENSIONLESS_KEYS,
    "drive": tuple(dict.fromkeys(sf.SPEED_KEYS + sf.TORQUE_KEYS + ("torque", "c1", "c2", "target_speed"))),
}
MAX_POINTS = 10_000_000  #: largest number of points accepted in one sweep


class SweepSpecError(ValueError):
    """A sweep file is invalid.  The message names the field, its value and what is expected."""


def _fmt(value: Any) -> str:
    return sf._fmt(value)


def _suggest(word: str, valid) -> str:
    close = difflib.get_close_matches(word, list(valid), n=1, cutoff=0.5)
    return f"did you mean {close[0]!r}? " if close else ""


def _is_number(v: Any) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))


def _number(name: str, v: Any, *, gt=None, ge=None) -> float:
    if not _is_number(v):
        raise SweepSpecError(f"{name} = {_fmt(v)}: must be a number, not {sf._kind(v)}")
    x = float(v)
    if not math.isfinite(x):
        raise SweepSpecError(f"{name} = {_fmt(v)}: must be finite")
    if gt is not None and not x > gt:
        raise SweepSpecError(f"{name} = {_fmt(v)}: must be > {_fmt(gt)}")
    if ge is not None and not x >= ge:
        raise SweepSpecError(f"{name} = {_fmt(v)}: must be >= {_fmt(ge)}")
    return x


def _integer(name: str, v: Any, minimum: int, maximum: int = MAX_POINTS) -> int:
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Integral):
        raise SweepSpecError(f"{name} = {_fmt(v)}: must be an integer >= {minimum}, "
                             f"not {sf._kind(v)}")
    if not minimum <= v <= maximum:
        raise SweepSpecError(f"{name} = {_fmt(v)}: must be an integer >= {minimum} and <= {maximum}")
    return int(v)


def _allow(table: Mapping, path: str, keys) -> None:
    for k in table:
        if k not in keys:
            raise SweepSpecError(f"unknown key {path}.{k}: {_suggest(k, keys)}"
                                 f"valid keys in [{path}]: {', '.join(keys)}")


@dataclass(frozen=True)
class Axis:
    """One swept parameter.

    Attributes
    ----------
    key : str
        Scene key (dotted), ``R_omega``/``speed`` or a bare dimensionless name.
    values : tuple of float
        The values taken, in the unit of that key (scene-file units: SI, degrees,
        rev/s; dimensionless for ``R_omega`` and the bare names).
    kind : str
        "grid", "values" or "random".
    """

    key: str
    values: tuple
    kind: str


@dataclass
class SweepSpec:
    """A validated sweep.

    Attributes
    ----------
    name : str
    base : dict
        The base scene as a TOML document (tables), paths already resolved.
    axes : list of Axis
    compute : tuple of str
        Subset of ("theory", "simulate").
    combine : str
        "product" or "zip".
    chunk_size : int or None
        Points per task; None: automatic.
    theory, simulate : dict
        Options of each computation.
    source : str
        Where the spec came from (path or "<string>").
    """

    name: str
    base: dict
    axes: list
    compute: tuple
    combine: str = "product"
    chunk_size: Optional[int] = None
    theory: dict = field(default_factory=dict)
    simulate: dict = field(default_factory=dict)
    source: str = "<string>"

    @property
    def columns(self) -> list:
        """Input column names, one per axis (the axis keys)."""
        return [a.key for a in self.axes]

    @property
    def n_points(self) -> int:
        if not self.axes:
            return 1
        if self.combine == "zip":
            return len(self.axes[0].values)
        return int(np.prod([len(a.values) for a in self.axes]))

    def points(self) -> np.ndarray:
        """All points, shape (n_points, n_axes), float; the last axis varies fastest."""
        if not self.axes:
            return np.zeros((1, 0))
        vals = [np.asarray(a.values, float) for a in self.axes]
        if self.combine == "zip":
            return np.column_stack(vals)
        grids = np.meshgrid(*vals, indexing="ij")
        return np.column_stack([g.ravel() for g in grids])

    def fingerprint(self) -> str:
        """Hash of everything but the axes' values: base scene, compute, options.

        Point ids are derived from it, so a changed base scene or option never
        reuses old results.
        """
        doc = {"base": self.base, "compute": list(self.compute), "theory": self.theory,
               "simulate": self.simulate, "keys": self.columns}
        text = json.dumps(doc, sort_keys=True, default=str, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()

    def point_ids(self, points: Optional[np.ndarray] = None) -> list:
        """Stable id of each point: 16 hex digits of sha256(fingerprint, input values)."""
        pts = self.points() if points is None else points
        fp = self.fingerprint()
        out = []
        for row in pts:
            text = fp + "|" + ",".join(repr(float(v)) for v in row)
            out.append(hashlib.sha256(text.encode()).hexdigest()[:16])
        return out

    def to_payload(self) -> dict:
        """Plain data (dicts, lists, floats) sent to workers: no code, no objects."""
        return {"base": self.base, "keys": self.columns, "compute": list(self.compute),
                "theory": dict(self.theory), "simulate": dict(self.simulate)}


# ---------------------------------------------------------------- axes
def _axis(i: int, t: Any, default_seed: Optional[int], base: dict) -> Axis:
    path = f"axis[{i}]"
    if not isinstance(t, Mapping):
        raise SweepSpecError(f"{path}: must be a table [[axis]], not {sf._kind(t)}")
    _allow(t, path, AXIS_KEYS)
    if "key" not in t:
        raise SweepSpecError(f"{path}.key: missing required key (a scene key such as "
                             f'"rotor.eccentricity", or "R_omega", "e0", ...)')
    key = t["key"]
    if not isinstance(key, str):
        raise SweepSpecError(f"{path}.key = {_fmt(key)}: must be a string")
    _check_key(f"{path}.key", key, base)
    modes = [m for m, ks in (("values", ("values",)), ("grid", ("start", "stop", "num")),
                             ("random", ("random",))) if any(k in t for k in ks)]
    if len(modes) != 1:
        raise SweepSpecError(f"{path}: give exactly one of values = [...], a grid (start, stop, "
                             f"num[, spacing]) or random = \"uniform\"|\"log-uniform\" (low, high, "
                             f"count[, seed]); got {' and '.join(modes) if modes else 'none'}")
    mode = modes[0]
    extra = {"values": ("spacing", "low", "high", "count", "seed", "start", "stop", "num", "random"),
             "grid": ("low", "high", "count", "seed", "values", "random"),
             "random": ("start", "stop", "num", "spacing", "values")}[mode]
    for k in extra:
        if k in t:
            raise SweepSpecError(f"{path}.{k} = {_fmt(t[k])}: not used by a {mode} axis")
    if mode == "values":
        vals = t["values"]
        if not isinstance(vals, list) or not vals:
            raise SweepSpecError(f"{path}.values = {_fmt(vals)}: must be a non-empty list of numbers")
        out = tuple(_number(f"{path}.values[{j}]", v) for j, v in enumerate(vals))
    elif mode == "grid":
        for k in ("start", "stop", "num"):
            if k not in t:
                raise SweepSpecError(f"{path}.{k}: missing required key of a grid axis "
                                     f"(start, stop, num[, spacing])")
        a = _number(f"{path}.start", t["start"])
        b = _number(f"{path}.stop", t["stop"])
        num = _integer(f"{path}.num", t["num"], 2)
        spacing = t.get("spacing", "linear")
        if spacing not in ("linear", "log"):
            raise SweepSpecError(f"{path}.spacing = {_fmt(spacing)}: must be \"linear\" or \"log\"")
        if spacing == "log":
            if not (a > 0 and b > 0):
                raise SweepSpecError(f"{path}.start, stop = {_fmt(a)}, {_fmt(b)}: a log grid needs "
                                     "start > 0 and stop > 0")
            out = tuple(float(v) for v in np.geomspace(a, b, num))
        else:
            out = tuple(float(v) for v in np.linspace(a, b, num))
    else:
        dist = t["random"]
        if dist not in ("uniform", "log-uniform"):
            raise SweepSpecError(f"{path}.random = {_fmt(dist)}: must be \"uniform\" or \"log-uniform\"")
        for k in ("low", "high", "count"):
            if k not in t:
                raise SweepSpecError(f"{path}.{k}: missing required key of a random axis "
                                     f"(low, high, count[, seed])")
        lo = _number(f"{path}.low", t["low"])
        hi = _number(f"{path}.high", t["high"])
        if not hi > lo:
            raise SweepSpecError(f"{path}.high = {_fmt(t['high'])}: must be > low = {_fmt(t['low'])}")
        count = _integer(f"{path}.count", t["count"], 1)
        seed = t.get("seed", default_seed)
        if seed is None:
            raise SweepSpecError(f"{path}.seed: missing; a random axis needs a seed (here or "
                                 "[sweep] seed) so that the sweep can be resumed and repeated")
        seed = _integer(f"{path}.seed", seed, 0, 2 ** 63 - 1)
        # a per-axis stream: the same seed on two axes still gives independent samples
        rng = np.random.default_rng([seed, i])
        if dist == "log-uniform":
            if not lo > 0:
                raise SweepSpecError(f"{path}.low = {_fmt(t['low'])}: log-uniform needs low > 0")
            out = tuple(float(v) for v in np.exp(rng.uniform(math.log(lo), math.log(hi), count)))
        else:
            out = tuple(float(v) for v in rng.uniform(lo, hi, count))
    return Axis(key, out, mode)


def _check_key(name: str, key: str, base: dict) -> None:
    """Reject keys that no point could use (unknown table or key)."""
    dimless = "dimensionless" in base
    if key in SPECIAL_KEYS:
        if "drive" not in base:
            raise SweepSpecError(f"{name} = {_fmt(key)}: the base scene has no [drive] table")
        return
    if "." not in key:
        if key not in DIMENSIONLESS_NAMES:
            valid = SPECIAL_KEYS[::2] + DIMENSIONLESS_NAMES
            raise SweepSpecError(f"{name} = {_fmt(key)}: {_suggest(key, valid)}not a dimensionless "
                                 f"parameter ({', '.join(valid)}) nor a dotted scene key "
                                 "such as \"rotor.eccentricity\"")
        if not dimless and key not in ("e0", "h", "H"):
            raise SweepSpecError(f"{name} = {_fmt(key)}: needs a [dimensionless] base scene (with a "
                                 "physical base scene only e0, h, H, R_omega, speed are converted); "
                                 "sweep the physical scene key instead")
        if not dimless and key == "h" and base.get("balancer", {}).get("type") != "balls":
            raise SweepSpecError(f"{name} = \"h\": converted to balancer.drag only for "
                                 "balancer.type = \"balls\"; sweep balancer.drag instead")
        return
    table, _, rest = key.partition(".")
    if table not in sf.TABLES or table == "perturbation":
        raise SweepSpecError(f"{name} = {_fmt(key)}: unknown scene table [{table}]: "
                             f"{_suggest(table, sf.TABLES)}valid tables: "
                             f"{', '.join(t for t in sf.TABLES if t != 'perturbation')}")
    first = rest.split(".")[0]
    known = SCENE_TABLE_KEYS.get(table)
    if known is not None and first not in known:
        raise SweepSpecError(f"{name} = {_fmt(key)}: unknown key {table}.{first}: "
                             f"{_suggest(first, known)}valid keys in [{table}]: {', '.join(known)}")
    if table == "dimensionless" and not dimless:
        raise SweepSpecError(f"{name} = {_fmt(key)}: the base scene has no [dimensionless] table")
    if table in ("rotor", "supports", "balancer") and dimless:
        raise SweepSpecError(f"{name} = {_fmt(key)}: the base scene is [dimensionless]; it has no "
                             f"[{table}] table (sweep dimensionless.* instead)")


# ---------------------------------------------------------------- point scenes
def _set(doc: dict, dotted: str, value: Any) -> None:
    parts = dotted.split(".")
    t = doc
    for p in parts[:-1]:
        t = t.setdefault(p, {})
        if not isinstance(t, dict):
            raise SceneError(f"{dotted}: {p} is not a table in the base scene")
    t[parts[-1]] = value


def _natural_frequency(doc: dict) -> float:
    """omega_1 [rad/s] of a scene document (before validation)."""
    if "dimensionless" in doc:
        return TWO_PI * float(doc["dimensionless"].get("natural_frequency", 1.0 / TWO_PI))
    s, r, b = doc.get("supports", {}), doc.get("rotor", {}), doc.get("balancer", {})
    c = float(s.get("stiffness", s.get("stiffness_x", math.nan)))
    return math.sqrt(c / (float(r.get("mass", math.nan)) + _weights_mass(b)))


def _per_weight(b: dict, key: str) -> np.ndarray:
    n = int(b.get("count", 0))
    v = b.get(key, 0.0)
    return np.asarray(v, float) if isinstance(v, list) else np.full(n, float(v))


def _weights_mass(b: dict) -> float:
    if b.get("type", "none") == "none":
        return 0.0
    return float(np.sum(_per_weight(b, "mass")))


def _set_speed(doc: dict, speed_rev_s: float, key: str) -> None:
    d = doc["drive"]
    if d.get("type") == "torque":
        d["target_speed"] = speed_rev_s
        return
    w1 = _natural_frequency(doc)
    if "programme_dimensionless" in d:
        prog, target = d["programme_dimensionless"], speed_rev_s * TWO_PI / w1
    else:
        prog, target = d.get("programme"), speed_rev_s
    if not isinstance(prog, list) or not prog:
        raise SceneError(f"{key}: the base scene's drive has no programme to scale")
    last = float(prog[-1][1])
    if len(prog) == 1 or last == 0.0:
        if len(prog) > 1:
            raise SceneError(f"{key}: the base programme ends at speed 0; cannot scale it to "
                             f"{target:g}")
        new = [[float(prog[0][0]), target]]
    else:
        new = [[float(t), float(v) * target / last] for t, v in prog]
    if "programme_dimensionless" in d:
        d["programme_dimensionless"] = new
    else:
        d["programme"] = new


def point_scene_dict(base: dict, keys, values) -> dict:
    """The scene document of one point: the base with the axes' values applied.

    Parameters
    ----------
    base : dict
        Base scene document (TOML tables).
    keys : sequence of str
        Axis keys (see the module notes).
    values : sequence of float
        One value per key, in that key's unit.

    Returns
    -------
    dict
        A new document; validate it with :func:`stand.scene_file.parse_scene`.

    Raises
    ------
    SceneError
        A value cannot be applied (e.g. scaling a programme that ends at 0).
    """
    doc = copy.deepcopy(base)
    speed = None
    for key, v in zip(keys, values):
        v = float(v)
        if key in ("n", "dimensionless.n", "balancer.count") or key.endswith(".count"):
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
        r, b, s = doc["rotor"], doc.get("balancer", {}), doc["supports"]
        w1 = _natural_frequency(doc)
        if "e0" in phys:
            S = float(np.sum(_per_weight(b, "mass") * _per_weight(b, "radius")))
            r["eccentricity"] = phys["e0"] * S / float(r["mass"])
        if "H" in phys:
            Ms = float(r["mass"]) + _weights_mass(b)
            for k in ("damping_x", "damping_y"):
                s.pop(k, None)
            s["damping"] = phys["H"] * w1 * Ms
        if "h" in phys:
            m = _per_weight(b, "mass")
            b["drag"] = [float(x) for x in phys["h"] * w1 * m]
    if speed is not None:
        key, v = speed
        rev_s = v * _natural_frequency(doc) / TWO_PI if key in ("R_omega", "dimensionless.R_omega") else v
        _set_speed(doc, rev_s, key)
    return doc


# ---------------------------------------------------------------- reading
def _options(data: Mapping, table: str, keys) -> dict:
    t = data.get(table, {})
    if not isinstance(t, Mapping):
        raise SweepSpecError(f"[{table}]: must be a table, not {sf._kind(t)}")
    _allow(t, table, keys)
    out = {}
    if table == "theory":
        for k in ("side", "critical_speeds"):
            if k in t:
                if not isinstance(t[k], bool):
                    raise SweepSpecError(f"theory.{k} = {_fmt(t[k])}: must be true or false")
                out[k] = t[k]
        out.setdefault("side", False)
        out.setdefault("critical_speeds", True)
        out["R_max"] = _number("theory.R_max", t["R_max"], gt=1.0) if "R_max" in t else 1000.0
    else:
        out["window"] = _number("simulate.window", t.get("window", 0.2), gt=0)
        if out["window"] > 1:
            raise SweepSpecError(f"simulate.window = {_fmt(t['window'])}: must be <= 1 (a fraction "
                                 "of the run)")
        out["sync_tol"] = _number("simulate.sync_tol", t.get("sync_tol", 1e-3), gt=0)
        out["balance_tol"] = _number("simulate.balance_tol", t.get("balance_tol", 1e-2), gt=0)
        method = t.get("method")
        if method is not None:
            from ..scene import METHODS
            if method not in METHODS:
                raise SweepSpecError(f"simulate.method = {_fmt(method)}: {_suggest(str(method), METHODS)}"
                                     f"must be one of {', '.join(METHODS)}")
            out["method"] = method
    return out


def parse_sweep(data: Mapping, base_dir: Union[str, Path, None] = None,
                source: str = "<string>") -> SweepSpec:
    """Validate a parsed SWEEP.toml document.

    Parameters
    ----------
    data : mapping
        As returned by ``tomllib.loads``.
    base_dir : path, optional
        Directory against which ``base.scene`` is resolved (that of the sweep
        file); default the current directory.
    source : str
        Label for messages.

    Returns
    -------
    SweepSpec

    Raises
    ------
    SweepSpecError
        The message names the offending field.
    """
    if not isinstance(data, Mapping):
        raise SweepSpecError("a sweep file must be a table of tables")
    for k in data:
        if k not in SWEEP_TABLES:
            raise SweepSpecError(f"unknown table [{k}]: {_suggest(k, SWEEP_TABLES)}valid tables: "
                                 f"{', '.join(SWEEP_TABLES)}")
    sw = data.get("sweep", {})
    if not isinstance(sw, Mapping):
        raise SweepSpecError(f"[sweep]: must be a table, not {sf._kind(sw)}")
    _allow(sw, "sweep", SWEEP_KEYS)
    name = sw.get("name", Path(source).stem if source != "<string>" else "sweep")
    if not isinstance(name, str):
        raise SweepSpecError(f"sweep.name = {_fmt(name)}: must be a string")
    compute = sw.get("compute", ["theory"])
    if isinstance(compute, str):
        compute = [compute]
    if not isinstance(compute, list) or not compute:
        raise SweepSpecError(f"sweep.compute = {_fmt(compute)}: must be a non-empty list of "
                             "\"theory\", \"simulate\"")
    for j, c in enumerate(compute):
        if c not in COMPUTE:
            raise SweepSpecError(f"sweep.compute[{j}] = {_fmt(c)}: {_suggest(str(c), COMPUTE)}"
                                 "must be \"theory\" or \"simulate\"")
    compute = tuple(c for c in COMPUTE if c in compute)
    combine = sw.get("combine", "product")
    if combine not in ("product", "zip"):
        raise SweepSpecError(f"sweep.combine = {_fmt(combine)}: must be \"product\" or \"zip\"")
    chunk = _integer("sweep.chunk_size", sw["chunk_size"], 1, 100_000) if "chunk_size" in sw else None
    seed = _integer("sweep.seed", sw["seed"], 0, 2 ** 63 - 1) if "seed" in sw else None

    # --- base scene
    if "base" not in data:
        raise SweepSpecError("missing table [base] (the base scene: base.scene = \"path.toml\" "
                             "or inline tables [base.rotor], [base.drive], ...)")
    b = data["base"]
    if not isinstance(b, Mapping):
        raise SweepSpecError(f"[base]: must be a table, not {sf._kind(b)}")
    if "scene" in b and not isinstance(b["scene"], Mapping):
        path = b["scene"]
        if not isinstance(path, str):
            raise SweepSpecError(f"base.scene = {_fmt(path)}: must be a path (string)")
        inline = [k for k in b if k != "scene"]
        if inline:
            raise SweepSpecError(f"base.scene = {_fmt(path)} and inline table [base.{inline[0]}] are "
                                 "both given: use either a path or inline tables")
        p = Path(path)
        if not p.is_absolute() and base_dir is not None:
            p = Path(base_dir) / p
        try:
            text = p.read_text(encoding="utf-8")
        except OSError as exc:
            raise SweepSpecError(f"base.scene = {_fmt(path)}: cannot read {p}: "
                                 f"{exc.strerror or exc}") from None
        try:
            base = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise SweepSpecError(f"base.scene = {_fmt(path)}: TOML syntax error: {exc}") from None
    else:
        base = copy.deepcopy(dict(b))
    try:
        sf.parse_scene(base)
    except SceneError as exc:
        raise SweepSpecError(f"[base] scene: {exc}") from None

    # --- axes
    axes_raw = data.get("axis", [])
    if not isinstance(axes_raw, list):
        raise SweepSpecError("axis: must be an array of tables [[axis]]")
    axes = [_axis(i, t, seed, base) for i, t in enumerate(axes_raw)]
    keys = [a.key for a in axes]
    for i, k in enumerate(keys):
        if k in keys[:i]:
            raise SweepSpecError(f"axis[{i}].key = {_fmt(k)}: the same key as axis[{keys.index(k)}]")
    speed_axes = [k for k in keys if k in SPECIAL_KEYS]
    if len(speed_axes) > 1:
        raise SweepSpecError(f"axis keys {', '.join(map(repr, speed_axes))}: give at most one speed axis")
    if combine == "zip" and len({len(a.values) for a in axes}) > 1:
        raise SweepSpecError("sweep.combine = \"zip\": every axis needs the same number of values "
                             f"(got {', '.join(str(len(a.values)) for a in axes)})")
    spec = SweepSpec(name=name, base=base, axes=axes, compute=compute, combine=combine,
                     chunk_size=chunk, theory=_options(data, "theory", THEORY_KEYS),
                     simulate=_options(data, "simulate", SIMULATE_KEYS), source=source)
    if spec.n_points > MAX_POINTS:
        raise SweepSpecError(f"axis: {spec.n_points} points, more than {MAX_POINTS}")
    return spec


def load_sweep(source: Union[str, Path, Mapping]) -> SweepSpec:
    """Read a SWEEP.toml file (a path), TOML text (a str with a newline) or a parsed dict.

    Raises
    ------
    SweepSpecError
        File missing, TOML syntax error, or invalid content (message starts
        with the file name).
    """
    if isinstance(source, Mapping):
        return parse_sweep(source)
    if isinstance(source, str) and "\n" in source:
        text, label, base_dir = source, "<string>", None
    else:
        p = Path(source)
        label, base_dir = str(p), p.resolve().parent
        try:
            text = p.read_text(encoding="utf-8")
        except FileNotFoundError:
            raise SweepSpecError(f"sweep file not found: {p}") from None
        except OSError as exc:
            raise SweepSpecError(f"cannot read sweep file {p}: {exc.strerror}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SweepSpecError(f"{label}: TOML syntax error: {exc}") from None
    try:
        return parse_sweep(data, base_dir, source=label)
    except SweepSpecError as exc:
        if label != "<string>":
            raise SweepSpecError(f"{label}: {exc}") from None
        raise
