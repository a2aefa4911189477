"""Recordings: one HDF5 file per run, written atomically, read back with checks.

Layout of a recording (all arrays float64, SI units, one row per sample)::

    /time                    (N,)    s      sample times
    /shaft/x, /shaft/y       (N,)    m      shaft displacement along the fixed X, Y axes
    /rotor/angle             (N,)    rad    angle of the rotor's reference mark
    /rotor/speed             (N,)    rad/s  rotor speed
    /weights/angle           (N, n)  rad    absolute weight angles, one column per weight
    /weights/speed           (N, n)  rad/s  absolute weight speeds
    /weights/relative_angle  (N, n)  rad    weight angle - rotor angle (unwrapped)

Every dataset carries a ``units`` and a ``description`` attribute.  With no
weights the ``weights/*`` datasets exist with shape (N, 0).  Root attributes:
``scene`` (the scene's TOML text), ``scene_name``, ``solver`` (JSON of
:class:`stand.simulate.SolverStats`), ``version`` (``stand.__version__``),
``format`` = :data:`FORMAT`, ``format_version`` = :data:`FORMAT_VERSION`,
``created`` (ISO 8601, UTC), plus any ``extra_attrs`` given to
:func:`write_recording`.

:func:`read_recording` also accepts files written by other tools (a real
stand, a data logger) as long as they hold ``time``, ``shaft/x`` and
``shaft/y``; the rotor and weight datasets are then optional, and what was
filled in is listed in :attr:`Recording.notes`.

Only numpy and h5py are imported here; pandas, the scene reader and the
simulator are imported when needed.
"""
from __future__ import annotations

import dataclasses
import datetime as _dt
import json
import os
import stat
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, TYPE_CHECKING, Any, Mapping, Optional, Union

import h5py
import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .scene import Scene
    from .simulate import Trajectory

__all__ = ["FORMAT", "FORMAT_VERSION", "DATASETS", "Recording", "RecordingError",
           "read_recording", "write_recording"]

FORMAT = "autobalancer-stand recording"
FORMAT_VERSION = 1
#: arrays with more samples than this are stored chunked and gzip-compressed
COMPRESS_ABOVE = 1000
GZIP_LEVEL = 4
#: target size of one chunk [bytes]
CHUNK_BYTES = 256 * 1024

#: dataset path -> (Recording field, units, description); the order is the file's
DATASETS = {
    "time": ("t", "s", "sample time"),
    "shaft/x": ("x", "m", "shaft displacement along the fixed X axis"),
    "shaft/y": ("y", "m", "shaft displacement along the fixed Y axis"),
    "rotor/angle": ("rotor_angle", "rad", "angle of the rotor's reference mark (keyphasor)"),
    "rotor/speed": ("rotor_speed", "rad/s", "rotor angular speed"),
    "weights/angle": ("weight_angle", "rad",
                      "absolute angle of each correction weight, one column per weight"),
    "weights/speed": ("weight_speed", "rad/s",
                      "absolute angular speed of each correction weight, one column per weight"),
    "weights/relative_angle": ("relative_angle", "rad",
                               "weight angle relative to the rotor's reference mark, "
                               "unwrapped (weights/angle - rotor/angle)"),
}
REQUIRED = ("time", "shaft/x", "shaft/y")
RESERVED_ATTRS = ("scene", "scene_name", "solver", "version", "format", "format_version",
                  "created")


class RecordingError(ValueError):
    """A file is not a readable recording.  The message names the file and the dataset."""


# ---------------------------------------------------------------- writing
def _json_default(value: Any) -> Any:
    """Make numpy scalars and arrays JSON-serialisable (plain int/float/bool/list)."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, Path):
        return str(value)
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


def _plain(value: Any) -> Any:
    """Recursively replace numpy scalars by Python ones (for ``json.dumps``)."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def _solver_json(stats: Any) -> str:
    if stats is None:
        return "{}"
    data = dataclasses.asdict(stats) if dataclasses.is_dataclass(stats) else dict(stats)
    return json.dumps(_plain(data), default=_json_default)


def _attr_value(key: str, value: Any) -> Any:
    """An ``extra_attrs`` value as HDF5 can store it; mappings become JSON text."""
    if value is None:
        raise ValueError(f"extra_attrs[{key!r}] = None: HDF5 attributes cannot be None")
    if isinstance(value, Mapping):
        return json.dumps(_plain(dict(value)), default=_json_default)
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, (list, tuple)) and any(isinstance(v, str) for v in value):
        return json.dumps(_plain(list(value)), default=_json_default)
    return value


def _column_array(name: str, value: Any, n_samples: int) -> np.ndarray:
    a = np.asarray(value, dtype=np.float64)
    if a.shape != (n_samples,):
        raise ValueError(f"trajectory.{name}: shape {a.shape}, expected ({n_samples},) "
                         f"(one value per sample of trajectory.t)")
    return a


def _weight_array(name: str, value: Any, n_samples: int) -> np.ndarray:
    if value is None:
        return np.zeros((n_samples, 0))
    a = np.asarray(value, dtype=np.float64)
    if a.size == 0:
        return np.zeros((n_samples, 0))
    if a.ndim != 2 or a.shape[0] != n_samples:
        raise ValueError(f"trajectory.{name}: shape {a.shape}, expected ({n_samples}, n) "
                         f"(one row per sample, one column per weight)")
    return a


def _storage_options(a: np.ndarray) -> dict:
    """Chunked gzip (level 4, shuffle) for long, non-empty arrays; contiguous otherwise."""
    if a.shape[0] <= COMPRESS_ABOVE or a.size == 0:
        return {}
    cols = int(np.prod(a.shape[1:], dtype=np.int64)) if a.ndim > 1 else 1
    rows = max(1, min(a.shape[0], CHUNK_BYTES // (8 * cols)))
    return {"chunks": (rows,) + a.shape[1:], "compression": "gzip",
            "compression_opts": GZIP_LEVEL, "shuffle": True}


def _new_file_mode(target: Path) -> int:
    """Permissions for the new file: the old target's, else 0o666 minus the umask."""
    try:
        return stat.S_IMODE(target.stat().st_mode)
    except OSError:
        pass
    try:  # Linux: read the umask without changing it
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return 0o666 & ~int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


def _fsync(path: str) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def check_output_path(path: Union[str, os.PathLike]) -> Path:
    """Check that ``path`` can receive a recording, before any work is done.

    Raises
    ------
    FileNotFoundError
        The directory does not exist (named in the message).
    IsADirectoryError, ValueError
        ``path`` is a directory, or exists and is not a regular file (a device
        such as /dev/null, a fifo, a symbolic link): the atomic rename would
        replace it, so it is refused.
    """
    path = Path(path)
    directory = path.parent
    if not directory.is_dir():
        raise FileNotFoundError(2, f"cannot write recording {path}: directory does not exist",
                                str(directory))
    if path.is_dir():
        raise IsADirectoryError(21, f"cannot write recording: {path} is a directory", str(path))
    if os.path.lexists(path) and (path.is_symlink() or not path.is_file()):
        raise ValueError(f"cannot write recording {path}: it exists and is not a regular file "
                         "(device, fifo or symbolic link); the atomic rename would replace it")
    return path


def write_recording(traj: "Trajectory", path: Union[str, os.PathLike], *,
                    extra_attrs: Optional[Mapping[str, Any]] = None,
                    writer: Optional[Callable[["h5py.File"], None]] = None) -> Path:
    """Write one run to an HDF5 file, atomically.

    The file is first written to a temporary ``*.h5.tmp`` file in the target's
    directory, then renamed onto ``path`` (``os.replace``).  If anything fails,
    the temporary file is removed, the exception propagates, and a file that
    already existed at ``path`` is left untouched.

    Parameters
    ----------
    traj : stand.simulate.Trajectory
        The run: times [s], shaft displacement [m], rotor angle [rad] and
        speed [rad/s], absolute weight angles [rad] and speeds [rad/s]
        (shape (N, n)), solver statistics and the scene.
    path : str or os.PathLike
        Target file (conventionally ``*.h5``).  Its directory must exist.
    writer : callable, optional
        ``writer(h5file)`` is called with the open temporary file after the
        core datasets are written (the instruments stream their frames, truth
        and settings through it); a failure there discards the whole file.
    extra_attrs : mapping, optional
        Additional root attributes (str, numbers, arrays; mappings are stored
        as JSON text).  The reserved names (``scene``, ``scene_name``,
        ``solver``, ``version``, ``format``, ``format_version``, ``created``)
        cannot be overridden.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    FileNotFoundError
        The target's directory does not exist (the message names it).
    ValueError
        The trajectory's arrays have inconsistent shapes, or ``extra_attrs``
        uses a reserved name or holds ``None``.
    """
    from . import __version__

    path = Path(path)
    check_output_path(path)
    directory = path.parent
    extra = dict(extra_attrs or {})
    clash = sorted(set(extra) & set(RESERVED_ATTRS))
    if clash:
        raise ValueError(f"extra_attrs: {', '.join(map(repr, clash))} reserved for the "
                         f"recording's own metadata ({', '.join(RESERVED_ATTRS)})")
    extra = {str(k): _attr_value(str(k), v) for k, v in extra.items()}

    # validate and convert everything before touching the disk
    t = np.asarray(traj.t, dtype=np.float64)
    if t.ndim != 1:
        raise ValueError(f"trajectory.t: shape {t.shape}, expected (N,)")
    N = t.shape[0]
    arrays = {"time": t}
    for name in ("x", "y", "rotor_angle", "rotor_speed"):
        arrays[name] = _column_array(name, getattr(traj, name), N)
    wa = _weight_array("weight_angle", traj.weight_angle, N)
    ws = _weight_array("weight_speed", traj.weight_speed, N)
    if ws.shape != wa.shape:
        raise ValueError(f"trajectory.weight_speed: shape {ws.shape} differs from "
                         f"trajectory.weight_angle {wa.shape}")
    data = {
        "time": t,
        "shaft/x": arrays["x"],
        "shaft/y": arrays["y"],
        "rotor/angle": arrays["rotor_angle"],
        "rotor/speed": arrays["rotor_speed"],
        "weights/angle": wa,
        "weights/speed": ws,
        "weights/relative_angle": wa - arrays["rotor_angle"][:, None],
    }
    scene = getattr(traj, "scene", None)
    root = {
        "format": FORMAT,
        "format_version": np.int64(FORMAT_VERSION),
        "version": __version__,
        "created": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "scene_name": str(getattr(scene, "name", "") or ""),
        "scene": str(getattr(scene, "text", "") or ""),
        "solver": _solver_json(getattr(traj, "stats", None)),
    }
    mode = _new_file_mode(path)

    with tempfile.NamedTemporaryFile(dir=directory, delete=False, prefix=f".{path.name}.",
                                     suffix=".h5.tmp") as tmp:
        tmp_name = tmp.name
    try:
        with h5py.File(tmp_name, "w") as f:
            for key, value in root.items():
                f.attrs[key] = value
            for key, value in extra.items():
                f.attrs[key] = value
            for key, a in data.items():
                _, units, description = DATASETS[key]
                ds = f.create_dataset(key, data=a, dtype=np.float64, **_storage_options(a))
                ds.attrs["units"] = units
                ds.attrs["description"] = description
            if writer is not None:
                writer(f)  # instruments: frames streamed in, truth, settings
        _fsync(tmp_name)
        os.chmod(tmp_name, mode)
        os.replace(tmp_name, path)
    except BaseException:
        try:
            os.unlink(tmp_name)
        except FileNotFoundError:
            pass
        raise
    return path


# ---------------------------------------------------------------- reading
def _freeze(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class Recording:
    """One recorded run, as read by :func:`read_recording`.  Arrays are read-only.

    Attributes
    ----------
    t : ndarray (N,)                  sample time [s]
    x, y : ndarray (N,)               shaft displacement [m]
    rotor_angle : ndarray (N,)        angle of the reference mark [rad]; NaN if not recorded
    rotor_speed : ndarray (N,)        rotor speed [rad/s]; NaN if not recorded
    weight_angle : ndarray (N, n)     absolute weight angles [rad]; (N, 0) if no weights
    weight_speed : ndarray (N, n)     absolute weight speeds [rad/s]
    relative_angle : ndarray (N, n)   weight angle - rotor angle, unwrapped [rad]
    units : dict
        Field name (``"t"``, ``"x"``, ...) -> units string as stored in the file
        (the SI default for datasets that were filled in).
    scene_text : str
        The scene's TOML text ("" if the file has none).
    solver : dict
        Solver statistics (method, rtol, atol, n_steps, n_rejected, nfev,
        wall_time [s], status, message, ...); empty if the file has none.
    version : str
        ``stand.__version__`` of the writer ("" if unknown).
    attrs : dict
        All root attributes, decoded to Python types.
    path : str
        The file read.
    notes : tuple of str
        What was missing or unusual (e.g. a dataset filled with NaN, units
        that differ from the SI default); empty for the simulator's files.
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    rotor_angle: np.ndarray
    rotor_speed: np.ndarray
    weight_angle: np.ndarray
    weight_speed: np.ndarray
    relative_angle: np.ndarray
    units: dict = field(default_factory=dict)
    scene_text: str = ""
    solver: dict = field(default_factory=dict)
    version: str = ""
    attrs: dict = field(default_factory=dict)
    path: str = ""
    notes: tuple = ()

    @property
    def n_weights(self) -> int:
        """Number of correction weights n (columns of ``weight_angle``)."""
        return int(self.weight_angle.shape[1])

    def __len__(self) -> int:
        return int(self.t.shape[0])

    def __repr__(self) -> str:
        name = self.attrs.get("scene_name", "")
        return (f"Recording({self.path!r}, scene_name={name!r}, samples={len(self)}, "
                f"weights={self.n_weights})")

    def to_frame(self) -> "pd.DataFrame":
        """The samples as a pandas DataFrame, one row per sample.

        Returns
        -------
        pandas.DataFrame
            Columns ``t_s`` [s], ``x_m``, ``y_m`` [m], ``rotor_angle_rad`` [rad],
            ``rotor_speed_rad_s`` [rad/s], then for each weight j = 1..n
            ``weight{j}_angle_rad`` [rad] and ``weight{j}_speed_rad_s`` [rad/s]
            (absolute; numbered from 1 as in the book, column j-1 of the arrays).
        """
        import pandas as pd

        cols = {
            "t_s": self.t,
            "x_m": self.x,
            "y_m": self.y,
            "rotor_angle_rad": self.rotor_angle,
            "rotor_speed_rad_s": self.rotor_speed,
        }
        for j in range(self.n_weights):
            cols[f"weight{j + 1}_angle_rad"] = self.weight_angle[:, j]
            cols[f"weight{j + 1}_speed_rad_s"] = self.weight_speed[:, j]
        return pd.DataFrame({k: np.array(v, dtype=np.float64) for k, v in cols.items()})

    def scene(self) -> "Scene":
        """The recorded scene, parsed with :func:`stand.scene_file.load_scene`.

        Raises
        ------
        RecordingError
            The file holds no scene text.
        stand.scene.SceneError
            The stored text is not a valid scene (e.g. from a newer version).
        """
        from .scene_file import load_scene

        if not self.scene_text.strip():
            raise RecordingError(f"{self.path}: no scene stored (root attribute 'scene' "
                                 f"is missing or empty)")
        text = self.scene_text if "\n" in self.scene_text else self.scene_text + "\n"
        return load_scene(text)


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
                  two_d: bool) -> np.ndarray:
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
    if two_d and a.ndim == 1:
        a = a[:, None]  # one weight stored as (N,)
    want = "(N, n)" if two_d else "(N,)"
    if a.ndim != (2 if two_d else 1):
        raise RecordingError(f"{label}: dataset '{key}' has shape {a.shape}, expected {want}")
    if N is not None and a.shape[0] != N:
        raise RecordingError(f"{label}: dataset '{key}' has shape {a.shape}: its length "
                             f"{a.shape[0]} differs from len(time) = {N}")
    return a


def _units(f: "h5py.File", key: str, notes: list) -> str:
    default = DATASETS[key][1]
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
    """Read a recording written by :func:`write_recording` (or a compatible file).

    Parameters
    ----------
    path : str or os.PathLike
        An HDF5 file with at least the datasets ``time`` [s], ``shaft/x`` and
        ``shaft/y`` [m], all of shape (N,).  ``rotor/angle``, ``rotor/speed``
        (N,) and ``weights/angle``, ``weights/speed``,
        ``weights/relative_angle`` (N, n) are optional: missing rotor data
        reads as NaN, missing weights as (N, 0) arrays (or NaN columns when
        only one of angle/speed is present), a missing ``relative_angle`` is
        computed; each such fill is listed in :attr:`Recording.notes`.

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


def _read_open(f: "h5py.File", label: str) -> Recording:
    notes: list = []
    attrs = {}
    for key in f.attrs.keys():
        try:
            attrs[key] = _decode(f.attrs[key])
        except (OSError, RuntimeError, ValueError, TypeError) as exc:
            raise RecordingError(f"{label}: cannot read root attribute '{key}' (truncated "
                                 f"or corrupt file?): {exc}") from None

    fmt, fver = attrs.get("format"), attrs.get("format_version")
    ours = isinstance(fmt, str) and fmt == FORMAT  # an array attribute would compare elementwise
    if ours and isinstance(fver, (int, float)) and fver > FORMAT_VERSION:
        raise RecordingError(f"{label}: attribute format_version = {fver}: written by a "
                             f"newer autobalancer-stand (this reader handles "
                             f"{FORMAT_VERSION}); upgrade the package")
    if not ours:
        notes.append(f"root attribute 'format' is {fmt!r}, not {FORMAT!r}: "
                     f"not written by the simulator")

    for key in REQUIRED:
        if key not in f:
            raise RecordingError(f"{label}: missing dataset '{key}' (required: "
                                 f"{', '.join(REQUIRED)})")
    t = _read_dataset(f, "time", label, None, False)
    N = t.shape[0]
    arrays = {"t": t}
    units = {}
    for key in ("shaft/x", "shaft/y", "rotor/angle", "rotor/speed"):
        name = DATASETS[key][0]
        if key in f:
            arrays[name] = _read_dataset(f, key, label, N, False)
            units[name] = _units(f, key, notes)
        else:
            arrays[name] = np.full(N, np.nan)
            units[name] = DATASETS[key][1]
            notes.append(f"{key}: not in the file; filled with NaN")
    units["t"] = _units(f, "time", notes)

    w = {}
    for key in ("weights/angle", "weights/speed", "weights/relative_angle"):
        if key in f:
            w[key] = _read_dataset(f, key, label, N, True)
            units[DATASETS[key][0]] = _units(f, key, notes)
        else:
            units[DATASETS[key][0]] = DATASETS[key][1]
    n_cols = {k: a.shape[1] for k, a in w.items()}
    if len(set(n_cols.values())) > 1:
        detail = ", ".join(f"'{k}' {w[k].shape}" for k in n_cols)
        raise RecordingError(f"{label}: weight datasets disagree on the number of weights: "
                             f"{detail}")
    n = next(iter(n_cols.values()), 0)
    if not w:
        notes.append("weights: no weight datasets in the file; no weights (shape (N, 0))")
    for key in ("weights/angle", "weights/speed"):
        if key not in w:
            w[key] = np.full((N, n), np.nan)
            if n:
                notes.append(f"{key}: not in the file; filled with NaN")
    if "weights/relative_angle" not in w:
        w["weights/relative_angle"] = w["weights/angle"] - arrays["rotor_angle"][:, None]
        if n:
            notes.append("weights/relative_angle: not in the file; computed as "
                         "weights/angle - rotor/angle")
    for key, a in w.items():
        arrays[DATASETS[key][0]] = a

    solver = {}
    if "solver" in attrs:
        try:
            solver = json.loads(attrs["solver"])
        except (TypeError, ValueError) as exc:
            raise RecordingError(f"{label}: root attribute 'solver' is not valid JSON: "
                                 f"{exc}") from None
        if not isinstance(solver, dict):
            raise RecordingError(f"{label}: root attribute 'solver' is JSON "
                                 f"{type(solver).__name__}, expected an object")
    scene_text = attrs.get("scene", "")
    if not isinstance(scene_text, str):
        raise RecordingError(f"{label}: root attribute 'scene' is not text")
    version = str(attrs.get("version", ""))
    if not scene_text:
        notes.append("root attribute 'scene' missing or empty: Recording.scene() unavailable")

    return Recording(
        **{k: _freeze(v) for k, v in arrays.items()},
        units=units,
        scene_text=scene_text,
        solver=solver,
        version=version,
        attrs=attrs,
        path=label,
        notes=tuple(notes),
    )
