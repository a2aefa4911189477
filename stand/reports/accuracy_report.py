"""Error against run time (`stand accuracy -o accuracy.html`): the accuracy
ladder of :mod:`stand.integrate.accuracy` as a report with a work-precision plot and the
recommended setting for the scene, stated first ("Use DOP853 at rtol 1e-8:
2e-9 relative error in 0.3 s", :func:`accuracy_banner`)."""
from __future__ import annotations

import math
import re

from stand.reports.html import check_schema, figure_png, write_report

__all__ = ["accuracy_report", "recommend", "accuracy_banner", "SCHEMA", "DEFAULT_TARGET"]

DEFAULT_TARGET = 1e-6     #: relative error a recommended setting must reach

SCHEMA = {
    "scene": "string",
    "reference": {"name": "string", "own_error_m": "number|null", "scale_m": "number"},
    "runs": "list",
    "notes": "list",
    "recommended": "object",
    "units": "object",
}
ROW_SCHEMA = {"method": "string", "rtol": "number|null", "step_s": "number|null",
              "max_error_m": "number|null", "relative_error": "number|null",
              "wall_time_s": "number", "rhs_evaluations": "number", "steps": "number",
              "success": "bool", "free_whirl_drift": "number|null"}


def recommend(rows, target: float = DEFAULT_TARGET) -> dict:
    """The recommended setting: the fastest run that reaches the target.

    Parameters
    ----------
    rows : list of dict
        Runs of the report (:data:`ROW_SCHEMA`; ``relative_error`` [-],
        ``wall_time_s`` [s]).
    target : float
        Relative error the setting must reach [-].

    Returns
    -------
    dict
        ``target_relative_error``, ``reached`` and the chosen row: the fastest
        successful run with ``relative_error <= target``; if none reaches it,
        the most accurate successful run (``reached`` False); no row if no run
        succeeded.
    """
    ok = [r for r in rows if r["success"] and r["relative_error"] is not None]
    good = [r for r in ok if r["relative_error"] <= target]
    if good:
        best = min(good, key=lambda r: r["wall_time_s"])
        return {"target_relative_error": target, "reached": True, **best}
    if ok:
        best = min(ok, key=lambda r: r["relative_error"])
        return {"target_relative_error": target, "reached": False, **best}
    return {"target_relative_error": target, "reached": False}


def _num(x: float, digits: int = 1) -> str:
    """``x`` with ``digits`` significant digits, exponent without padding: 2e-9, 0.31, 12."""
    text = f"{x:.{digits}g}"
    return re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("-" if m[1] == "-" else "") + m[2], text)


def _seconds(t: float) -> str:
    """A wall time [s] to 1-2 significant digits: ``0.79 ms``, ``0.3 s``, ``1.2 s``, ``14 s``."""
    if t >= 10:
        return f"{t:.0f} s"
    return f"{_num(t, 2)} s" if t >= 0.1 else f"{_num(t * 1e3, 2)} ms"


def _setting(rec) -> str:
    """The run's setting in words: ``DOP853 at rtol 1e-8`` / ``RK4 with a fixed step of 1e-3 s``."""
    if rec.get("rtol") is not None:
        return f"{rec['method']} at rtol {_num(rec['rtol'], 6)}"
    return f"{rec['method']} with a fixed step of {_num(rec['step_s'], 6)} s"


def accuracy_banner(doc) -> dict:
    """The recommendation as a verdict banner (:func:`stand.reports.html.banner_html`).

    Parameters
    ----------
    doc : mapping
        The report (:data:`SCHEMA`): ``recommended`` (:func:`recommend`),
        ``reference``, ``runs``.

    Returns
    -------
    dict
        ``status`` "info" when a setting reaches the target, else "fail";
        ``headline`` e.g. "Use DOP853 at rtol 1e-8: 2e-9 relative error in 0.3 s"
        (errors to 1 significant digit, times to 1-2); ``lines``: the target
        and the reference the errors are measured against.
    """
    rec, ref = doc["recommended"], doc["reference"]
    target = _num(rec["target_relative_error"], 2)
    n = len(doc["runs"])
    if rec.get("method") is None:
        status, headline = "fail", f"No run succeeded: no setting to recommend ({n} runs)"
        first = f"Target: relative error ≤ {target}; none of the {n} runs finished."
    else:
        got = (f"{_num(rec['relative_error'])} relative error in {_seconds(rec['wall_time_s'])}")
        if rec["reached"]:
            status, headline = "info", f"Use {_setting(rec)}: {got}"
            first = (f"Target: relative error ≤ {target} (max |r - r_ref| / max |r_ref|); "
                     f"the fastest of the {n} runs that reach it.")
        else:
            status = "fail"
            headline = f"No setting reaches {target}; the most accurate: {_setting(rec)}: {got}"
            first = (f"Target: relative error ≤ {target} (max |r - r_ref| / max |r_ref|); "
                     f"none of the {n} runs reaches it.")
    own = ref.get("own_error_m")
    second = (f"Reference: {ref['name']}"
              + (f" (its own error ~ {_num(own)} m)" if own else "")
              + f"; max |r_ref| = {_num(ref['scale_m'], 2)} m.")
    return {"status": status, "headline": headline, "lines": [first, second]}


def _rows(rep) -> list:
    """The report's rows (:data:`ROW_SCHEMA`) from a :class:`stand.integrate.accuracy` report."""
    out = []
    for r in rep.rows:
        out.append({"method": r.method, "rtol": None if r.method == "RK4" else r.rtol,
                    "atol": None if r.method == "RK4" else r.atol,
                    "step_s": r.step_s if r.method == "RK4" else None,
                    "max_error_m": r.max_error_m, "relative_error": r.relative_error,
                    "wall_time_s": r.wall_time_s, "rhs_evaluations": r.nfev, "steps": r.n_steps,
                    "success": bool(r.success),
                    "free_whirl_drift": r.free_whirl_drift if math.isfinite(r.free_whirl_drift) else None})
    return out


def _plot(rows, title):
    """Work-precision plot (relative error [-] against wall time [s]) as a PNG data URI."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.4))
    ax = fig.subplots()
    for m in sorted({r["method"] for r in rows}):
        pts = [(r["wall_time_s"], r["relative_error"]) for r in rows
               if r["method"] == m and r["relative_error"] and r["wall_time_s"] > 0]
        if pts:
            x, y = zip(*sorted(pts))
            ax.loglog(x, y, "o-", label=m)
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel("max error / max |r|")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return figure_png(fig)


def accuracy_report(scene, *, rtols=(1e-4, 1e-6, 1e-8, 1e-10), methods=None, rk4_steps=None,
                    target: float = DEFAULT_TARGET, html_path=None, json_path=None) -> dict:
    """Run the accuracy ladder and write the report (HTML and/or JSON).

    Parameters
    ----------
    scene : Scene
        The scene to run (:mod:`stand.integrate.accuracy` says which scenes have an
        oracle).
    rtols : sequence of float
        Relative tolerances of the adaptive methods [-].
    methods : sequence of str, optional
        Default: the compiled DOP853, scipy's LSODA and Radau, and fixed-step
        RK4 (every available class of method).
    rk4_steps : sequence of float, optional
        Fixed steps of RK4 [s]; default chosen by :func:`stand.integrate.accuracy.accuracy`.
    target : float
        Relative error the recommended setting must reach [-].
    html_path, json_path : str or Path, optional
        Where to write the self-contained HTML and the JSON (atomically,
        through :mod:`stand.io.atomic`).

    Returns
    -------
    dict
        The report (plain JSON types, :data:`SCHEMA`; rows :data:`ROW_SCHEMA`):
        errors in m and relative to max |r_ref|, times in s; ``verdict`` the
        recommendation in words (:func:`accuracy_banner`), shown first in the HTML.
    """
    from stand.integrate.accuracy import accuracy

    if methods is None:
        methods = ["DOP853", "LSODA", "Radau", "RK4"]
    rep = accuracy(scene, rtols=rtols, methods=methods, rk4_steps=rk4_steps)
    rows = _rows(rep)
    doc = {
        "scene": rep.scene,
        "reference": {"name": rep.reference + (f"; compared over t = 0 to {rep.compared_to_s:.4g} s"
                                               if math.isfinite(rep.compared_to_s) else ""),
                      "own_error_m": rep.reference_error_m, "scale_m": rep.scale_m},
        "runs": rows,
        "notes": list(rep.notes or []),
        "recommended": recommend(rows, target),
        "units": {"max_error_m": "m (max over the samples of |r - r_ref|, r = x + i y)",
                  "relative_error": "max error / max |r_ref|", "wall_time_s": "s",
                  "step_s": "s (fixed-step RK4)", "free_whirl_drift":
                  "relative change of the free-whirl amplitude |c+| at the end of the run-up"},
    }
    doc["verdict"] = accuracy_banner(doc)
    figs = {"work-precision: error against wall time": _plot(rows, rep.scene)} if html_path else None
    plain = write_report(f"Error against run time: {rep.scene}", doc, html_path, json_path, figs,
                         sections=("scene", "recommended", "reference", "notes", "runs", "units"),
                         banner=doc["verdict"])
    problems = check_schema(plain, SCHEMA)
    for i, r in enumerate(plain["runs"]):
        problems += check_schema(r, ROW_SCHEMA, f"runs[{i}].")
    if problems:   # pragma: no cover - a programming error
        raise AssertionError("accuracy report does not match its schema: " + "; ".join(problems))
    return plain
