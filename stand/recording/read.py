"""Reading a recording: :func:`read_recording` (``stand.read``) and the :class:`Recording` it returns.

It opens this version's layout (:mod:`.layout`), format_version 1 files
(``weights/angle`` (N, n) matrices), the rotor-family and weight-model files
written before the one layout (:mod:`.legacy`), and files of other tools (a real
stand, a data logger) holding at least ``time``, ``shaft/x`` and ``shaft/y``;
what was filled in is listed in :attr:`Recording.notes`.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Optional, Union

import h5py
import numpy as np

from stand.integrate.result import Run, SolverStats
from stand.io.guard import memory_budget
from stand.recording.layout import (DATASETS, FORMAT, FORMAT_VERSION, INSTRUMENTS, REQUIRED,
                                    SCREEN, V1_WEIGHTS, RecordingError, decode_attr,
                                    scene_language, screen_group, truth_key)
from stand.recording.legacy import legacy_layout

if TYPE_CHECKING:  # pragma: no cover
    from stand.scene.model import Scene

__all__ = ["Recording", "read_recording", "named_screens", "screen_group_of"]


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
            return {} if obj is None else {k: decode_attr(v) for k, v in obj.attrs.items()}

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



def _read_dataset(f: "h5py.File", key: str, label: str, N: Optional[int],
                  ndim: int = 1) -> np.ndarray:
    obj = f.get(key)
    if not isinstance(obj, h5py.Dataset):
        kind = "a group" if isinstance(obj, h5py.Group) else type(obj).__name__
        raise RecordingError(f"{label}: '{key}' is {kind}, not a dataset")
    if obj.dtype.kind not in "fiu":
        raise RecordingError(f"{label}: dataset '{key}' has dtype {obj.dtype}, expected "
                             f"a numeric array")
    budget = memory_budget() / 2         # the float64 copy and the arrays built from it
    if obj.size * 8.0 > budget:
        raise RecordingError(f"{label}: dataset '{key}' declares {obj.size} samples "
                             f"({obj.size * 8 / 2 ** 30:.3g} GiB as float64); the memory allows "
                             f"{budget / 2 ** 30:.3g} GiB per dataset: not readable on this machine")
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
    u = decode_attr(f[key].attrs.get("units", None))
    if u is None:
        notes.append(f"{key}: no 'units' attribute; assumed {default!r}")
        return default
    u = str(u)
    if u != default:
        notes.append(f"{key}: units {u!r} differ from the expected {default!r}; "
                     f"values are not converted")
    return u


def named_screens(path: Union[str, os.PathLike], positioned: bool = True) -> list:
    """Names of a recording's named laser screens (the groups ``instruments/screen.<name>``;
    ``positioned``: those with an ``axial_position_m``), in the file's order, without reading
    the recording; ``[]`` for a file that is not a readable HDF5 file."""
    try:
        with h5py.File(path, "r") as f:
            g = f.get(INSTRUMENTS)
            return [k.split(".", 1)[1] for k in (g if isinstance(g, h5py.Group) else ())
                    if k.startswith(SCREEN + ".") and isinstance(g[k], h5py.Group)
                    and (not positioned or "axial_position_m" in g[k].attrs)]
    except (OSError, ValueError):
        return []


def screen_group_of(path: Union[str, os.PathLike], screen: Optional[str] = None) -> str:
    """The recording group of the screen a command reads (``stand snapshot``, ``track``,
    ``video``: their ``--screen``), checked against the screens the file holds.

    Parameters
    ----------
    path : str or os.PathLike
        An HDF5 recording.
    screen : str, optional
        A named screen (``"front"`` or ``"screen.front"``: ``[instruments.screen.front]``);
        None: the recording's one screen (``[instruments.screen]``).

    Returns
    -------
    str
        :func:`stand.recording.layout.screen_group` of ``screen``: the group is in the file,
        or (without ``screen``) the file has no screen at all or is not readable -- the
        caller says what is missing.

    Raises
    ------
    ValueError
        ``screen`` not given but the file holds only named screens (the message names them
        and the option to add: "this recording has two screens, front and rear, and no
        unnamed one: add --screen front or --screen rear"), or the named screen is not in
        the file (the screens it holds named).
    """
    group = screen_group(screen)
    try:
        with h5py.File(path, "r") as f:
            if isinstance(f.get(group), h5py.Group):
                return group
            g = f.get(INSTRUMENTS)
            unnamed = isinstance(g, h5py.Group) and isinstance(g.get(SCREEN), h5py.Group)
    except (OSError, ValueError):
        return group                     # not a readable HDF5 file: the caller's reader says so
    names = named_screens(path, positioned=False)
    if screen is None and not names:
        return group
    count = {1: "one screen", 2: "two screens", 3: "three screens"}.get(len(names),
                                                                        f"{len(names)} screens")
    listed = ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else "".join(names)
    choice = " or ".join(f"--screen {n}" for n in names)
    if screen is None:
        raise ValueError(f"{path}: this recording has {count}, {listed}, and no unnamed one: "
                         f"add {choice}")
    held = (f"this recording has {count}, {listed}: give {choice}" if names
            else "this recording has one unnamed screen: leave out --screen" if unnamed
            else "this recording has no screen")
    raise ValueError(f"--screen {screen}: {path} has no {group}; {held}")


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
            attrs[key] = decode_attr(f.attrs[key])
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
    for group, target in (("coordinates", coords), (truth_key("residual"), truth)):
        g = f.get(group)
        if isinstance(g, h5py.Group):
            g.visititems(lambda name, obj: target.__setitem__(
                name if group == "coordinates" else f"residual/{name}",
                (_read_dataset(f, f"{group}/{name}", label, N, obj.ndim), str(decode_attr(
                    obj.attrs.get("units", "1"))))) if isinstance(obj, h5py.Dataset) else None)
    if legacy is not None:
        coords.update(legacy.get("coordinates", {}))
        truth.update(legacy.get("truth", {}))
    solver = _json_attr(attrs, "solver", label)
    scene_text = attrs.get("scene", attrs.get("scene_text", ""))
    if not isinstance(scene_text, str):
        raise RecordingError(f"{label}: root attribute 'scene' is not text")
    scene = _scene(scene_text, notes, scene_language(attrs))
    stats = SolverStats(**{k: v for k, v in solver.items() if k in SolverStats.FIELDS})
    return Recording(
        t=_freeze(t), planes={p: _freeze(a) for p, a in planes.items()}, main_plane=main,
        rotor_angle=_freeze(rotor["rotor_angle"]), rotor_speed=_freeze(rotor["rotor_speed"]),
        weights=weights, weight_planes=wplanes, stats=stats, scene=scene,
        coordinates=coords, truth=truth, scene_text=scene_text, solver=solver, units=units,
        version=str(attrs.get("version", "")), attrs=attrs, path=label, notes=tuple(notes))


def _scene(text: str, notes: list, language: int) -> "Optional[Scene]":
    """The stored scene, read in the scene-file language it was written in (a file without
    ``scene_language`` predates it: language 1, ``[structure]`` angles in rad)."""
    if not text.strip():
        notes.append("root attribute 'scene' missing or empty: Recording.scene is None")
        return None
    from stand.errors import SceneError
    from stand.scene.parse import load

    try:
        scene = load(text if "\n" in text else text + "\n", language=language)
    except (SceneError, ValueError, TypeError, KeyError) as exc:
        notes.append(f"the stored scene is not readable by this version ({exc}); "
                     "Recording.scene is None")
        return None
    if language == 1 and scene.kind == "rotor":
        from stand.scene.structure_tables import angle_keys

        keys = angle_keys(scene.structure.type, scene.structure.params)
        if keys:
            notes.append("the stored scene predates scene language 2 (every angle of a scene "
                         f"file in degrees): its structure.{', structure.'.join(keys)} are read "
                         "in rad, as written")
    return scene


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
