"""Recordings: one HDF5 layout for every scene, written atomically, read back with checks.

Layout (format_version 2; all arrays float64, SI units, one row per sample)::

    /time                          (N,)   s      sample times (an HDF5 dimension scale)
    /planes/<plane>/x, .../y       (N,)   m      fixed-frame translation of each plane
    /shaft/x, /shaft/y             (N,)   m      links to the main (instrumented or only) plane
    /rotor/angle, /rotor/speed     (N,)   rad, rad/s
    /weights/<weight>/<coord>      (N,)          each weight's coordinates (ball1/angle [rad], ...)
    /coordinates/...               (N,)          structure coordinates, a book model's state
    /truth/residual/<plane>        (N, 2) kg*m   total unbalance of a plane, rotor frame
    /instruments/<name>/...                      what the instruments output (stand.instruments)
    /truth/<name>/...                            their ground truth

Every dataset carries ``units`` and ``description``; every (N, ...) dataset
has ``time`` attached as its first dimension's scale, so h5py, h5netcdf and
xarray users see the time axis.  Root attributes: ``format`` =
:data:`FORMAT`, ``format_version``, ``version`` (``stand.__version__``),
``created`` (ISO 8601, UTC), ``scene_name``, ``scene`` (the scene's TOML
text), ``structure`` (:attr:`stand.scene.model.Scene.structure_type`),
``main_plane``, ``weight_planes`` (JSON: weight -> plane), ``solver`` (JSON of
:class:`stand.integrate.result.SolverStats`), plus any ``extra_attrs``.

:func:`read_recording` (``stand.read``) returns a :class:`Recording` with the
fields of :class:`stand.integrate.result.Run`.  It also opens format_version 1 files
(``weights/angle`` (N, n) matrices), the rotor-family and weight-model
files written before the one layout, and files of other tools (a real
stand, a data logger) holding at least ``time``, ``shaft/x`` and ``shaft/y``;
what was filled in is listed in :attr:`Recording.notes`.
"""
from __future__ import annotations

import datetime as _dt
import io
import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping, Optional, Union

import h5py
import numpy as np

from stand.io.atomic import atomic_path, check_output_path
from stand.io.jsonable import to_jsonable
from stand.integrate.result import Run, SolverStats

if TYPE_CHECKING:  # pragma: no cover
    from stand.scene.model import Scene

__all__ = ["FORMAT", "FORMAT_VERSION", "DATASETS", "Recording", "RecordingError",
           "read_recording", "write_recording", "check_output_path", "pandas_table_key",
           "read_pandas_table"]

FORMAT = "autobalancer-stand recording"
FORMAT_VERSION = 2
#: arrays with more samples than this are stored chunked and gzip-compressed
COMPRESS_ABOVE = 1000
GZIP_LEVEL = 4
#: target size of one chunk [bytes]
CHUNK_BYTES = 256 * 1024
#: recordings up to this size are assembled in memory, then written in one piece [bytes]
IN_MEMORY_BYTES = 256 * 1024 * 1024

#: the fixed datasets: path -> (Recording field, units, description)
DATASETS = {
    "time": ("t", "s", "sample time"),
    "shaft/x": ("x", "m", "main plane's translation along the fixed X axis"),
    "shaft/y": ("y", "m", "main plane's translation along the fixed Y axis"),
    "rotor/angle": ("rotor_angle", "rad", "angle of the rotor's reference mark (keyphasor)"),
    "rotor/speed": ("rotor_speed", "rad/s", "rotor angular speed"),
}
REQUIRED = ("time", "shaft/x", "shaft/y")
RESERVED_ATTRS = ("scene", "scene_name", "solver", "version", "format", "format_version",
                  "created", "structure", "main_plane", "weight_planes", "run_notes")
#: format_version 1 weight matrices (N, n): path -> coordinate
V1_WEIGHTS = {"weights/angle": "angle", "weights/speed": "speed"}


class RecordingError(ValueError):
    """A file is not a readable recording.  The message names the file and the dataset."""


# ---------------------------------------------------------------- writing
def _attr_value(key: str, value: Any) -> Any:
    """An ``extra_attrs`` value as HDF5 can store it; mappings become JSON text."""
    if value is None:
        raise ValueError(f"extra_attrs[{key!r}] = None: HDF5 attributes cannot be None")
    if isinstance(value, Mapping) or (isinstance(value, (list, tuple))
                                      and any(isinstance(v, str) for v in value)):
        return json.dumps(to_jsonable(value), default=str)
    if isinstance(value, os.PathLike):
        return str(value)
    return value


def _storage_options(a: np.ndarray) -> dict:
    """Chunked gzip (level 4, shuffle) for long, non-empty arrays; contiguous otherwise."""
    if a.shape[0] <= COMPRESS_ABOVE or a.size == 0:
        return {}
    cols = int(np.prod(a.shape[1:], dtype=np.int64)) if a.ndim > 1 else 1
    rows = max(1, min(a.shape[0], CHUNK_BYTES // (8 * cols)))
    return {"chunks": (rows,) + a.shape[1:], "compression": "gzip",
            "compression_opts": GZIP_LEVEL, "shuffle": True}


def _describe(key: str) -> str:
    if key in DATASETS:
        return DATASETS[key][2]
    parts = key.split("/")
    if parts[0] == "planes":
        return f"plane {parts[1]}: translation along the fixed {parts[2].upper()} axis"
    if parts[0] == "weights":
        return f"weight {parts[1]}: {parts[2].replace('_', ' ')}"
    if parts[0] == "truth" and parts[1] == "residual":
        return f"total unbalance in plane {parts[2]} (rotor + weights), rotor frame x, y"
    return key


def _check_arrays(run: Run) -> dict:
    """``{path: (float64 array, units)}`` for every channel and truth array, shapes checked."""
    t = np.asarray(run.t, dtype=np.float64)
    if t.ndim != 1:
        raise ValueError(f"run.t: shape {t.shape}, expected (N,)")
    N = t.shape[0]
    data = {}
    for key, (a, units) in {**run.channels(),
                            **{f"truth/{k}": v for k, v in run.truth.items()}}.items():
        a = np.asarray(a, dtype=np.float64)
        if a.ndim == 0 or a.shape[0] != N:
            raise ValueError(f"run channel {key!r}: shape {a.shape}, expected ({N}, ...) "
                             f"(one row per sample of run.t)")
        data[key] = (a, str(units))
    if run.main_plane not in run.planes:
        raise ValueError(f"run.main_plane = {run.main_plane!r}: not one of the planes "
                         f"{', '.join(run.planes)}")
    return data


def write_recording(run: Run, path: Union[str, os.PathLike], *,
                    extra_attrs: Optional[Mapping[str, Any]] = None,
                    writer: Optional[Callable[["h5py.File"], None]] = None) -> Path:
    """Write one run to an HDF5 file, atomically (:func:`stand.io.atomic.atomic_path`).

    If anything fails, the temporary file is removed, the exception propagates,
    and a file that already existed at ``path`` is left untouched.

    Parameters
    ----------
    run : stand.integrate.result.Run
        Any scene's run (or a :class:`Recording`).
    path : str or os.PathLike
        Target file (conventionally ``*.h5``).  Its directory must exist.
    writer : callable, optional
        ``writer(h5file)`` is called with the open temporary file after the
        core datasets are written (the instruments stream their frames, truth
        and settings through it); a failure there discards the whole file.
    extra_attrs : mapping, optional
        Additional root attributes (str, numbers, arrays; mappings are stored
        as JSON text).  The reserved names (:data:`RESERVED_ATTRS`) cannot be
        overridden.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    FileNotFoundError
        The target's directory does not exist (the message names it).
    ValueError
        The run's arrays have inconsistent shapes, or ``extra_attrs`` uses a
        reserved name or holds ``None``.
    """
    from stand import __version__

    path = check_output_path(path, "recording")
    extra = dict(extra_attrs or {})
    clash = sorted(set(extra) & set(RESERVED_ATTRS))
    if clash:
        raise ValueError(f"extra_attrs: {', '.join(map(repr, clash))} reserved for the "
                         f"recording's own metadata ({', '.join(RESERVED_ATTRS)})")
    extra = {str(k): _attr_value(str(k), v) for k, v in extra.items()}
    data = _check_arrays(run)
    scene = run.scene
    stats = run.stats
    root = {
        "format": FORMAT,
        "format_version": np.int64(FORMAT_VERSION),
        "version": __version__,
        "created": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "scene_name": str(getattr(scene, "name", "") or ""),
        "scene": str(getattr(scene, "text", "") or getattr(run, "scene_text", "") or ""),
        "structure": str(getattr(scene, "structure_type", "") or ""),
        "main_plane": run.main_plane,
        "run_notes": json.dumps(list(run.notes)),
        "weight_planes": json.dumps(run.weight_planes),
        "solver": json.dumps(to_jsonable(dict(stats or {}))),
    }
    estimate = sum(a.nbytes for a, _ in data.values()) + getattr(writer, "estimated_bytes",
                                                                 0 if writer is None else np.inf)
    with atomic_path(path, suffix=".h5.tmp") as tmp:
        # up to IN_MEMORY_BYTES the file is assembled in memory and then written with one plain
        # write: a full disk or a file-size limit is then a clean OSError, not a failure inside
        # the HDF5 library; larger files (long videos) are streamed to the temporary file
        target = io.BytesIO() if estimate <= IN_MEMORY_BYTES else tmp
        with h5py.File(target, "w") as f:
            for key, value in {**root, **extra}.items():
                f.attrs[key] = value
            for key, (a, units) in data.items():
                ds = f.create_dataset(key, data=a, dtype=np.float64, **_storage_options(a))
                ds.attrs["units"] = units
                ds.attrs["description"] = _describe(key)
            for axis in ("x", "y"):
                f[f"shaft/{axis}"] = h5py.SoftLink(f"/planes/{run.main_plane}/{axis}")
            f.require_group("weights")
            time = f["time"]
            time.make_scale("time")
            for key in data:
                if key != "time":
                    f[key].dims[0].attach_scale(time)
            if writer is not None:
                writer(f)  # instruments: frames streamed in, truth, settings
        if target is not tmp:
            with open(tmp, "wb") as fh:
                fh.write(target.getbuffer())
    return path


# ---------------------------------------------------------------- reading
def _freeze(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


@dataclass(eq=False, repr=False)
class Recording(Run):
    """One recorded run, as read by :func:`read_recording`: the fields of
    :class:`stand.integrate.result.Run` (arrays read-only) plus what the file says of itself.

    Attributes
    ----------
    scene : stand.scene.model.Scene or None
        The recorded scene, parsed from its stored text (None when the file has
        none or it is not readable; the reason is in ``notes``).
    scene_text : str
        The scene's TOML text ("" if the file has none).
    solver : dict
        Solver statistics as stored (``stats`` holds them as a SolverStats).
    units : dict
        Field name (``"t"``, ``"x"``, ...) -> units string as stored.
    version : str
        ``stand.__version__`` of the writer ("" if unknown).
    attrs : dict
        All root attributes, decoded to Python types.
    path : str
        The file read.
    notes : tuple of str
        What was missing or unusual (a dataset filled with NaN, units that
        differ from the SI default, an older layout); empty for the stand's files.
    """

    scene_text: str = ""
    solver: dict = field(default_factory=dict)
    units: dict = field(default_factory=dict)
    version: str = ""
    attrs: dict = field(default_factory=dict)
    path: str = ""

    @property
    def n_weights(self) -> int:
        """Number of balls / pendulums n (columns of ``weight_angle``)."""
        return int(self.weight_angle.shape[1])

    @property
    def format_version(self) -> int:
        v = self.attrs.get("format_version", 0)
        return int(v) if isinstance(v, (int, float)) else 0

    def __repr__(self) -> str:
        name = self.attrs.get("scene_name", "")
        return (f"Recording({self.path!r}, scene_name={name!r}, samples={len(self)}, "
                f"planes={list(self.planes)}, weights={self.n_weights})")

    def has(self, key: str) -> bool:
        """True when the file holds a dataset ``key`` (e.g. ``"instruments/screen/frames"``)."""
        with h5py.File(self.path, "r") as f:
            return isinstance(f.get(key), h5py.Dataset)

    def dataset(self, key: str, index=()) -> np.ndarray:
        """Read dataset ``key`` (or ``index`` of it, e.g. one frame) from the file, on demand.

        Raises
        ------
        RecordingError
            No such dataset (the message names it), or it cannot be read.
        """
        try:
            with h5py.File(self.path, "r") as f:
                obj = f.get(key)
                if not isinstance(obj, h5py.Dataset):
                    raise RecordingError(f"{self.path}: no dataset {key!r}")
                return obj[index]
        except (OSError, ValueError, IndexError) as exc:
            if isinstance(exc, RecordingError):
                raise
            raise RecordingError(f"{self.path}: cannot read {key!r}{'' if index == () else f'[{index}]'}: "
                                 f"{exc}") from None

    def dataset_attrs(self, key: str) -> dict:
        """The attributes of dataset or group ``key`` (empty if absent), decoded."""
        with h5py.File(self.path, "r") as f:
            obj = f.get(key)
            return {} if obj is None else {k: _decode(v) for k, v in obj.attrs.items()}

    def members(self, key: str) -> list:
        """Names of the members of group ``key`` (empty if absent or not a group)."""
        with h5py.File(self.path, "r") as f:
            obj = f.get(key)
            return list(obj.keys()) if isinstance(obj, h5py.Group) else []

    def shape(self, key: str) -> Optional[tuple]:
        """Shape of dataset ``key``, or None if the file has no such dataset."""
        with h5py.File(self.path, "r") as f:
            obj = f.get(key)
            return tuple(obj.shape) if isinstance(obj, h5py.Dataset) else None


def _decode(value: Any) -> Any:
    """An HDF5 attribute value as a plain Python value."""
    if isinstance(value, bytes):
        return value.decode("utf-8", errors="replace")
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "OSU":
            return [_decode(v) for v in value.tolist()]
        return value
    if isinstance(value, np.generic):
        return value.item()
    return value


def _read_dataset(f: "h5py.File", key: str, label: str, N: Optional[int],
                  ndim: int = 1) -> np.ndarray:
    obj = f.get(key)
    if not isinstance(obj, h5py.Dataset):
        kind = "a group" if isinstance(obj, h5py.Group) else type(obj).__name__
        raise RecordingError(f"{label}: '{key}' is {kind}, not a dataset")
    if obj.dtype.kind not in "fiu":
        raise RecordingError(f"{label}: dataset '{key}' has dtype {obj.dtype}, expected "
                             f"a numeric array")
    try:
        a = np.asarray(obj[()], dtype=np.float64)
    except (OSError, RuntimeError, ValueError, KeyError) as exc:
        raise RecordingError(f"{label}: cannot read dataset '{key}' (file truncated or "
                             f"corrupt?): {exc}") from None
    if ndim == 2 and a.ndim == 1:
        a = a[:, None]  # one weight stored as (N,)
    if a.ndim != ndim:
        want = "(N,)" if ndim == 1 else "(N, n)"
        raise RecordingError(f"{label}: dataset '{key}' has shape {a.shape}, expected {want}")
    if N is not None and a.shape[0] != N:
        raise RecordingError(f"{label}: dataset '{key}' has shape {a.shape}: its length "
                             f"{a.shape[0]} differs from len(time) = {N}")
    return a


def _units(f: "h5py.File", key: str, default: str, notes: list) -> str:
    u = _decode(f[key].attrs.get("units", None))
    if u is None:
        notes.append(f"{key}: no 'units' attribute; assumed {default!r}")
        return default
    u = str(u)
    if u != default:
        notes.append(f"{key}: units {u!r} differ from the expected {default!r}; "
                     f"values are not converted")
    return u


def read_recording(path: Union[str, os.PathLike]) -> Recording:
    """Read a recording (this version's layout, format_version 1, or a compatible file).

    Parameters
    ----------
    path : str or os.PathLike
        An HDF5 file with at least the datasets ``time`` [s], ``shaft/x`` and
        ``shaft/y`` [m] (or ``planes/<plane>/x|y``), all of shape (N,).  The
        rotor and weight datasets are optional: missing rotor data reads as
        NaN, missing weights as none; each such fill is listed in
        :attr:`Recording.notes`.

    Returns
    -------
    Recording

    Raises
    ------
    FileNotFoundError
        ``path`` does not exist.
    RecordingError
        Not an HDF5 file, a truncated or corrupt file, a missing required
        dataset, a dataset whose length differs from ``len(time)``, malformed
        solver JSON, or a ``format_version`` newer than this reader.  The
        message names the file and the dataset or attribute.
    """
    path = Path(path)
    label = str(path)
    if not path.exists():
        raise FileNotFoundError(2, "recording not found", label)
    if path.is_dir():
        raise RecordingError(f"{label}: is a directory, not a recording file")
    try:
        is_hdf5 = h5py.is_hdf5(label)
    except OSError as exc:
        raise RecordingError(f"{label}: cannot read file: {exc}") from None
    if not is_hdf5:
        raise RecordingError(f"{label}: not an HDF5 file (no HDF5 signature); expected an "
                             f"autobalancer-stand recording")
    try:
        f = h5py.File(label, "r")
    except OSError as exc:
        raise RecordingError(f"{label}: cannot open HDF5 file (truncated or corrupt?): "
                             f"{exc}") from None
    try:
        with f:
            return _read_open(f, label)
    except RecordingError:
        raise
    except (OSError, RuntimeError, KeyError, ValueError, TypeError) as exc:
        raise RecordingError(f"{label}: cannot read recording (truncated or corrupt "
                             f"file?): {type(exc).__name__}: {exc}") from None


def _root_attrs(f, label) -> dict:
    attrs = {}
    for key in f.attrs.keys():
        try:
            attrs[key] = _decode(f.attrs[key])
        except (OSError, RuntimeError, ValueError, TypeError) as exc:
            raise RecordingError(f"{label}: cannot read root attribute '{key}' (truncated "
                                 f"or corrupt file?): {exc}") from None
    return attrs


def _json_attr(attrs, key, label, kind=dict):
    if key not in attrs:
        return kind()
    try:
        v = json.loads(attrs[key])
    except (TypeError, ValueError) as exc:
        raise RecordingError(f"{label}: root attribute '{key}' is not valid JSON: {exc}") from None
    if not isinstance(v, kind):
        raise RecordingError(f"{label}: root attribute '{key}' is JSON {type(v).__name__}, "
                             f"expected an object")
    return v


def _read_open(f: "h5py.File", label: str) -> Recording:
    from stand.recording.legacy import legacy_layout

    attrs = _root_attrs(f, label)
    notes: list = [str(n) for n in _json_attr(attrs, "run_notes", label, list)]
    fmt, fver = attrs.get("format"), attrs.get("format_version")
    ours = isinstance(fmt, str) and fmt == FORMAT  # an array attribute would compare elementwise
    if ours and isinstance(fver, (int, float)) and fver > FORMAT_VERSION:
        raise RecordingError(f"{label}: attribute format_version = {fver}: written by a "
                             f"newer autobalancer-stand (this reader handles up to "
                             f"{FORMAT_VERSION}); upgrade the package")
    legacy = legacy_layout(f, attrs, label, notes)
    if not ours and legacy is None:
        notes.append(f"root attribute 'format' is {fmt!r}, not {FORMAT!r}: "
                     f"not written by the simulator")
    if "time" not in f:
        raise RecordingError(f"{label}: missing dataset 'time' (required: {', '.join(REQUIRED)})")
    t = _read_dataset(f, "time", label, None)
    N = t.shape[0]
    units = {"t": _units(f, "time", "s", notes)}
    # planes
    planes = {}
    pg = f.get("planes")
    if isinstance(pg, h5py.Group):
        for p, g in pg.items():
            if isinstance(g, h5py.Group) and "x" in g and "y" in g:
                planes[p] = np.column_stack([_read_dataset(f, f"planes/{p}/{a}", label, N)
                                             for a in "xy"])
    if legacy is not None:
        planes.update(legacy.get("planes", {}))
    main = attrs.get("main_plane") if isinstance(attrs.get("main_plane"), str) else None
    if main is None and legacy is not None:
        main = legacy.get("main")
    if (f.get("shaft/x") is not None and f.get("shaft/y") is not None) or main not in planes:
        for key in REQUIRED[1:]:
            if f.get(key) is None:   # absent, or a link to a deleted plane
                raise RecordingError(f"{label}: missing dataset '{key}' (required: "
                                     f"{', '.join(REQUIRED)})")
        shaft = np.column_stack([_read_dataset(f, k, label, N) for k in REQUIRED[1:]])
        for k, name in zip(REQUIRED[1:], "xy"):
            units[name] = _units(f, k, "m", notes)
        if main not in planes or not np.array_equal(planes[main], shaft, equal_nan=True):
            main = "shaft" if main is None or main in planes else main
            planes[main] = shaft
    else:
        units["x"] = units["y"] = "m"
    # rotor
    rotor = {}
    for key in ("rotor/angle", "rotor/speed"):
        name = DATASETS[key][0]
        if key in f:
            rotor[name] = _read_dataset(f, key, label, N)
            units[name] = _units(f, key, DATASETS[key][1], notes)
        else:
            rotor[name] = np.full(N, np.nan)
            units[name] = DATASETS[key][1]
            notes.append(f"{key}: not in the file; filled with NaN")
    weights, wplanes = _read_weights(f, attrs, label, N, rotor["rotor_angle"], main, notes, units)
    coords, truth = {}, {}
    for group, target in (("coordinates", coords), ("truth/residual", truth)):
        g = f.get(group)
        if isinstance(g, h5py.Group):
            g.visititems(lambda name, obj: target.__setitem__(
                name if group == "coordinates" else f"residual/{name}",
                (_read_dataset(f, f"{group}/{name}", label, N, obj.ndim), str(_decode(
                    obj.attrs.get("units", "1"))))) if isinstance(obj, h5py.Dataset) else None)
    if legacy is not None:
        coords.update(legacy.get("coordinates", {}))
        truth.update(legacy.get("truth", {}))
    solver = _json_attr(attrs, "solver", label)
    scene_text = attrs.get("scene", attrs.get("scene_text", ""))
    if not isinstance(scene_text, str):
        raise RecordingError(f"{label}: root attribute 'scene' is not text")
    scene = _scene(scene_text, notes)
    stats = SolverStats(**{k: v for k, v in solver.items() if k in SolverStats.FIELDS})
    return Recording(
        t=_freeze(t), planes={p: _freeze(a) for p, a in planes.items()}, main_plane=main,
        rotor_angle=_freeze(rotor["rotor_angle"]), rotor_speed=_freeze(rotor["rotor_speed"]),
        weights=weights, weight_planes=wplanes, stats=stats, scene=scene,
        coordinates=coords, truth=truth, scene_text=scene_text, solver=solver, units=units,
        version=str(attrs.get("version", "")), attrs=attrs, path=label, notes=tuple(notes))


def _scene(text: str, notes: list) -> "Optional[Scene]":
    if not text.strip():
        notes.append("root attribute 'scene' missing or empty: Recording.scene is None")
        return None
    from stand.scene.model import SceneError
    from stand.scene.parse import load

    try:
        return load(text if "\n" in text else text + "\n")
    except (SceneError, ValueError, TypeError, KeyError) as exc:
        notes.append(f"the stored scene is not readable by this version ({exc}); "
                     "Recording.scene is None")
        return None


def _read_weights(f, attrs, label, N, rotor_angle, main, notes, units):
    """``weights`` and ``weight_planes`` of a file (format 2 groups or format 1 matrices)."""
    wplanes = _json_attr(attrs, "weight_planes", label) if "weight_planes" in attrs else {}
    weights: dict = {}
    g = f.get("weights")
    if not isinstance(g, h5py.Group):
        notes.append("weights: no weight datasets in the file; no weights")
        return weights, {}
    v1 = {k: c for k, c in V1_WEIGHTS.items() if k in f}
    if v1 or "weights/relative_angle" in f:
        mats = {c: _read_dataset(f, k, label, N, 2) for k, c in v1.items()}
        if "weights/relative_angle" in f:
            mats["relative_angle"] = _read_dataset(f, "weights/relative_angle", label, N, 2)
        cols = {c: a.shape[1] for c, a in mats.items()}
        if len(set(cols.values())) > 1:
            detail = ", ".join(f"'weights/{c}' {mats[c].shape}" for c in cols)
            raise RecordingError(f"{label}: weight datasets disagree on the number of weights: "
                                 f"{detail}")
        n = next(iter(cols.values()))
        if "angle" not in mats:
            if "relative_angle" in mats:
                mats["angle"] = mats["relative_angle"] + rotor_angle[:, None]
            else:
                mats["angle"] = np.full((N, n), np.nan)
            if n:
                notes.append("weights/angle: not in the file; "
                             + ("computed from weights/relative_angle + rotor/angle"
                                if "relative_angle" in mats else "filled with NaN"))
        if "speed" not in mats:
            mats["speed"] = np.full((N, n), np.nan)
            if n:
                notes.append("weights/speed: not in the file; filled with NaN")
        if n and "relative_angle" not in mats:
            notes.append("weights/relative_angle: not in the file; computed as "
                         "weights/angle - rotor/angle")
        for k, c in v1.items():
            units[f"weight_{c}"] = _units(f, k, "rad" if c == "angle" else "rad/s", notes)
        for j in range(n):
            name = f"weight{j + 1}"
            weights[name] = {"angle": _freeze(mats["angle"][:, j]),
                             "speed": _freeze(mats["speed"][:, j])}
            wplanes.setdefault(name, main)
        return weights, wplanes
    for name, wg in g.items():
        if not isinstance(wg, h5py.Group):
            continue
        weights[name] = {c: _freeze(_read_dataset(f, f"weights/{name}/{c}", label, N))
                         for c, d in wg.items() if isinstance(d, h5py.Dataset)}
        wplanes.setdefault(name, main)
    return weights, wplanes


# ------------------------------------------------------------ pandas HDF5 tables (lab recordings)
def pandas_table_key(path) -> Optional[str]:
    """The key of the first pandas table (``DataFrame.to_hdf``) in an HDF5 file, or None (a
    stand recording, or not readable: :func:`read_recording` names the problem)."""
    keys = []
    try:
        with h5py.File(path, "r") as f:
            if "format_version" in f.attrs or "time" in f:
                return None
            f.visititems(lambda n, o: keys.append(n) if "pandas_type" in o.attrs else None)
    except Exception:   # noqa: BLE001 -- a damaged file: the recording reader names the problem
        return None
    return keys[0] if keys else None


def _pickled_names(raw) -> list:
    """Column names pandas stores as a protocol-0 pickled list of strings, read as text: the
    arguments of its ``V`` (unicode) and ``S`` (str) opcodes; nothing is unpickled."""
    text = bytes(raw).decode("latin-1")
    names, i = [], 0
    while i < len(text):
        op = text[i]
        if op in "pgIFLVS":                       # opcodes with a line argument
            j = text.find("\n", i)
            j = len(text) if j < 0 else j
            arg = text[i + 1:j]
            if op == "V":
                names.append(arg.encode("latin-1").decode("raw_unicode_escape"))
            elif op == "S" and len(arg) >= 2 and arg[0] in "'\"":
                names.append(arg[1:-1])
            i = j + 1
        else:                                     # ( l a t . ) and others without arguments
            i += 1
    return names


def read_pandas_table(path, key: str):
    """A table written by ``DataFrame.to_hdf``, read with h5py: numeric columns only, nothing
    unpickled (pandas' own reader unpickles object columns: unsafe on a file from elsewhere).

    ``format="fixed"``: the ``block<i>_items`` / ``block<i>_values`` arrays;
    ``format="table"``: the fields of the ``table`` dataset (``data_columns=True``) and the
    ``values_block_<i>`` fields with their names.  Used by :mod:`stand.lab.table` (lab
    tables); HDF5 is opened here, in one module.

    Raises
    ------
    RecordingError
        No such key, not a DataFrame, no numeric column.
    """
    import pandas as pd

    label = str(path)
    cols = {}
    skipped = []
    with h5py.File(path, "r") as f:
        if key not in f:
            raise RecordingError(f"{label}: no key {key!r} in this HDF5 file")
        g = f[key]
        kind = g.attrs.get("pandas_type", b"")
        kind = kind.decode() if isinstance(kind, bytes) else str(kind)
        if kind == "frame":
            for i in range(int(g.attrs.get("nblocks", 0))):
                names = [n.decode() if isinstance(n, bytes) else str(n)
                         for n in g[f"block{i}_items"][()]]
                vals = g[f"block{i}_values"]
                if vals.dtype.kind not in "iufb" or vals.ndim != 2:
                    skipped += names                 # text (pickled object) columns
                    continue
                a = vals[()]
                for j, n in enumerate(names):
                    cols[n] = a[:, j]
        elif kind == "frame_table":
            t = g["table"]
            data = t[()]
            for name in data.dtype.names:
                if name == "index":
                    continue
                a = data[name]
                if name.startswith("values_block_"):
                    names = _pickled_names(t.attrs.get(f"{name}_kind", b""))
                    if a.dtype.kind not in "iufb" or len(names) != (a.shape[1] if a.ndim == 2 else 1):
                        skipped.append(name)
                        continue
                    a = a.reshape(a.shape[0], -1)
                    for j, n in enumerate(names):
                        cols[n] = a[:, j]
                elif a.dtype.kind in "iufb" and a.ndim == 1:
                    cols[name] = a
                else:
                    skipped.append(name)
        else:
            raise RecordingError(f"{label}: {key!r} is a pandas {kind or 'object'}, not a DataFrame")
    if not cols:
        raise RecordingError(f"{label}: no numeric column in the pandas table {key!r}")
    df = pd.DataFrame(cols)
    df.attrs["skipped_columns"] = skipped
    return df
