"""Run a sweep: compute the points in chunks on a process pool or a Dask cluster,
append each finished chunk to a checkpoint directory, combine at the end.

Layout of the results of ``run_sweep(spec, "results.parquet")``::

    results.parquet              # final combined table (written last, atomically)
    results.parquet.parts/       # one Parquet file per finished chunk
        part-000000500-3f9c...parquet

Every file is first written under a temporary name (``*.tmp``) in the same
directory and then renamed with :func:`os.replace` (atomic on POSIX), so a
killed sweep (even ``kill -9``) leaves only complete part files plus at most a
few stray ``*.tmp`` files, which the next run deletes.  Re-running the same
command reads the parts, skips every point whose id is already there (ids are
hashes of the base scene, the options and the point's inputs:
:meth:`SweepSpec.point_ids`) and computes the rest.  A killed sweep loses at
most the chunks in flight.

A point that fails (invalid scene at that point, theory out of scope, solver
error ...) gets ``status = "error"`` and the message in ``error``; it never
stops the sweep, and it counts as finished (a resume does not retry it).
"""
from __future__ import annotations

import functools
import json
import math
import os
import time
import uuid
import warnings
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from pathlib import Path
from typing import Any, Iterable, Optional, Union

import numpy as np
import pandas as pd

from .spec import SPECIAL_KEYS, SweepSpec, SweepSpecError, load_sweep, point_scene_dict

__all__ = ["run_sweep", "compute_chunk", "read_results", "parts_dir", "RESULT_SCHEMA",
           "auto_chunk_size", "sweep_main", "add_sweep_arguments"]

#: output columns and their dtypes (inputs are float64 columns named by the axis keys)
COMMON_COLUMNS = {"point_index": "int64", "point_id": "string", "status": "string",
                  "error": "string", "wall_time_s": "float64",
                  "p.n": "Int64", "p.Rt": "float64", "p.h": "float64", "p.H": "float64",
                  "p.e0": "float64", "p.R": "float64", "p.f0_hz": "float64"}
THEORY_COLUMNS = {"theory.d": "float64", "theory.main_abscissa": "float64",
                  "theory.main_stable": "boolean", "theory.qp_stable": "boolean",
                  "theory.escape_speed_R": "float64", "theory.stable_motions": "string",
                  "theory.critical_speeds_R": "string", "theory.critical_kinds": "string",
                  "theory.n_critical": "Int64"}
SIMULATE_COLUMNS = {"sim.regime": "string", "sim.residual": "float64",
                    "sim.rotor_speed_R": "float64", "sim.spread_rad": "float64",
                    "sim.success": "boolean", "sim.message": "string", "sim.nfev": "Int64",
                    "sim.wall_s": "float64"}
RESULT_SCHEMA = {**COMMON_COLUMNS, **THEORY_COLUMNS, **SIMULATE_COLUMNS}
#: columns that depend on the machine, not on the inputs (dropped when comparing runs)
TIMING_COLUMNS = ("wall_time_s", "sim.wall_s")


# =====================================================================  per point
def _error_text(exc: BaseException) -> str:
    text = f"{type(exc).__name__}: {exc}"
    return text if len(text) <= 2000 else text[:1997] + "..."


@functools.lru_cache(maxsize=4096)
def _main_d(n: int, e0: float):
    """Configuration parameter d of the main motion (as :func:`scene_theory`); None if none."""
    from ..planar_theory import main_motion as mm
    from ..planar_theory import side

    if not e0 <= 1:
        return None
    configs = [c for c in side.main_motion_angles(e0, n) if getattr(c, "balanced", True)]
    return mm.d_from_angles(configs[0].alphas) if configs else None


@functools.lru_cache(maxsize=4096)
def _critical(Rt: float, h: float, H: float, d: float, R_max: float):
    """Critical speeds of the main motion (R, kind) on (0.05, R_max), cached per worker."""
    from ..planar_theory import main_motion as mm

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cs = mm.critical_speeds(Rt, h, H, d, R_min=0.05, R_max=R_max)
    return tuple((float(c.R), c.kind) for c in cs)


def _q(x: float) -> float:
    """``x`` rounded to 12 significant digits: parameters recomputed from SI scene fields
    (e.g. e0 = M e / S) carry round-off in the last digits; rounding lets the points of
    one curve share their critical speeds and their vectorised stability batch."""
    return float(f"{x:.12g}")


def _main_stable_batch(R: np.ndarray, Rt: float, h: float, H: float, d: float):
    """(abscissa, stable) at the speeds ``R``: :func:`main_motion.is_stable`, vectorised."""
    from ..planar_theory import main_motion as mm

    if h == 0.0 and H == 0.0:
        marg = mm._conservative_margin_batch(R, Rt, d)
        return marg, marg <= mm._conservative_tol(R)
    a = mm._abscissa_batch(R, Rt, h, H, d)
    if h == 0.0 or H == 0.0:
        return a, np.zeros(R.shape, bool)
    return a, a <= mm._abscissa_tol(R)


def _with_speed(scene, key: str, value: float):
    """The validated scene at another held speed: :func:`spec.point_scene_dict`'s
    scaling of the programme (or the torque drive's target speed), on the dataclass."""
    import dataclasses

    from ..scene import SceneError

    w1 = scene.natural_frequency
    target = value * w1 if key in ("R_omega", "dimensionless.R_omega") else value * 2 * math.pi
    if not (math.isfinite(target) and target >= 0):
        raise SceneError(f"{key} = {value!r}: must be a finite speed >= 0")
    d = scene.drive
    if d.kind == "torque":
        return dataclasses.replace(scene, drive=dataclasses.replace(d, target_speed=target))
    prog = np.array(d.programme, float)
    last = prog[-1, 1]
    if len(prog) == 1:
        prog[0, 1] = target
    elif last == 0.0:
        raise SceneError(f"{key}: the base programme ends at speed 0; cannot scale it to {value:g}")
    else:
        prog[:, 1] *= target / last
    return dataclasses.replace(scene, drive=dataclasses.replace(d, programme=prog))


def _operating_R(scene) -> float:
    from ..planar_theory.speedmap import _operating_speed

    d0 = scene.drive
    w1 = scene.natural_frequency
    if d0.kind == "torque" and d0.model == "constant":
        return d0.torque / d0.rotor_drag / w1 if d0.rotor_drag > 0 else math.nan
    return _operating_speed(scene) / w1


def _point_parameters(scene) -> dict:
    """Dimensionless parameters of a point (the book's units) and the operating speed."""
    from ..scene import dimensionless
    p = dimensionless(scene)
    R = _operating_R(scene)
    H = p.H_x if p.H_x == p.H_y else 0.5 * (p.H_x + p.H_y)
    return {"p.n": p.n, "p.Rt": p.Rt, "p.h": float(p.h[0]) if p.n else math.nan, "p.H": H,
            "p.e0": p.e0, "p.R": R, "p.f0_hz": p.omega_1 / (2 * math.pi)}


def _theory_rows(rows: list, scenes: list, opts: dict) -> None:
    """Fill the theory columns of ``rows`` (in place); vectorised over speeds per group."""
    import dataclasses

    from ..planar import build_planar_model
    from ..scene import SpeedDrive
    from ..planar_theory import qp, side
    from ..planar_theory.speedmap import MAX_WEIGHTS_FOR_SIDE, TheoryError, _check_scope

    groups: dict = {}
    for i, (row, sc) in enumerate(zip(rows, scenes)):
        if row["status"] != "ok":
            continue
        try:
            _check_scope(sc, None)
            s = sc.supports
            if s.stiffness_x != s.stiffness_y:
                raise TheoryError("theory: anisotropic supports (stiffness_x != stiffness_y); the "
                                  "steady motions of chapter 5 need isotropic supports")
            n, Rt, h, H, e0, R = (row[k] for k in ("p.n", "p.Rt", "p.h", "p.H", "p.e0", "p.R"))
            if not (math.isfinite(R) and R > 0):
                raise TheoryError(f"theory: no steady operating speed (R = {R})")
            Rt, h, H, e0 = _q(Rt), _q(h), _q(H), _q(e0)
            d = _main_d(int(n), e0)
            d = None if d is None else _q(d)
            row["theory.d"] = math.nan if d is None else d
            qp_ok = h > 0 and H > 0
            R_star = qp.escape_speed(Rt, h, H) if qp_ok else math.inf
            row["theory.escape_speed_R"] = R_star
            row["theory.qp_stable"] = bool(qp_ok and R < R_star)
            if d is None:
                row["theory.main_stable"] = False
                row["theory.main_abscissa"] = math.nan
            else:
                groups.setdefault((Rt, h, H, d), []).append(i)
        except Exception as exc:  # a failing point must not stop the others
            row["status"], row["error"] = "error", _error_text(exc)
    for (Rt, h, H, d), idx in groups.items():
        try:
            R = np.array([rows[i]["p.R"] for i in idx], float)
            a, st = _main_stable_batch(R, Rt, h, H, d)
            for i, ai, si in zip(idx, a, st):
                rows[i]["theory.main_abscissa"] = float(ai)
                rows[i]["theory.main_stable"] = bool(si)
        except Exception as exc:
            for i in idx:
                rows[i]["status"], rows[i]["error"] = "error", _error_text(exc)
    for row, sc in zip(rows, scenes):
        if row["status"] != "ok":
            continue
        try:
            motions = []
            if row["theory.main_stable"]:
                motions.append("main")
            if row["theory.qp_stable"]:
                motions.append("quasi-periodic")
            d = row["theory.d"]
            if opts.get("side") and int(row["p.n"]) <= MAX_WEIGHTS_FOR_SIDE:
                R = row["p.R"]
                sc_speed = sc if sc.drive.kind == "speed" else dataclasses.replace(
                    sc, drive=SpeedDrive(np.array([[0.0, R * sc.natural_frequency]])))
                model = build_planar_model(sc_speed)
                for rep in side.stable_steady_motions(model, R):
                    if rep.stable and (rep.kind == "side" or not math.isfinite(d)):
                        motions.append(rep.label)
            row["theory.stable_motions"] = ";".join(sorted(set(motions)))
            if opts.get("critical_speeds", True) and math.isfinite(d):
                cs = _critical(_q(row["p.Rt"]), _q(row["p.h"]), _q(row["p.H"]), float(d),
                               float(opts.get("R_max", 1000.0)))
                row["theory.critical_speeds_R"] = json.dumps([c[0] for c in cs])
                row["theory.critical_kinds"] = json.dumps([c[1] for c in cs])
                row["theory.n_critical"] = len(cs)
        except Exception as exc:
            row["status"], row["error"] = "error", _error_text(exc)


def _simulate_row(row: dict, scene, opts: dict) -> None:
    from ..regime import classify
    from ..simulate import simulate

    t0 = time.perf_counter()
    traj = simulate(scene, method=opts.get("method"))
    reg = classify(traj, window=opts.get("window", 0.2), sync_tol=opts.get("sync_tol", 1e-3),
                   balance_tol=opts.get("balance_tol", 1e-2))
    row.update({"sim.regime": reg.name, "sim.residual": float(reg.residual),
                "sim.rotor_speed_R": float(reg.rotor_speed), "sim.spread_rad": float(reg.spread),
                "sim.success": bool(traj.stats.success), "sim.message": traj.stats.message,
                "sim.nfev": int(traj.stats.nfev), "sim.wall_s": time.perf_counter() - t0})


def compute_chunk(payload: dict, indices: list, ids: list, points: list) -> list:
    """Compute one chunk of points; runs on a worker (local process or Dask).

    Parameters
    ----------
    payload : dict
        :meth:`SweepSpec.to_payload`: plain data only (base scene document,
        axis keys, compute list, options).
    indices : list of int
        Point indices (row order of the final table).
    ids : list of str
        Point ids.
    points : list of list of float
        Input values, one list per point, in the order of ``payload["keys"]``.

    Returns
    -------
    list of dict
        One row per point (see :data:`RESULT_SCHEMA`); failures are rows with
        ``status = "error"``.
    """
    from ..scene_file import parse_scene

    keys, base, compute = payload["keys"], payload["base"], payload["compute"]
    rows, scenes = [], []
    t_start = time.perf_counter()
    speed = [j for j, k in enumerate(keys) if k in SPECIAL_KEYS]
    # theory only: the scene of the non-speed inputs is parsed once and the speed is applied
    # to the validated drive (the same scaling as point_scene_dict); simulations parse each point
    fast = bool(speed) and compute == ["theory"]
    cache: dict = {}
    for idx, pid, vals in zip(indices, ids, points):
        row = {"point_index": int(idx), "point_id": pid, "status": "ok", "error": ""}
        row.update({k: float(v) for k, v in zip(keys, vals)})
        sc = None
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                if fast:
                    j = speed[0]
                    other = tuple(v for i, v in enumerate(vals) if i != j)
                    if other not in cache:
                        try:
                            ks = [k for i, k in enumerate(keys) if i != j]
                            s0 = parse_scene(point_scene_dict(base, ks, other))
                            cache[other] = (s0, _point_parameters(s0))
                        except Exception as exc:
                            cache[other] = exc
                    got = cache[other]
                    if isinstance(got, Exception):
                        raise got
                    sc = _with_speed(got[0], keys[j], float(vals[j]))
                    row.update(got[1])
                    row["p.R"] = _operating_R(sc)
                else:
                    sc = parse_scene(point_scene_dict(base, keys, vals))
                    row.update(_point_parameters(sc))
        except Exception as exc:
            row["status"], row["error"] = "error", _error_text(exc)
        rows.append(row)
        scenes.append(sc)
    t_setup = (time.perf_counter() - t_start) / max(len(rows), 1)
    shared = [t_setup] * len(rows)
    if "theory" in compute:
        t0 = time.perf_counter()
        _theory_rows(rows, scenes, payload.get("theory", {}))
        dt = (time.perf_counter() - t0) / max(len(rows), 1)
        shared = [s + dt for s in shared]
    for row, sc, s in zip(rows, scenes, shared):
        t0 = time.perf_counter()
        if "simulate" in compute and row["status"] == "ok":
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    _simulate_row(row, sc, payload.get("simulate", {}))
            except Exception as exc:
                row["status"], row["error"] = "error", _error_text(exc)
        row["wall_time_s"] = s + time.perf_counter() - t0
    return rows


def rows_to_frame(rows: list, spec_or_keys, compute: Optional[Iterable[str]] = None) -> pd.DataFrame:
    """Rows (dicts) -> DataFrame with the fixed schema (so that every part has the same dtypes)."""
    if isinstance(spec_or_keys, SweepSpec):
        keys, compute = spec_or_keys.columns, spec_or_keys.compute
    else:
        keys = list(spec_or_keys)
    schema = dict(COMMON_COLUMNS)
    if "theory" in compute:
        schema.update(THEORY_COLUMNS)
    if "simulate" in compute:
        schema.update(SIMULATE_COLUMNS)
    cols = ["point_index", "point_id"] + list(keys) + [c for c in schema if c not in
                                                       ("point_index", "point_id")]
    data = {}
    for c in cols:
        vals = [r.get(c) for r in rows]
        dtype = schema.get(c, "float64")
        if dtype == "string":
            vals = ["" if v is None else str(v) for v in vals]
        elif dtype == "float64":
            vals = [math.nan if v is None else float(v) for v in vals]
        data[c] = pd.array(vals, dtype=dtype)
    return pd.DataFrame(data, columns=cols)


# =====================================================================  files
def parts_dir(output: Union[str, Path]) -> Path:
    """Checkpoint directory of an output file: ``<output>.parts``."""
    return Path(str(output) + ".parts")


def _atomic_parquet(df: pd.DataFrame, path: Path) -> None:
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:8]}.tmp")
    try:
        df.to_parquet(tmp, index=False)
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def _atomic_hdf5(df: pd.DataFrame, path: Path, attrs: dict) -> None:
    """Write the table with h5py: one dataset per column under ``/results``."""
    import h5py

    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:8]}.tmp")
    try:
        with h5py.File(tmp, "w") as f:
            g = f.create_group("results")
            for k, v in attrs.items():
                f.attrs[k] = v
            g.attrs["columns"] = json.dumps(list(df.columns))
            for c in df.columns:
                col = df[c]
                if col.dtype == "string" or col.dtype == object:
                    g.create_dataset(c, data=np.array(col.fillna("").astype(str), dtype=object),
                                     dtype=h5py.string_dtype())
                elif str(col.dtype) == "boolean":
                    g.create_dataset(c, data=col.astype("float64").to_numpy(na_value=np.nan))
                    g[c].attrs["dtype"] = "boolean"
                elif str(col.dtype) == "Int64":
                    g.create_dataset(c, data=col.astype("float64").to_numpy(na_value=np.nan))
                    g[c].attrs["dtype"] = "Int64"
                else:
                    g.create_dataset(c, data=col.to_numpy())
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def _read_hdf5(path: Path) -> pd.DataFrame:
    import h5py

    with h5py.File(path, "r") as f:
        g = f["results"]
        cols = json.loads(g.attrs["columns"])
        data = {}
        for c in cols:
            ds = g[c]
            kind = ds.attrs.get("dtype")
            if h5py.check_string_dtype(ds.dtype) is not None:
                data[c] = pd.array([s.decode() if isinstance(s, bytes) else s for s in ds[()]],
                                   dtype="string")
            elif kind in ("boolean", "Int64"):
                x = ds[()]
                vals = [None if np.isnan(v) else (bool(v) if kind == "boolean" else int(v)) for v in x]
                data[c] = pd.array(vals, dtype=kind)
            else:
                data[c] = ds[()]
    return pd.DataFrame(data, columns=cols)


def read_results(path: Union[str, Path]) -> pd.DataFrame:
    """Read a sweep's final table (``.parquet`` or ``.h5``/``.hdf5``)."""
    path = Path(path)
    if path.suffix.lower() in (".h5", ".hdf5"):
        return _read_hdf5(path)
    return pd.read_parquet(path)


def _read_parts(pdir: Path) -> list:
    """All complete part tables; stray temporary files are removed."""
    frames = []
    if not pdir.is_dir():
        return frames
    for tmp in pdir.glob(".*.tmp"):
        try:
            tmp.unlink()
        except OSError:
            pass
    for f in sorted(pdir.glob("part-*.parquet")):
        try:
            frames.append(pd.read_parquet(f))
        except Exception as exc:  # cannot happen with atomic writes; keep going anyway
            warnings.warn(f"sweep: skipping unreadable part {f.name}: {exc}")
    return frames


# =====================================================================  execution
def auto_chunk_size(n_points: int, workers: int, compute) -> int:
    """Points per task: about 4 tasks per worker (theory: 50-500 points; simulate: 1-50)."""
    per = math.ceil(n_points / max(1, 4 * workers))
    if "simulate" in compute:
        per = math.ceil(n_points / max(1, 8 * workers))
        return int(min(max(per, 1), 50))
    return int(min(max(per, 50), 500))


class _SerialExecutor:
    """In-process stand-in for an executor (``scheduler="serial"``: debugging, profiling)."""

    def submit(self, fn, *args):
        from concurrent.futures import Future

        fut = Future()
        try:
            fut.set_result(fn(*args))
        except BaseException as exc:  # pragma: no cover
            fut.set_exception(exc)
        return fut

    def shutdown(self, wait=True, cancel_futures=False):
        pass


def _start_method() -> str:
    """"fork" when this process has a single thread (fast start, and scripts need no
    ``if __name__ == "__main__"`` guard), else "spawn" (forking a process that holds
    other threads -- a Dask client, a progress-bar monitor -- can deadlock)."""
    import multiprocessing as mp
    import threading

    if "fork" in mp.get_all_start_methods() and threading.active_count() == 1:
        return "fork"
    return "spawn"


def _local_executor(workers: int, start_method: Optional[str] = None):
    import multiprocessing as mp

    ctx = mp.get_context(start_method or _start_method())
    return ProcessPoolExecutor(max_workers=workers, mp_context=ctx)


def run_sweep(spec: Union[SweepSpec, str, Path, dict], output: Union[str, Path], *,
              scheduler: Any = None, workers: Optional[int] = None,
              chunk_size: Optional[int] = None, resume: bool = True, progress: bool = True,
              max_in_flight: Optional[int] = None,
              start_method: Optional[str] = None) -> pd.DataFrame:
    """Run a sweep with checkpoints; return the final table.

    Parameters
    ----------
    spec : SweepSpec, path, TOML text or dict
        The sweep (see :mod:`stand.sweep.spec`).
    output : path
        Final table: ``*.parquet`` (default format) or ``*.h5``/``*.hdf5``.
        Finished chunks go to ``<output>.parts/`` as they complete.
    scheduler : None, "serial", "tcp://host:port" or dask.distributed.Client
        None: local process pool (``ProcessPoolExecutor``, ``workers`` processes,
        default all cores); "serial": in this process; an address or a Client:
        the same chunks are submitted to that Dask cluster.
    workers : int, optional
        Local pool size (default ``os.cpu_count()``); with Dask only used to
        size the chunks (default: the cluster's thread count).
    chunk_size : int, optional
        Points per task; default ``spec.chunk_size`` or :func:`auto_chunk_size`.
    resume : bool
        Reuse the finished parts in ``<output>.parts`` (default).  False deletes
        them first.
    progress : bool
        tqdm progress bar on stderr.
    max_in_flight : int, optional
        Chunks submitted but not finished at any time (default 2 x workers);
        bounds memory and what a kill can lose.
    start_method : {"fork", "spawn", "forkserver"}, optional
        Start method of the local pool; default "fork" when this process has
        one thread, else "spawn" (which, like "forkserver", needs the usual
        ``if __name__ == "__main__":`` guard in a calling script).

    Returns
    -------
    pandas.DataFrame
        One row per point, in point order: ``point_index``, ``point_id``, the
        inputs (one column per axis key), ``status`` ("ok"/"error"), ``error``,
        ``wall_time_s`` [s], ``p.*`` (dimensionless parameters at the point:
        n, Rt, h, H, e0, R = omega/omega_1, f0_hz [Hz]) and the outputs
        ``theory.*`` and/or ``sim.*`` (see ``docs/sweep.md``).
    """
    if not isinstance(spec, SweepSpec):
        spec = load_sweep(spec)
    output = Path(output)
    pdir = parts_dir(output)
    if not resume and pdir.exists():
        for f in pdir.iterdir():
            f.unlink()
    pdir.mkdir(parents=True, exist_ok=True)

    points = spec.points()
    ids = spec.point_ids(points)
    id_set = set(ids)
    done = set()
    for fr in _read_parts(pdir):
        done.update(x for x in fr["point_id"].astype(object) if x in id_set)
    pending = [int(i) for i in _task_order(spec, points) if ids[i] not in done]

    client = None
    own_client = False
    if scheduler is None:
        workers = workers or os.cpu_count() or 1
        executor = _local_executor(workers, start_method) if pending else None
    elif isinstance(scheduler, str) and scheduler == "serial":
        workers = 1
        executor = _SerialExecutor()
    else:
        from dask.distributed import Client

        if isinstance(scheduler, str):
            client, own_client = Client(scheduler), True
        else:
            client = scheduler
        if workers is None:
            workers = max(1, sum(client.nthreads().values()))
        executor = None
    per = chunk_size or spec.chunk_size or auto_chunk_size(len(pending), workers, spec.compute)
    chunks = [pending[i:i + per] for i in range(0, len(pending), per)]
    limit = max_in_flight or 2 * workers
    payload = spec.to_payload()

    def submit(ch):
        args = (payload, ch, [ids[i] for i in ch], points[ch].tolist())
        if client is not None:
            return client.submit(compute_chunk, *args, pure=False)
        return executor.submit(compute_chunk, *args)

    bar = None
    if progress and pending:
        from tqdm import tqdm

        bar = tqdm(total=len(pending), unit="pt", desc=f"sweep {spec.name}", smoothing=0.1)
    try:
        queue = list(reversed(chunks))
        if client is not None:
            from dask.distributed import as_completed

            first = [submit(queue.pop()) for _ in range(min(limit, len(queue)))]
            ac = as_completed(first)
            for fut in ac:
                rows = fut.result()
                _write_part(pdir, rows, spec)
                if bar is not None:
                    bar.update(len(rows))
                if queue:
                    ac.add(submit(queue.pop()))
        else:
            running = set()
            while queue or running:
                while queue and len(running) < limit:
                    running.add(submit(queue.pop()))
                finished, running = wait(running, return_when=FIRST_COMPLETED)
                for fut in finished:
                    rows = fut.result()
                    _write_part(pdir, rows, spec)
                    if bar is not None:
                        bar.update(len(rows))
    finally:
        if bar is not None:
            bar.close()
        if executor is not None:
            executor.shutdown(wait=True, cancel_futures=True)
        if own_client:
            client.close()

    frames = [f for f in _read_parts(pdir) if len(f)]
    table = pd.concat(frames, ignore_index=True) if frames else rows_to_frame([], spec)
    keep = np.fromiter((x in id_set for x in table["point_id"].astype(object)), bool, len(table))
    table = table[keep]
    table = table.drop_duplicates("point_id").sort_values("point_index", kind="stable")
    table = table.reset_index(drop=True)
    missing = len(ids) - len(table)
    if missing:  # pragma: no cover - every chunk is written before we get here
        raise RuntimeError(f"sweep: {missing} points have no result in {pdir}")
    attrs = {"sweep_name": spec.name, "fingerprint": spec.fingerprint(),
             "axes": json.dumps(spec.columns), "compute": json.dumps(list(spec.compute))}
    if output.suffix.lower() in (".h5", ".hdf5"):
        _atomic_hdf5(table, output, attrs)
    else:
        _atomic_parquet(table, output)
    return table


def _task_order(spec: SweepSpec, points: np.ndarray) -> np.ndarray:
    """Point order for chunking: the speed axis varies fastest, so that a chunk holds
    whole speed lines (one scene parse, one vectorised stability batch and one set of
    critical speeds per line)."""
    cols = spec.columns
    if not cols:
        return np.arange(len(points))
    sp = [j for j, k in enumerate(cols) if k in SPECIAL_KEYS]
    others = [j for j in range(len(cols)) if j not in sp]
    order = others + sp                      # primary ... fastest
    return np.lexsort(tuple(points[:, j] for j in reversed(order)))  # stable: ties keep index order


def _write_part(pdir: Path, rows: list, spec: SweepSpec) -> None:
    df = rows_to_frame(rows, spec)
    first = int(df["point_index"].min()) if len(df) else 0
    name = f"part-{first:09d}-{uuid.uuid4().hex[:8]}.parquet"
    _atomic_parquet(df, pdir / name)


# =====================================================================  CLI glue
def add_sweep_arguments(parser) -> None:
    """Add the arguments of ``stand sweep`` to an ``argparse`` (sub)parser.

    ``stand sweep SWEEP.toml -o results.parquet [--scheduler ADDRESS] [--workers N]
    [--chunk-size N] [--no-resume] [--no-progress] [--regime-map PNG]
    [--critical-map PNG]``
    """
    parser.add_argument("spec", help="SWEEP.toml")
    parser.add_argument("-o", "--output", required=True,
                        help="results table: .parquet (default) or .h5; checkpoints in OUTPUT.parts/")
    parser.add_argument("--scheduler", default=None,
                        help="Dask scheduler address tcp://host:port (default: local process pool; "
                             "'serial': in this process)")
    parser.add_argument("--workers", type=int, default=None,
                        help="local worker processes (default: all cores)")
    parser.add_argument("--chunk-size", type=int, default=None, help="points per task")
    parser.add_argument("--no-resume", action="store_true",
                        help="discard finished parts and start again")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--regime-map", default=None, help="also draw the regime map (PNG)")
    parser.add_argument("--critical-map", default=None,
                        help="also draw the critical-speed map (PNG; theory sweeps)")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")


def sweep_main(args) -> int:
    """Entry point of ``stand sweep`` given parsed arguments.

    Parameters
    ----------
    args : argparse.Namespace
        Attributes (see :func:`add_sweep_arguments`): ``spec`` (path),
        ``output`` (path), and optionally ``scheduler`` (str or None),
        ``workers`` (int or None), ``chunk_size`` (int or None), ``no_resume``,
        ``no_progress``, ``json`` (bool), ``regime_map``, ``critical_map``
        (PNG paths or None).

    Returns
    -------
    int
        0: every point succeeded; 1: the table was written but some points
        failed (``status = "error"``); 2: invalid sweep file (message on stderr).
    """
    import sys

    g = lambda name, default=None: getattr(args, name, default)  # noqa: E731
    try:
        spec = load_sweep(args.spec)
    except SweepSpecError as exc:
        print(f"stand sweep: {exc}", file=sys.stderr)
        return 2
    workers, chunk = g("workers"), g("chunk_size")
    for name, v in (("--workers", workers), ("--chunk-size", chunk)):
        if v is not None and v < 1:
            print(f"stand sweep: {name} = {v}: must be >= 1", file=sys.stderr)
            return 2
    t0 = time.perf_counter()
    table = run_sweep(spec, args.output, scheduler=g("scheduler"), workers=workers,
                      chunk_size=chunk, resume=not g("no_resume", False),
                      progress=not g("no_progress", False))
    wall = time.perf_counter() - t0
    from . import maps

    made = []
    if g("regime_map"):
        maps.regime_map(table, g("regime_map"), spec=spec)
        made.append(g("regime_map"))
    if g("critical_map"):
        maps.critical_speed_map(table, g("critical_map"), spec=spec)
        made.append(g("critical_map"))
    n_err = int((table["status"] != "ok").sum())
    summary = {"sweep": spec.name, "points": len(table), "failed": n_err, "output": str(args.output),
               "wall_time_s": wall, "points_per_s": len(table) / wall if wall > 0 else None,
               "maps": made}
    if g("json"):
        print(json.dumps(summary))
    else:
        print(f"{spec.name}: {len(table)} points ({n_err} failed) in {wall:.1f} s -> {args.output}")
        if n_err:
            first = table.loc[table["status"] != "ok", "error"].iloc[0]
            print(f"first failure: {first}")
    return 1 if n_err else 0
