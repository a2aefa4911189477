"""The API of the commands that simulate or predict (``stand run``, ``experiment``, ``accuracy``,
``theory``, ``stress``): each function does one command's work and returns what it prints.

The command line (:mod:`stand.cli`) calls these and nothing below them; they may call anything
of the stand.
"""
from __future__ import annotations

import os
import sys
from typing import Optional, Sequence, Union

from stand.scene.model import METHODS

__all__ = ["METHODS", "experiment", "required_options", "accuracy", "theory_text", "speed_map", "stress",
           "precompile_in_background"]


def experiment(scene, programme: str, output: Union[str, os.PathLike], *, progress: bool = False,
               record: Optional[dict] = None, **options):
    """Run an experiment programme of tables 4.2-4.6 on a scene and write its recording.

    Parameters
    ----------
    scene : Scene, str or os.PathLike
        The stand (a scene file or a Scene).
    programme : str
        A name of :data:`stand.scene.experiments.PROGRAMMES` (``"run-up"``, ``"impact"``, ...).
    output : path
        The recording to write (HDF5); checked before the run.
    progress : bool
        Progress bar on stderr.
    record : dict, optional
        Stored in the recording's ``experiment`` attribute beside the programme's name.
    **options
        The programme builder's arguments (SI units: rev/s, rev/s², s, m, N, N/m, deg);
        None = not given.

    Returns
    -------
    (Run, Scene)
        The run (``run.stats`` says whether it finished) and the programme's scene.

    Raises
    ------
    stand.errors.NotApplicable
        The programme does not apply to this scene (the message says why).
    ValueError
        A required option of the programme is missing (the message names it).
    """
    from stand.api import load, run, save
    from stand.errors import NotApplicable
    from stand.io.atomic import check_output_path
    from stand.scene.experiments import not_applicable, programme as build

    base = scene if not isinstance(scene, (str, os.PathLike)) else load(scene)
    out = check_output_path(output)
    why = not_applicable(base, programme)
    if why:
        raise NotApplicable(why)
    missing = [k for k in required_options(programme) if options.get(k) is None]
    if missing:
        raise ValueError(f"experiment {programme}: {', '.join(missing)} required")
    sc = build(base, programme, **options)
    res = run(sc, progress=progress)
    save(res, out, attrs={"experiment": {"programme": programme, **(record or {})}})
    return res, sc


def required_options(programme: str) -> tuple:
    """The options an experiment programme cannot do without (their keyword names)."""
    from stand.scene.experiments import PROGRAMMES

    return tuple(PROGRAMMES[programme][1])


def accuracy(scene, *, rtols: Optional[Sequence[float]] = None, methods=None, rk4_steps=None,
             fast: bool = False, duration: Optional[float] = None, html_path=None, json_path=None):
    """Error against run time over tolerances and methods (``stand accuracy``).

    ``rtols`` default to the standard ladder (``fast``: 1e-4, 1e-6 against a reference at
    1e-10); ``duration`` [s] runs only the scene's first seconds (a quick check of every
    scene); ``methods`` are names of :data:`METHODS` or ``"RK4"`` (fixed steps ``rk4_steps``
    [s]).  With ``html_path`` / ``json_path`` the report is written
    (:func:`stand.reports.accuracy_report.accuracy_report`) and its JSON document returned;
    else an :class:`stand.integrate.accuracy.AccuracyReport` (``table()``, ``to_dict()``).
    """
    from stand.api import load
    from stand.integrate.accuracy import (DEFAULT_RTOLS, FAST_REFERENCE_RTOL, FAST_RTOLS,
                                          accuracy as _accuracy)

    bad = [m for m in methods or () if m not in METHODS and m != "RK4"]
    if bad:
        raise ValueError(f"methods: unknown {', '.join(bad)}; valid: {', '.join(METHODS)}, RK4")
    scene = scene if not isinstance(scene, (str, os.PathLike)) else load(scene)
    if duration is not None:
        import dataclasses
        import math

        if not 0 < duration < math.inf:
            raise ValueError(f"duration = {duration!r} s: must be > 0 and finite")
        scene = dataclasses.replace(scene, run=dataclasses.replace(
            scene.run, duration=min(float(duration), scene.run.duration)))
    if html_path or json_path:
        from stand.reports.accuracy_report import accuracy_report

        return accuracy_report(scene, rtols=rtols or (1e-4, 1e-6, 1e-8, 1e-10), methods=methods,
                               rk4_steps=rk4_steps, html_path=html_path, json_path=json_path)
    return _accuracy(scene, rtols=rtols or (FAST_RTOLS if fast else DEFAULT_RTOLS), methods=methods,
                     rk4_steps=rk4_steps, reference_rtol=FAST_REFERENCE_RTOL if fast else None)


def theory_text(doc) -> list:
    """A Theory (:func:`stand.theory`) as the lines of text ``stand theory`` prints."""
    from stand.theories.scene import theory_lines

    return theory_lines(doc)


def speed_map(scene, path, max_speed: Optional[float] = None) -> None:
    """Draw the speed map (PNG) of a chapter-5 scene (a Theory of ``kind`` ``"chapter5"``:
    the planar rotor with weights); ``max_speed`` [rev/s] is the map's upper end."""
    import math

    from stand.theories.planar.speedmap import plot_speed_map, scene_theory

    plot_speed_map(scene_theory(scene, R_max=max_speed * 2 * math.pi / scene.natural_frequency
                                if max_speed else None), path)


def stress(catalogue=None, *, cases=None, html_path=None, json_path=None, progress: bool = False):
    """Numerical stability on the stiff and extreme catalogue (:func:`stand.reports.stress.run_stress`,
    the built-in catalogue when ``catalogue`` is None); returns the JSON document."""
    from stand.reports.stress import DEFAULT_CATALOGUE, run_stress

    return run_stress(catalogue or DEFAULT_CATALOGUE, cases=cases, html_path=html_path,
                      json_path=json_path, progress=progress)


def precompile_in_background() -> None:
    """After a command that ran a kernel on numba's JIT: start the build of its precompiled module
    (:mod:`stand.integrate.kernel_set`), so that the next command starts without numba.  Never
    raises (a background build must not spoil the command)."""
    ks = sys.modules.get("stand.integrate.kernel_set")
    if ks is not None:
        try:
            ks.precompile_in_background()
        except Exception:  # noqa: BLE001 - never let a background build spoil the command
            pass
