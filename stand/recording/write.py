"""Writing a recording: one run into the one HDF5 layout (:mod:`.layout`), atomically.

The one HDF5 writer of a run (``stand.save``): the core datasets here, what the instruments
output (``run.instruments``) through :mod:`.write_instruments`.  Takes any object with the
fields of :class:`stand.integrate.result.Run`.
"""
from __future__ import annotations

import datetime as _dt
import io
import json
import os
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Mapping, Optional, Union

import h5py
import numpy as np

from stand.io.atomic import atomic_path, check_output_path
from stand.integrate.result import WEIGHT_UNITS
from stand.io.jsonable import to_jsonable
from stand.recording.layout import (DATASETS, FORMAT, FORMAT_VERSION, RESERVED_ATTRS,
                                    SCENE_LANGUAGE, scene_language, truth_key)

__all__ = ["write_recording", "open_for_writing"]

#: arrays with more samples than this are stored chunked and gzip-compressed
COMPRESS_ABOVE = 1000
GZIP_LEVEL = 4
#: target size of one chunk [bytes]
CHUNK_BYTES = 256 * 1024
#: recordings up to this size are assembled in memory, then written in one piece [bytes]
IN_MEMORY_BYTES = 256 * 1024 * 1024


@contextmanager
def open_for_writing(path: Path, estimate: float = 0.0):
    """The one place the stand opens an HDF5 file for writing: an ``h5py.File`` to fill, which
    becomes ``path`` atomically (:func:`stand.io.atomic.atomic_path`) when the block ends
    without an exception.  Up to :data:`IN_MEMORY_BYTES` (``estimate`` [bytes]) the file is
    assembled in memory and written with one plain write: a full disk or a file-size limit is
    then a clean OSError, not a failure inside the HDF5 library; larger files (long videos)
    are streamed to the temporary file."""
    with atomic_path(path, suffix=".h5.tmp") as tmp:
        target = io.BytesIO() if estimate <= IN_MEMORY_BYTES else tmp
        with h5py.File(target, "w") as f:
            yield f
        if target is not tmp:
            with open(tmp, "wb") as fh:
                fh.write(target.getbuffer())


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



def _channels(run: Any) -> dict:
    """Every channel of a run by its dataset path (the layout, :mod:`.layout`):
    ``{path: (array, units)}``, the truth arrays included."""
    ch = {key: (getattr(run, field), units) for key, (field, units, _) in DATASETS.items()
          if not key.startswith("shaft/")}      # shaft/x|y: links to the main plane
    for p, xy in run.planes.items():
        ch[f"planes/{p}/x"], ch[f"planes/{p}/y"] = (xy[:, 0], "m"), (xy[:, 1], "m")
    for name, coords in run.weights.items():
        ch.update({f"weights/{name}/{c}": (a, WEIGHT_UNITS.get(c, "1")) for c, a in coords.items()})
    ch.update({f"coordinates/{name}": v for name, v in run.coordinates.items()})
    ch.update({truth_key(k): v for k, v in run.truth.items()})
    return ch


def _check_arrays(run: Any) -> dict:
    """``{path: (float64 array, units)}`` for every channel and truth array, shapes checked."""
    t = np.asarray(run.t, dtype=np.float64)
    if t.ndim != 1:
        raise ValueError(f"run.t: shape {t.shape}, expected (N,)")
    N = t.shape[0]
    data = {}
    for key, (a, units) in _channels(run).items():
        a = np.asarray(a, dtype=np.float64)
        if a.ndim == 0 or a.shape[0] != N:
            raise ValueError(f"run channel {key!r}: shape {a.shape}, expected ({N}, ...) "
                             f"(one row per sample of run.t)")
        data[key] = (a, str(units))
    return data   # (a Run checks its main_plane is one of its planes)


def write_recording(run: Any, path: Union[str, os.PathLike], *,
                    extra_attrs: Optional[Mapping[str, Any]] = None) -> Path:
    """Write one run to an HDF5 file, atomically (:func:`stand.io.atomic.atomic_path`).

    If anything fails, the temporary file is removed, the exception propagates,
    and a file that already existed at ``path`` is left untouched.

    Parameters
    ----------
    run : stand.integrate.result.Run
        Any scene's run (or a :class:`Recording`).  What its instruments output
        (``run.instruments``, :class:`stand.instruments.outputs.InstrumentOutputs`) is
        stored after the core datasets, frames rendered one at a time
        (:mod:`.write_instruments`); a failure there discards the whole file.
    path : str or os.PathLike
        Target file (conventionally ``*.h5``).  Its directory must exist.
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
    from stand.io import __version__

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
        # the language the stored text is written in (a recording's text keeps its own)
        "scene_language": np.int64(getattr(scene, "language", None) or (
            scene_language(run.attrs) if isinstance(getattr(run, "attrs", None), dict)
            and getattr(run, "scene_text", "") else SCENE_LANGUAGE)),
        "structure": str(getattr(scene, "structure_type", "") or ""),
        "main_plane": run.main_plane,
        "run_notes": json.dumps(list(run.notes)),
        "weight_planes": json.dumps(run.weight_planes),
        "solver": json.dumps(to_jsonable(dict(stats or {}))),
    }
    from stand.instruments.outputs import InstrumentOutputs
    from stand.recording.write_instruments import estimated_bytes, write_outputs

    outputs = getattr(run, "instruments", None)
    estimate = sum(a.nbytes for a, _ in data.values()) + estimated_bytes(outputs)
    with open_for_writing(path, estimate) as f:
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
        if isinstance(outputs, InstrumentOutputs):
            write_outputs(f, outputs)  # instruments: frames streamed in, truth, settings
    return path
