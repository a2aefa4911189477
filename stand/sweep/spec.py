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
    window = 0.2                 # fraction of the run classified (stand.analysis.regime.classify)

Every problem raises :class:`SweepSpecError` naming the field, its value and
what is expected, e.g. ``axis[1].num = 1: must be an integer >= 2``.  Nothing
is evaluated (no ``eval``) and nothing is unpickled: the file is TOML only.

The base scene may be any scene kind (:attr:`stand.scene.model.Scene.kind`): the
planar rotor of chapter 5, any rotor of the family (``[structure]``) or a book
weight model (``[weight_model]``); what each kind accepts is in
:mod:`stand.sweep.keys`.

Axis keys
---------
* Dotted scene keys, ``table.key`` (``rotor.eccentricity``,
  ``dimensionless.e0``, ``supports.damping``, ``drive.coast_down.start``,
  ``structure.rotor_stiffness``, ``weights[0].drag``, ``weight_model.h`` ...):
  the value replaces that key of the base scene, in the scene file's units.
* ``R_omega`` (alias ``dimensionless.R_omega``, planar base scenes): the held
  rotor speed in units of omega_1.  For a speed drive the programme's speeds are scaled so that its
  last point equals it (a one-point programme is a constant speed); for a
  torque drive it sets ``drive.target_speed``.
* ``speed`` (alias ``drive.speed``): the same in rev/s (planar and
  ``[structure]`` base scenes).
* Bare dimensionless names ``n``, ``Rt``, ``h``, ``H``, ``e0``, ``R_omega2``,
  ``unbalance_angle`` (deg, planar base scenes): ``dimensionless.<name>`` for a ``[dimensionless]``
  base scene.  For a physical base scene ``e0`` sets ``rotor.eccentricity`` =
  e0 S / M (S the balancer capacity, M the rotor mass), ``H`` sets
  ``supports.damping`` = H omega_1 M_Sigma and ``h`` (balls) sets
  ``balancer.drag`` = h omega_1 m; the others need a ``[dimensionless]`` base.
"""
from __future__ import annotations

import copy
import hashlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Optional, Union

import numpy as np

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

from stand.scene import parse as sf
from stand.io.jsonable import dumps
from stand.io.tomlfile import read_toml
from stand.sweep.axes import AXIS_KEYS, Axis, read_axis  # noqa: F401  (AXIS_KEYS re-exported)
from stand.sweep.checks import (MAX_POINTS, SweepSpecError, _allow, _fmt, _integer, _number, _suggest, _table,
                     spec_errors)
from stand.sweep.keys import (DIMENSIONLESS_NAMES, SCENE_TABLE_KEYS, SPECIAL_KEYS,  # noqa: F401
                   TWO_PI, point_scene_dict)

__all__ = ["SweepSpecError", "Axis", "SweepSpec", "load_sweep", "parse_sweep", "point_scene_dict",
           "COMPUTE", "SPECIAL_KEYS", "DIMENSIONLESS_NAMES"]

COMPUTE = ("theory", "simulate")
SWEEP_TABLES = ("sweep", "base", "axis", "theory", "simulate")
SWEEP_KEYS = ("name", "description", "compute", "combine", "chunk_size", "seed")
THEORY_KEYS = ("side", "critical_speeds", "R_max")
SIMULATE_KEYS = ("window", "sync_tol", "balance_tol", "method")


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
    #: kind of the base scene: "planar", "rotor" or "book" (:attr:`stand.scene.model.Scene.kind`)
    kind: str = "planar"

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
        text = dumps(doc, sort_keys=True, separators=(",", ":"))
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


# ---------------------------------------------------------------- reading
def _options(data: Mapping, table: str, keys) -> dict:
    t = _table(table, data.get(table, {}))
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
        out["R_max"] = (_number("theory.R_max", t["R_max"], "units of omega_1", gt=1.0)
                        if "R_max" in t else 1000.0)
        return out
    out["window"] = _number("simulate.window", t.get("window", 0.2), "fraction of the run", gt=0)
    if out["window"] > 1:
        raise SweepSpecError(f"simulate.window = {_fmt(t['window'])}: must be <= 1 (a fraction "
                             "of the run)")
    out["sync_tol"] = _number("simulate.sync_tol", t.get("sync_tol", 1e-3), "relative", gt=0)
    out["balance_tol"] = _number("simulate.balance_tol", t.get("balance_tol", 1e-2),
                                 "fraction of the capacity", gt=0)
    method = t.get("method")
    if method is not None:
        from stand.scene.model import METHODS
        if method not in METHODS:
            raise SweepSpecError(f"simulate.method = {_fmt(method)}: {_suggest(str(method), METHODS)}"
                                 f"must be one of {', '.join(METHODS)}")
        out["method"] = method
    return out


def _compute(sw: Mapping) -> tuple:
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
    return tuple(c for c in COMPUTE if c in compute)


def _base(data: Mapping, base_dir: Union[str, Path, None]) -> tuple:
    """(document, kind) of the base scene: a path (read and validated by
    :func:`stand.scene.parse.load_scene`) or inline tables (:func:`stand.scene.parse.parse`)."""
    if "base" not in data:
        raise SweepSpecError("missing table [base] (the base scene: base.scene = \"path.toml\" "
                             "or inline tables [base.rotor], [base.drive], ...)")
    b = _table("base", data["base"])
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
        with spec_errors(f"base.scene = {_fmt(path)}: "):
            scene = sf.load_scene(p)
        return tomllib.loads(scene.text), scene.kind
    base = copy.deepcopy(dict(b))
    with spec_errors("[base] scene: "):
        return base, sf.parse(base).kind


def _check_compute(compute: tuple, theory: dict, base: dict, kind: str) -> None:
    """What the compute list asks of the base scene's kind."""
    bodies = [w.get("type") for w in base.get("weights", []) if isinstance(w, Mapping)
              and w.get("type", "balls") != "balls"]
    if "theory" in compute and theory.get("side") and bodies:
        raise SweepSpecError(f"theory.side = true: the side motions of chapter 5 are those of "
                             f"balls; the base scene carries body weights ({', '.join(bodies)})")
    if "theory" not in compute or kind == "planar":
        return
    if kind == "book":
        raise SweepSpecError(f"sweep.compute = \"theory\": the base scene is a [weight_model] scene "
                             f"(book model {base['weight_model'].get('type')!r}); its theory "
                             "(stand.theory) is a document of steady motions, not sweep columns: "
                             "use compute = [\"simulate\"]")
    if theory.get("side"):
        raise SweepSpecError("theory.side = true: the side motions of chapter 5 need a planar base "
                             "scene; the base scene is a [structure] scene")


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
    sw = _table("sweep", data.get("sweep", {}))
    _allow(sw, "sweep", SWEEP_KEYS)
    name = sw.get("name", Path(source).stem if source != "<string>" else "sweep")
    if not isinstance(name, str):
        raise SweepSpecError(f"sweep.name = {_fmt(name)}: must be a string")
    compute = _compute(sw)
    combine = sw.get("combine", "product")
    if combine not in ("product", "zip"):
        raise SweepSpecError(f"sweep.combine = {_fmt(combine)}: must be \"product\" or \"zip\"")
    chunk = _integer("sweep.chunk_size", sw["chunk_size"], 1, 100_000) if "chunk_size" in sw else None
    seed = _integer("sweep.seed", sw["seed"], 0, 2 ** 63 - 1) if "seed" in sw else None
    base, kind = _base(data, base_dir)

    # --- axes
    axes_raw = data.get("axis", [])
    if not isinstance(axes_raw, list):
        raise SweepSpecError("axis: must be an array of tables [[axis]]")
    axes = [read_axis(i, t, seed, base) for i, t in enumerate(axes_raw)]
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
    theory = _options(data, "theory", THEORY_KEYS)
    _check_compute(compute, theory, base, kind)
    spec = SweepSpec(name=name, base=base, axes=axes, compute=compute, combine=combine,
                     chunk_size=chunk, theory=theory,
                     simulate=_options(data, "simulate", SIMULATE_KEYS), source=source, kind=kind)
    if spec.n_points > MAX_POINTS:
        raise SweepSpecError(f"axis: {spec.n_points} points, more than {MAX_POINTS}")
    return spec


def load_sweep(source: Union[str, Path, Mapping]) -> SweepSpec:
    """Read a SWEEP.toml file (a path), TOML text (a str with a newline) or a parsed dict
    (the file through :func:`stand.io.tomlfile.read_toml`).

    Parameters
    ----------
    source : path, str or mapping

    Returns
    -------
    SweepSpec
        Validated by :func:`parse_sweep`, ``base.scene`` resolved against the
        file's directory.

    Raises
    ------
    SweepSpecError
        File missing, TOML syntax error, or invalid content (message starts
        with the file name).
    """
    if isinstance(source, Mapping):
        return parse_sweep(source)
    text = isinstance(source, str) and "\n" in source
    if not text and not Path(source).exists():
        raise SweepSpecError(f"sweep file not found: {source}")
    data, _, label = read_toml(source, "sweep file", SweepSpecError)
    try:
        return parse_sweep(data, None if text else Path(source).resolve().parent,
                           source="<string>" if text else str(source))
    except SweepSpecError as exc:
        if label:
            raise SweepSpecError(f"{label}{exc}") from None
        raise
