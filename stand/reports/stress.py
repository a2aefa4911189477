"""``stand stress``: numerical stability on stiff and extreme cases.

One data file, the *catalogue* (TOML, default :data:`DEFAULT_CATALOGUE`,
``stress_catalogue.toml`` beside this module), lists the cases; users extend
it by adding ``[[case]]`` tables (docs/reports_stress.md, section "Stress
catalogue (stand stress)").  Each case names a *kind* (which model is run and
how), its *params*, the *check* (what is compared with what), a *tolerance*
and a *time budget*.  :func:`run_stress` runs them and returns a JSON document
(schema :data:`SCHEMA` / :data:`CASE_SCHEMA`), optionally written as JSON and
as one self-contained HTML file through :mod:`stand.reports.html` (the verdict
banner, then one line per case, "NAME: passed" / "NAME: failed — why":
:mod:`stand.reports.stress_page`).

For every case the report gives: the method chosen (``"auto"`` unless the
case asks otherwise) and why, whether the run converged, the error against
an oracle (closed form, theory) or against a converged reference with the
reference's own estimated error, the drift of a conserved quantity where one
exists (free-whirl amplitude of an undamped run-up, energy of an unforced
undamped system, the Jacobi integral of an undamped rotor at constant speed,
the balanced state's residual), the wall time, and pass/fail with a reason.

Kinds and checks
----------------
``dimensionless`` (planar ball balancer from the book's dimensionless
parameters, :func:`stand.scene.parse.scene_from_dimensionless`, omega_1 = 1
rad/s so t [s] = tau):

* ``balanced`` -- residual unbalance |psi|/S at the end against the main
  motion of the theory: 0 for e0 <= 1, e0 - 1 for e0 > 1 (all weights on
  the light side, digest 4.5); stability of the main motion from
  :func:`stand.theories.planar.main_motion.is_stable`.
* ``locked`` -- huge ball drag: the shaft against the closed form of the same
  rotor with the weights locked at their initial angles (the limit h -> inf,
  :func:`stand.integrate.accuracy.closed_form_no_balancer`).
* ``energy`` -- h = H = 0, e0 = 0: the total energy (shaft + weights +
  supports) is conserved; relative drift.
* ``jacobi`` -- h = H = 0, constant speed, isotropic supports: the Jacobi
  integral E - omega p_theta (energy in the frame turning with the rotor) is
  conserved; relative drift.
* ``reference`` -- only the comparison with a converged reference run.

``scene_file`` (a TOML scene): ``runup_closed_form`` (weight-free run-up at
constant acceleration, :func:`stand.integrate.accuracy.runup_params`: error against the
Fresnel/Faddeeva closed form and, undamped, drift of the free-whirl amplitude
|c+|) or ``closed_form`` (weight-free, constant speed).

``liquid_runup`` (paper-001 liquid float balancer, model M1,
:mod:`stand.model.balancers.liquid_float`, run as the one model's composition):
``runup_closed_form``.

``platform`` (paper-004 suspended platform, :func:`platform_rotor`,
:func:`simulate_coupled`): ``steady_response`` (no weights, started on the
exact steady unbalance response, which it must keep) or ``balanced`` (two
balls: static residual / unbalance at the end).

``qp_threshold`` (stuck balls near the escape speed R*_omega = 1 + 2 Rt/(h H)
of :mod:`stand.theories.planar.qp`, e0 = 0, started on the quasi-periodic motion with a
small separation of the balls): ``qp_persists`` (R < R*: the precession speed
must stay Omega_1 of (5.181)) or ``escape`` (R > R*: the balls leave the QP
motion and balance).

``body_scene`` (a TOML scene with body weights -- two-axis pendulum, coupled
pair, damper, liquid float, liquid chamber -- on the generic kernel,
:mod:`stand.reports.stress_bodies`): ``runup_closed_form`` (one liquid lever
on the planar rotor is paper 001's model M1 itself: closed-form run-up,
free-whirl drift undamped), ``steady_theory`` (one tilting weight or damper on
the planar rotor held at speed: residual unbalance / M e at the end against
the book's stable main motions, spread over the last 30 % as the drift) or
``reference``.

Pass rule: the solver succeeded, the error (and the drift, where checked) is
within the tolerance, the method is the expected one if the case names it,
the case ran within its time budget, and the case is inside the model's
validity -- or, if the runner finds it outside (the reason is stated
precisely), the catalogue declares it so with ``outside_validity``.

Modules: the catalogue is read and validated by
:mod:`stand.reports.stress_catalogue` (:func:`load_catalogue`,
:class:`CatalogueError`, :data:`KINDS`), the cases are run by
:mod:`stand.reports.stress_cases` and :mod:`stand.reports.stress_planar`
(a new kind: a runner registered in ``stress_cases.RUNNERS`` and its spec in
``KINDS``); this module judges each case and writes the report.  The public
names stay importable from here.
"""
from __future__ import annotations

import sys
import time

import numpy as np

from stand.io.jsonable import to_jsonable
from stand.reports.html import figure_png, write_report
from stand.reports.stress_cases import RUNNERS, outcome, warm
from stand.reports.stress_catalogue import (DEFAULT_CATALOGUE, KINDS, CatalogueError, load_catalogue,
                               select_cases)
from stand.reports.stress_page import stress_banner, stress_body

__all__ = ["run_stress", "load_catalogue", "CatalogueError", "SCHEMA", "CASE_SCHEMA",
           "DEFAULT_CATALOGUE", "KINDS"]

TITLE = "stand stress: numerical stability on stiff and extreme cases"

#: JSON schema of the whole document (structure checked by :func:`stand.reports.html.check_schema`)
SCHEMA = {
    "summary": {
        "catalogue": "string",
        "n_cases": "number",
        "n_passed": "number",
        "n_failed": "number",
        "all_passed": "bool",
        "total_time_s": "number",
        "python": "string",
    },
    "cases": "list",
}
#: JSON schema of one entry of ``cases``
CASE_SCHEMA = {
    "name": "string",
    "kind": "string",
    "description": "string",
    "check": "string",
    "method": "string",
    "method_reason": "string",
    "solver_success": "bool",
    "solver_message": "string",
    "converged": "bool",
    "oracle": "string",
    "error": "number|null",
    "error_measure": "string",
    "tolerance": "number",
    "reference_error": "number|null",
    "conserved_quantity": "string|null",
    "drift": "number|null",
    "nfev": "number|null",
    "wall_time_s": "number",
    "case_time_s": "number",
    "time_budget_s": "number",
    "outside_validity": "string|null",
    "declared_outside_validity": "string|null",
    "pass": "bool",
    "reason": "string",
    "details": "object",
}

#: kind -> runner (:data:`stand.reports.stress_cases.RUNNERS`; register a new kind there and in KINDS)
_RUNNERS = RUNNERS


# ------------------------------------------------------------------ one case
def _run_case(case: dict) -> dict:
    """Warm up, run and judge one case (the pass rule of the module docstring).

    Parameters
    ----------
    case : dict
        One case of :func:`load_catalogue`.

    Returns
    -------
    dict
        The keys of :data:`CASE_SCHEMA`, in that order; times in s.

    Raises
    ------
    CatalogueError
        The case cannot be run as written (e.g. its scene file is invalid); any
        other exception is a failed case, not an error.
    """
    res = outcome()
    t_warm = time.perf_counter()
    try:
        warm(case)
    except Exception:  # the timed run reports the problem
        pass
    res["details"]["warm_up_s"] = time.perf_counter() - t_warm
    tic = time.perf_counter()
    invalid: list = []
    exc_msg = None
    try:
        invalid = RUNNERS[case["kind"]](case, res) or []
    except CatalogueError:
        raise
    except Exception as exc:  # a numerical failure is a result, not a crash of the report
        exc_msg = f"{type(exc).__name__}: {exc}"
    case_time = time.perf_counter() - tic
    tol = case["tolerance"]
    reasons_fail, reasons_ok = [], []
    if exc_msg:
        reasons_fail.append(f"the case raised {exc_msg}")
    conv_tol = case["convergence_tolerance"]
    ref_diff = res["details"].get("reference_difference")
    converged = bool(res["solver_success"]) and (ref_diff is None or ref_diff <= conv_tol)
    res["converged"] = converged
    if not res["solver_success"] and not exc_msg:
        reasons_fail.append(f"the solver did not finish: {res['solver_message']}")
    elif ref_diff is not None and ref_diff > conv_tol:
        reasons_fail.append(f"not converged: differs from the reference run by {ref_diff:.3g} "
                            f"> convergence_tolerance {conv_tol:g}")
    err = res["error"]
    if err is None or not np.isfinite(err):
        if not invalid and not exc_msg:
            reasons_fail.append("no error could be computed")
    elif err > tol:
        reasons_fail.append(f"error {err:.3g} > tolerance {tol:g} ({res['error_measure']})")
    else:
        reasons_ok.append(f"error {err:.3g} <= tolerance {tol:g}")
    if res.pop("_drift_checked", False) and res["drift"] is not None:
        drift = f"drift of the {res['conserved_quantity']} {res['drift']:.3g}"
        if abs(res["drift"]) > tol:
            reasons_fail.append(f"{drift}: |drift| > tolerance {tol:g}")
        else:
            reasons_ok.append(f"{drift}: |drift| <= tolerance {tol:g}")
    reasons_fail += res.pop("checks", [])
    if case["expect_method"] and not res["method"].startswith(case["expect_method"]):
        reasons_fail.append(f"method {res['method']!r} chosen, the catalogue expects "
                            f"{case['expect_method']!r}")
    if case_time > case["time_budget_s"]:
        reasons_fail.append(f"took {case_time:.3g} s > time budget {case['time_budget_s']:g} s")
    declared = case["outside_validity"]
    if invalid:
        res["outside_validity"] = "; ".join(invalid)
        if not declared:
            reasons_fail.append("outside the model's validity, not declared in the catalogue: "
                                + res["outside_validity"])
        else:
            reasons_ok.append("outside the model's validity as declared in the catalogue ("
                              f"{declared}); detected: {res['outside_validity']}")
    elif declared:
        reasons_ok.append(f"declared outside validity ({declared}), but the runner detected no "
                          "violation")
    passed = not reasons_fail
    res["reason"] = ("; ".join(reasons_ok) if passed else "; ".join(reasons_fail)) or "ok"
    res["pass"] = passed
    res.update(name=case["name"], kind=case["kind"], description=case["description"],
               check=case["check"], tolerance=tol, time_budget_s=case["time_budget_s"],
               case_time_s=case_time, declared_outside_validity=declared)
    res["details"]["params"] = dict(case["params"])
    res["details"]["fast"] = case["fast"]
    order = list(CASE_SCHEMA)
    return {k: res[k] for k in order}


# ------------------------------------------------------------------ report
def _figure(cases):
    """Bar charts of each case's time [s] against its budget and of error / tolerance [-]."""
    from matplotlib.figure import Figure

    names = [c["name"] for c in cases]
    y = np.arange(len(cases))
    fig = Figure(figsize=(11, 0.35 * len(cases) + 1.5))
    a1, a2 = fig.subplots(1, 2, sharey=True)
    colors = ["#070" if c["pass"] else "#b00" for c in cases]
    a1.barh(y, [max(c["case_time_s"], 1e-3) for c in cases], color=colors)
    a1.scatter([c["time_budget_s"] for c in cases], y, marker="|", color="k", s=200, label="budget")
    a1.set_xscale("log")
    a1.set_xlabel("case time [s]")
    a1.set_yticks(y)
    a1.set_yticklabels(names)
    a1.legend(loc="lower right")
    ratio = [(c["error"] / c["tolerance"]) if c["error"] else 1e-12 for c in cases]
    a2.barh(y, [max(r, 1e-12) for r in ratio], color=colors)
    a2.axvline(1.0, color="k", lw=1)
    a2.set_xscale("log")
    a2.set_xlabel("error / tolerance")
    fig.tight_layout()
    return fig


def run_stress(catalogue_path=DEFAULT_CATALOGUE, *, cases=None, html_path=None, json_path=None,
               progress: bool = False) -> dict:
    """Run the stress catalogue; return the JSON document (:data:`SCHEMA`).

    Parameters
    ----------
    catalogue_path : str or Path
        The catalogue (TOML, ``[[case]]`` tables); default the shipped one.
    cases : sequence of str, or "fast", optional
        Run only these cases (by name, in catalogue order), or only the cases
        marked ``fast = true``.  Default: all.
    html_path, json_path : str or Path, optional
        Write the self-contained HTML report / the JSON document (atomically).
    progress : bool
        One line per case on stderr.

    Returns
    -------
    dict
        ``{"summary": {...}, "cases": [{...}, ...]}``; every case has the keys
        of :data:`CASE_SCHEMA`.

    Raises
    ------
    CatalogueError
        Malformed catalogue (names the case and the field) or an unknown name
        in ``cases``.
    """
    todo = select_cases(load_catalogue(catalogue_path), cases, catalogue_path)
    out = []
    tic = time.perf_counter()
    for i, c in enumerate(todo):
        if progress:
            print(f"[{i + 1}/{len(todo)}] {c['name']} ({c['kind']}, {c['check']}) ...", end="",
                  file=sys.stderr, flush=True)
        r = _run_case(c)
        out.append(r)
        if progress:
            print(f" {'pass' if r['pass'] else 'FAIL'} in {r['case_time_s']:.2f} s: {r['reason']}",
                  file=sys.stderr, flush=True)
    total = time.perf_counter() - tic
    n_pass = sum(r["pass"] for r in out)
    doc = {
        "summary": {
            "catalogue": str(catalogue_path),
            "n_cases": len(out),
            "n_passed": n_pass,
            "n_failed": len(out) - n_pass,
            "all_passed": n_pass == len(out),
            "total_time_s": total,
            "python": sys.version.split()[0],
        },
        "cases": out,
    }
    plain = to_jsonable(doc)
    figs = None
    if html_path and out:
        figs = {"case time against budget; error against tolerance (green: pass, red: fail)":
                figure_png(_figure(out))}
    if html_path or json_path:   # verdict first, then one line per case (stress_page)
        write_report(TITLE, plain, html_path=html_path, json_path=json_path, figures=figs,
                     sections=["summary", "cases"], banner=stress_banner(plain),
                     body=lambda d: stress_body(d, figs))
    return plain
