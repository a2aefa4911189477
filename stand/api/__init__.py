"""The flat Python API: ``stand.load``, ``run``, ``read``, ``theory``, ``analyze``, ``report``.

Every function takes every scene (planar rotor, any rotor of the family, a
book weight model) and every recording::

    import stand
    scene = stand.load("data_samples/scenes/ball_runup.toml")
    run = stand.run(scene)                 # stand.Run: t, planes, rotor, weights, stats
    run.to_frame()                         # pandas, SI units in the column names
    stand.save(run, "runup.h5")            # the one recording layout
    rec = stand.read("runup.h5")           # stand.Recording: the same fields
    stand.analyze(rec)                     # identification (dsp): an Analysis
    stand.report(rec, html_path="r.html")  # balancing-quality report: a Report
    stand.theory(scene)                    # what the theory predicts: a Theory
    stand.track("runup.h5")                # the screen's spot in each frame: a Track
    stand.balance("job.toml")              # field balancing from readings: a FieldBalance
    stand.fit("scene.toml", "rec.csv", free=["supports.stiffness", "balancer.drag"],
              recording_map="rec.map.toml")    # the scene calibrated to a record: a Fit

The answers are result objects (:mod:`stand.io.result`, docs/results.md): attribute
and mapping access, ``to_dict()`` (the JSON the command line prints), ``to_frame()``
and ``plot(ax=)``.

What else the ``stand`` command needs lives in submodules by job, not exported from ``stand``:
:mod:`.simulation` (``save`` a run, experiment programmes, accuracy, stress), :mod:`.analysis`
(folders of recordings, two-plane and influence balancing, DAQ exports), :mod:`.images`
(snapshots, track files, videos), :mod:`.sweep` and :mod:`.warmup`.  :mod:`stand.cli` calls
only these (tests/test_architecture.py).
"""
from __future__ import annotations

import os
from typing import Optional, Union

__all__ = ["load", "run", "save", "read", "theory", "analyze", "report", "track", "balance",
           "fit"]


def load(source: Union[str, os.PathLike]):
    """Read a scene file (any form) or TOML text into a :class:`stand.scene.model.Scene`."""
    from stand.scene.parse import load_scene

    return load_scene(source)


def run(scene, method: Optional[str] = None, rtol: Optional[float] = None,
        atol: Optional[float] = None, progress: bool = False, checkpoint=None):
    """Integrate a scene (or a scene file) with its instruments; returns a :class:`stand.Run`.

    Parameters
    ----------
    scene : Scene, str or os.PathLike
    method : str, optional
        ``"auto"``, ``"DOP853"``, ``"Radau"``, ``"BDF"``, ``"LSODA"``, ``"numpy-DOP853"``
        (overrides the scene's ``run.method``).
    rtol, atol : float, optional
        Override the scene's tolerances.
    progress : bool
        Progress bar on stderr for long runs.
    checkpoint : path, optional
        Resumable compiled DOP853 runs (:func:`stand.integrate.simulate.simulate`).

    Returns
    -------
    Run
        ``run.stats.status`` is 0 on success, negative when the run stopped early
        (what was computed is kept); ``run.instruments`` the instruments' output in
        memory, stored by :func:`save`.
    """
    from stand.scene.model import Scene

    if not isinstance(scene, Scene):
        scene = load(scene)
    if scene.instruments:
        from stand.instruments.pipeline import run_with_instruments

        return run_with_instruments(scene, method=method, progress=progress,
                                    checkpoint=checkpoint, rtol=rtol, atol=atol)
    from stand.integrate.simulate import simulate

    return simulate(scene, method=method, rtol=rtol, atol=atol, progress=progress,
                    checkpoint=checkpoint)


def save(run, path: Union[str, os.PathLike], *, attrs=None):
    """Write a run (with what its instruments output) to the one HDF5 recording layout,
    atomically (:func:`stand.recording.write.write_recording`); returns the path.

    Parameters
    ----------
    run : Run
        :func:`run`'s answer (or a :class:`stand.Recording`).
    path : str or os.PathLike
        Target file (``*.h5``); its directory must exist.
    attrs : mapping, optional
        Further root attributes (e.g. the command that made the run; mappings as JSON).
    """
    from stand.recording.write import write_recording

    return write_recording(run, path, extra_attrs=attrs)


def read(path: Union[str, os.PathLike]):
    """Read a recording into a :class:`stand.Recording` (:func:`stand.recording.hdf5.read_recording`)."""
    from stand.recording.hdf5 import read_recording

    return read_recording(path)


def theory(scene, max_speed: Optional[float] = None, floquet: bool = True):
    """What the theory says of a scene (:func:`stand.theories.scene.theory`): a
    :class:`stand.theories.result.Theory`.

    ``max_speed`` [rev/s] is the upper end of the speed scans.
    """
    from stand.scene.model import Scene
    from stand.theories.scene import theory as _theory

    if not isinstance(scene, Scene):
        scene = load(scene)
    return _theory(scene, max_speed=max_speed, floquet=floquet)


def _recording_map(recording_map, columns):
    """A RecordingMap from a map object, a TOML path and/or a ``--columns`` string."""
    from stand.lab.recording_map import RecordingMap, map_from_options

    if isinstance(recording_map, RecordingMap):
        extra = map_from_options(columns) if columns else None
        return recording_map if extra is None else recording_map.merged(extra)
    return map_from_options(columns, recording_map)


def analyze(source, grade: float = 6.3, service_speed_rpm: Optional[float] = None,
            recording_map=None, columns: Optional[str] = None, *,
            grade_mm_s: Optional[float] = None):
    """Identification from a recording (:func:`stand.analysis.identify.analyze`): a Run, a Recording,
    or a path (HDF5 recording, or a lab table: CSV, Parquet, pandas HDF5).

    ``grade`` is the required ISO 21940-11 grade G [mm/s] (``grade_mm_s``: its old name,
    deprecated).  ``recording_map`` (a :class:`stand.lab.recording_map.RecordingMap` or the
    path of a TOML map) and ``columns`` (``"time=time_ms[ms],x=..."``) say which column of
    a table is what (docs/lab_recordings.md).  Returns a
    :class:`stand.analysis.results.Analysis`."""
    from stand.analysis.identify import analyze as _analyze
    from stand.io.result import renamed

    grade = renamed(grade, grade_mm_s, "grade_mm_s", "grade", "stand.analyze")
    return _analyze(source, grade=grade, service_speed_rpm=service_speed_rpm,
                    recording_map=_recording_map(recording_map, columns))


def report(source, *, html_path=None, json_path=None, grade: float = 6.3,
           service_speed_rpm: Optional[float] = None, recording_map=None,
           columns: Optional[str] = None, pdf_path=None, tracks=None):
    """Balancing-quality report (:func:`stand.reports.balancing.balancing_report`) of a Run,
    a Recording or a path (``recording_map`` / ``columns`` for lab tables, as
    :func:`analyze`): a view of :func:`analyze`'s result, whose document it embeds unchanged
    as ``analysis`` -- every input ``analyze`` takes, ``report`` takes.

    A Run or a Recording is read where it is (nothing is written but what is asked for);
    ``html_path`` / ``json_path`` / ``pdf_path`` are written when given.  ``grade`` is the
    required ISO 21940-11 grade G [mm/s].  Returns a :class:`stand.reports.result.Report`
    (the report's JSON document)."""
    from stand.reports.balancing import balancing_report

    rmap = None if not isinstance(source, (str, os.PathLike)) else _recording_map(recording_map, columns)
    return balancing_report(source, grade=grade, service_speed_rpm=service_speed_rpm,
                            html_path=html_path, json_path=json_path, recording_map=rmap,
                            pdf_path=pdf_path, tracks=tracks)


def track(source, *, strobe: bool = False, **options):
    """The laser spot of a screen's frames (:func:`stand.analysis.tracking.track_frames`,
    ``stand track``), or with ``strobe=True`` the weights' angles in stroboscope frames
    (:func:`stand.analysis.tracking.strobe_angles`, ``stand strobe``).

    ``source``: a recording (``RUN.h5[:dataset]``), a video or images; ``options`` are the
    keywords of those functions (``screen=``, ``calibration=``, ``n_weights=``, ...).
    Returns a :class:`stand.analysis.results.Track`: ``to_frame()`` one row per frame
    (the CSV ``stand track`` writes), ``plot(ax=)`` the spot's path."""
    from stand.analysis.results import Track
    from stand.analysis.tracking import strobe_angles, track_frames

    df = (strobe_angles if strobe else track_frames)(os.fspath(source), **options)
    return Track(df, source=source, strobe=strobe)


def balance(job, *, influence=None, method: Optional[str] = None, html_path=None, pdf_path=None,
            json_path=None):
    """Field balancing from a job file of readings
    (:func:`stand.analysis.field_balance.balance_job`; the contract is in the README).

    ``influence``: a saved influence file (``--save-influence``) instead of the job's trial
    runs; ``method`` overrides the job's.  ``html_path`` / ``pdf_path`` / ``json_path``: the
    field-balancing report (:mod:`stand.reports.field_balancing`), written when given.
    Returns a :class:`stand.analysis.field_balance.FieldBalance`."""
    from stand.analysis.field_balance import balance_job

    res = balance_job(job, influence=influence, method=method)
    if html_path or pdf_path or json_path:
        from stand.reports.field_balancing import write_field_report

        write_field_report(res, html_path, pdf=pdf_path, json_path=json_path)
    return res


def fit(scene, data, free, *, recording_map=None, columns: Optional[str] = None,
        workers: Optional[int] = None, scheduler=None, progress=False,
        runout: Optional[bool] = None, initial_state: Optional[bool] = None,
        max_nfev: int = 40, rtol: float = 1e-9):
    """Calibrate a scene to a record (:func:`stand.fitting.solve.fit_scene`, ``stand fit``).

    The simulation is driven as the record was (the rotor angle of its keyphasor, encoder or
    tachometer, with what that source leaves open of it) and read as its sensors read the
    shaft; the values named in ``free`` are adjusted by nonlinear least squares (scans of
    each value on the record's first stretch, then continuation over the record).

    Parameters
    ----------
    scene : str, os.PathLike or Scene
        The template scene (a file, TOML text, or a Scene read from a file).
    data : str, os.PathLike, Run or Recording
        Anything :func:`analyze` reads: a lab table (with ``recording_map`` / ``columns``), a
        stand recording with probes, a Run.
    free : str or sequence
        Dotted TOML paths of the scene values to fit, each with optional bounds in the file's
        units: ``"supports.stiffness=1000..3000,rotor.unbalance_angle,balancer.drag"``, or a
        list of such strings or of ``(path, (lo, hi))``.  A path to a list frees every element.
    recording_map, columns
        As for :func:`analyze`.
    workers, scheduler
        Where the Jacobian's simulations run: local processes (default: all cores), or a
        dask.distributed scheduler address (as ``stand sweep``).
    progress : bool or callable
        Iteration, cost and values on stderr (or to the callable).
    runout, initial_state : bool, optional
        Fit a probe runout / the shaft's initial state (default: decided from the record).

    Returns
    -------
    stand.fitting.result.Fit
        ``parameters`` (value, std, unit, identifiable per path), ``correlation``, ``fit``
        (chi2_dof, rms_residual, ...), ``comparison`` (theory against experiment), ``scene``
        (the fitted Scene), ``write_scene(path)``, ``to_frame()``, ``plot(ax=)``.
    """
    from stand.fitting.solve import fit_scene

    rmap = None if not isinstance(data, (str, os.PathLike)) else _recording_map(recording_map, columns)
    return fit_scene(scene, data, free, recording_map=rmap, workers=workers,
                     scheduler=scheduler, progress=progress, runout=runout,
                     initial_state=initial_state, max_nfev=max_nfev, rtol=rtol)
