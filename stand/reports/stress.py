"""``stand stress``: numerical stability on stiff and extreme cases.

One data file, the *catalogue* (TOML, default :data:`DEFAULT_CATALOGUE`,
``stress_catalogue.toml`` beside this module), lists the cases; users extend
it by adding ``[[case]]`` tables (docs/reports_stress.md, section "Stress
catalogue (stand stress)").  Each case names a *kind* (which model is run and
how), its *params*, the *check* (what is compared with what), a *tolerance*
and a *time budget*.  :func:`run_stress` runs them and returns a JSON document
(schema :data:`SCHEMA` / :data:`CASE_SCHEMA`), optionally written as JSON and
as one self-contained HTML file through :mod:`stand.reports.html`.

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
parameters, :func:`stand.scene_file.scene_from_dimensionless`, omega_1 = 1
rad/s so t [s] = tau):

* ``balanced`` -- residual unbalance |psi|/S at the end against the main
  motion of the theory: 0 for e0 <= 1, e0 - 1 for e0 > 1 (all weights on
  the light side, digest 4.5); stability of the main motion from
  :func:`stand.planar_theory.main_motion.is_stable`.
* ``locked`` -- huge ball drag: the shaft against the closed form of the same
  rotor with the weights locked at their initial angles (the limit h -> inf,
  :func:`stand.accuracy.closed_form_no_balancer`).
* ``energy`` -- h = H = 0, e0 = 0: the total energy (shaft + weights +
  supports) is conserved; relative drift.
* ``jacobi`` -- h = H = 0, constant speed, isotropic supports: the Jacobi
  integral E - omega p_theta (energy in the frame turning with the rotor) is
  conserved; relative drift.
* ``reference`` -- only the comparison with a converged reference run.

``scene_file`` (a TOML scene): ``runup_closed_form`` (weight-free run-up at
constant acceleration, :func:`stand.accuracy.runup_params`: error against the
Fresnel/Faddeeva closed form and, undamped, drift of the free-whirl amplitude
|c+|) or ``closed_form`` (weight-free, constant speed).

``liquid_runup`` (paper-001 liquid float balancer, model M1,
:mod:`stand.balancers.liquid_float`): ``runup_closed_form``.

``platform`` (paper-004 suspended platform, :func:`platform_rotor`,
:func:`simulate_coupled`): ``steady_response`` (no weights, started on the
exact steady unbalance response, which it must keep) or ``balanced`` (two
balls: static residual / unbalance at the end).

``qp_threshold`` (stuck balls near the escape speed R*_omega = 1 + 2 Rt/(h H)
of :mod:`stand.planar_theory.qp`, e0 = 0, started on the quasi-periodic motion with a
small separation of the balls): ``qp_persists`` (R < R*: the precession speed
must stay Omega_1 of (5.181)) or ``escape`` (R > R*: the balls leave the QP
motion and balance).

Pass rule: the solver succeeded, the error (and the drift, where checked) is
within the tolerance, the method is the expected one if the case names it,
the case ran within its time budget, and the case is inside the model's
validity -- or, if the runner finds it outside (the reason is stated
precisely), the catalogue declares it so with ``outside_validity``.
"""
from __future__ import annotations

import dataclasses
import math
import sys
import time
import warnings
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

from .html import check_schema, figure_png, jsonable, write_report

__all__ = ["run_stress", "load_catalogue", "CatalogueError", "SCHEMA", "CASE_SCHEMA",
           "DEFAULT_CATALOGUE", "KINDS"]

DEFAULT_CATALOGUE = Path(__file__).with_name("stress_catalogue.toml")
REPO_ROOT = Path(__file__).resolve().parents[2]
TITLE = "stand stress: numerical stability on stiff and extreme cases"

#: JSON schema of the whole document (structure checked by :func:`check_schema`)
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


class CatalogueError(ValueError):
    """A malformed catalogue; the message names the case and the field."""


# ------------------------------------------------------------------ catalogue
_CASE_FIELDS = ("name", "kind", "description", "check", "tolerance", "time_budget_s", "fast",
                "outside_validity", "expect_method", "reference_rtol", "convergence_tolerance",
                "params")

_NUM, _INT, _STR, _BOOL, _LIST = "number", "integer", "string", "boolean", "array"


def _p(kind, default=..., *, gt=None, ge=None, lt=None, choices=None):
    return dict(kind=kind, default=default, gt=gt, ge=ge, lt=lt, choices=choices)


_DIMLESS = {
    "n": _p(_INT, ge=1), "Rt": _p(_NUM, ge=0, lt=0.5), "h": _p(_NUM, ge=0), "H": _p(_NUM, ge=0),
    "e0": _p(_NUM, ge=0), "R": _p(_NUM, None, gt=0), "programme": _p(_LIST, None),
    "R_omega2": _p(_NUM, 1.0, gt=0), "duration_tau": _p(_NUM, gt=0),
    "sample_rate": _p(_NUM, 1.0, gt=0), "rtol": _p(_NUM, 1e-9, gt=0), "atol": _p(_NUM, None, gt=0),
    "method": _p(_STR, "auto", choices=("auto", "DOP853", "Radau", "BDF", "LSODA")),
    "initial_angles_deg": _p(_LIST, None), "initial_x": _p(_NUM, 0.0),
    "initial_speeds": _p(_NUM, 0.0), "max_steps": _p(_INT, 50_000_000, ge=1),
}
_SCENE_FILE = {
    "path": _p(_STR), "rtol": _p(_NUM, None, gt=0), "atol": _p(_NUM, None, gt=0),
    "method": _p(_STR, "auto", choices=("auto", "DOP853", "Radau", "BDF", "LSODA")),
}
_LIQUID = {
    "psi": _p(_NUM, gt=0), "n": _p(_NUM, 0.0, ge=0), "Omega_0": _p(_NUM, 1000.0, gt=0),
    "e": _p(_NUM, 1e-4, gt=0), "omega_0": _p(_NUM, 40.0, ge=0), "acceleration": _p(_NUM, gt=0),
    "t_end": _p(_NUM, gt=0), "sample_rate": _p(_NUM, 100.0, gt=0), "rtol": _p(_NUM, 1e-10, gt=0),
    "frame": _p(_STR, "rotating", choices=("rotating", "fixed")),
    "method": _p(_STR, "DOP853", choices=("DOP853", "RK45", "Radau", "BDF", "LSODA")),
}
_PLATFORM = {
    "speed": _p(_NUM, gt=0), "duration": _p(_NUM, gt=0), "sample_rate": _p(_NUM, 100.0, gt=0),
    "rtol": _p(_NUM, 1e-10, gt=0), "atol": _p(_NUM, None, gt=0),
    "ball_mass": _p(_NUM, 0.1, gt=0), "ball_radius": _p(_NUM, 0.1, gt=0),
    "ball_drag": _p(_NUM, 2.0, ge=0), "initial_angles_deg": _p(_LIST, [60.0, 250.0]),
    "max_rotation": _p(_NUM, 0.05, gt=0),
}
_QP = {
    "Rt": _p(_NUM, gt=0, lt=0.5), "h": _p(_NUM, gt=0), "H": _p(_NUM, gt=0),
    "offset": _p(_NUM), "duration_tau": _p(_NUM, gt=0), "separation": _p(_NUM, 1e-3, ge=0),
    "sample_rate": _p(_NUM, 1.0, gt=0), "rtol": _p(_NUM, 1e-10, gt=0), "atol": _p(_NUM, None, gt=0),
    "method": _p(_STR, "auto", choices=("auto", "DOP853", "Radau", "BDF", "LSODA")),
}

#: kind -> (parameter spec, valid checks)
KINDS = {
    "dimensionless": (_DIMLESS, ("balanced", "locked", "energy", "jacobi", "reference")),
    "scene_file": (_SCENE_FILE, ("runup_closed_form", "closed_form", "reference")),
    "liquid_runup": (_LIQUID, ("runup_closed_form",)),
    "platform": (_PLATFORM, ("steady_response", "balanced")),
    "qp_threshold": (_QP, ("qp_persists", "escape")),
}


def _tname(v):
    if isinstance(v, bool):
        return "a boolean"
    if isinstance(v, str):
        return "a string"
    if isinstance(v, list):
        return "an array"
    if isinstance(v, Mapping):
        return "a table"
    return f"a {type(v).__name__}"


def _check_value(where: str, key: str, v, spec) -> Any:
    k = spec["kind"]
    bad = f"{where}: field {key} = {v!r}: "
    if k == _NUM:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
            raise CatalogueError(bad + f"must be a finite number, not {_tname(v)}")
        v = float(v)
        if spec["gt"] is not None and not v > spec["gt"]:
            raise CatalogueError(bad + f"must be > {spec['gt']}")
        if spec["ge"] is not None and not v >= spec["ge"]:
            raise CatalogueError(bad + f"must be >= {spec['ge']}")
        if spec["lt"] is not None and not v < spec["lt"]:
            raise CatalogueError(bad + f"must be < {spec['lt']}")
    elif k == _INT:
        if isinstance(v, bool) or not isinstance(v, int):
            raise CatalogueError(bad + f"must be an integer, not {_tname(v)}")
        if spec["ge"] is not None and v < spec["ge"]:
            raise CatalogueError(bad + f"must be >= {spec['ge']}")
    elif k == _STR:
        if not isinstance(v, str):
            raise CatalogueError(bad + f"must be a string, not {_tname(v)}")
        if spec["choices"] and v not in spec["choices"]:
            raise CatalogueError(bad + "must be one of " + ", ".join(map(repr, spec["choices"])))
    elif k == _BOOL:
        if not isinstance(v, bool):
            raise CatalogueError(bad + f"must be true or false, not {_tname(v)}")
    elif k == _LIST:
        if not isinstance(v, list):
            raise CatalogueError(bad + f"must be an array, not {_tname(v)}")
    return v


def _case_where(i: int, name) -> str:
    return f"case #{i + 1}" + (f" {name!r}" if isinstance(name, str) else "")


def _parse_case(i: int, raw, source: str) -> dict:
    if not isinstance(raw, Mapping):
        raise CatalogueError(f"{source}: case #{i + 1}: must be a table [[case]], not {_tname(raw)}")
    where = f"{source}: {_case_where(i, raw.get('name'))}"
    for key in raw:
        if key not in _CASE_FIELDS:
            raise CatalogueError(f"{where}: unknown field {key!r} (valid: {', '.join(_CASE_FIELDS)})")
    for key in ("name", "kind", "check", "tolerance", "time_budget_s"):
        if key not in raw:
            raise CatalogueError(f"{where}: field {key} is missing (required)")
    c = {"name": _check_value(where, "name", raw["name"], _p(_STR))}
    if not c["name"].strip():
        raise CatalogueError(f"{where}: field name is empty")
    c["kind"] = _check_value(where, "kind", raw["kind"], _p(_STR, choices=tuple(KINDS)))
    spec, checks = KINDS[c["kind"]]
    c["check"] = _check_value(where, "check", raw["check"], _p(_STR, choices=checks))
    c["tolerance"] = _check_value(where, "tolerance", raw["tolerance"], _p(_NUM, gt=0))
    c["time_budget_s"] = _check_value(where, "time_budget_s", raw["time_budget_s"], _p(_NUM, gt=0))
    c["description"] = _check_value(where, "description", raw.get("description", ""), _p(_STR))
    c["fast"] = _check_value(where, "fast", raw.get("fast", False), _p(_BOOL))
    ov = raw.get("outside_validity")
    c["outside_validity"] = None if ov is None else _check_value(where, "outside_validity", ov, _p(_STR))
    em = raw.get("expect_method")
    c["expect_method"] = None if em is None else _check_value(where, "expect_method", em, _p(_STR))
    rr = raw.get("reference_rtol")
    c["reference_rtol"] = None if rr is None else _check_value(where, "reference_rtol", rr, _p(_NUM, gt=0))
    c["convergence_tolerance"] = _check_value(where, "convergence_tolerance",
                                              raw.get("convergence_tolerance", 1e-3), _p(_NUM, gt=0))
    params = raw.get("params", {})
    if not isinstance(params, Mapping):
        raise CatalogueError(f"{where}: field params must be a table [case.params], not {_tname(params)}")
    for key in params:
        if key not in spec:
            raise CatalogueError(f"{where}: unknown field params.{key} for kind {c['kind']!r} "
                                 f"(valid: {', '.join(spec)})")
    p = {}
    for key, s in spec.items():
        if key in params:
            p[key] = _check_value(where, f"params.{key}", params[key], s)
        elif s["default"] is ...:
            raise CatalogueError(f"{where}: field params.{key} is missing (required for kind "
                                 f"{c['kind']!r})")
        else:
            p[key] = s["default"]
    _cross_check(where, c, p)
    c["params"] = p
    return c


def _cross_check(where, c, p):
    """Checks that involve several fields of a case."""
    if c["kind"] == "dimensionless":
        if (p["R"] is None) == (p["programme"] is None):
            raise CatalogueError(f"{where}: fields params.R and params.programme: give exactly one "
                                 "(constant speed R_omega, or [[tau, R_omega], ...])")
        if p["programme"] is not None:
            rows = p["programme"]
            ok = (len(rows) >= 1 and all(isinstance(r, list) and len(r) == 2 and all(
                isinstance(x, (int, float)) and not isinstance(x, bool) for x in r) for r in rows))
            if not ok or any(b[0] <= a[0] for a, b in zip(rows[:-1], rows[1:])):
                raise CatalogueError(f"{where}: field params.programme = {rows!r}: must be rows "
                                     "[tau, R_omega] with increasing tau")
        if p["initial_angles_deg"] is not None and len(p["initial_angles_deg"]) != p["n"]:
            raise CatalogueError(f"{where}: field params.initial_angles_deg has "
                                 f"{len(p['initial_angles_deg'])} entries, params.n = {p['n']}")
        if c["check"] in ("energy", "jacobi") and p["R"] is None:
            raise CatalogueError(f"{where}: field params.R: check {c['check']!r} needs a constant speed")
    if c["kind"] == "platform" and len(p["initial_angles_deg"]) != 2 and c["check"] == "balanced":
        raise CatalogueError(f"{where}: field params.initial_angles_deg: two balls, two angles")


def load_catalogue(path=DEFAULT_CATALOGUE) -> list:
    """Read and validate a catalogue file; returns the list of case dicts.

    Raises
    ------
    CatalogueError
        Unreadable file, TOML syntax error, or a malformed case: the message
        names the file, the case (number and name) and the field.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise CatalogueError(f"cannot read catalogue {path}: {exc.strerror or exc}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CatalogueError(f"{path}: TOML syntax error: {exc}") from None
    for key in data:
        if key not in ("case", "catalogue"):
            raise CatalogueError(f"{path}: unknown top-level key {key!r} (valid: [catalogue], [[case]])")
    raw = data.get("case")
    if not isinstance(raw, list) or not raw:
        raise CatalogueError(f"{path}: no [[case]] tables")
    cases = [_parse_case(i, r, str(path)) for i, r in enumerate(raw)]
    seen = {}
    for i, c in enumerate(cases):
        if c["name"] in seen:
            raise CatalogueError(f"{path}: {_case_where(i, c['name'])}: field name duplicates "
                                 f"case #{seen[c['name']] + 1}")
        seen[c["name"]] = i
    for c in cases:
        c["_dir"] = str(path.resolve().parent)
    return cases


# ------------------------------------------------------------------ helpers
def _outcome(**kw) -> dict:
    """A case result with every key of CASE_SCHEMA (defaults filled in)."""
    base = dict(method="", method_reason="", solver_success=False, solver_message="",
                converged=False, oracle="", error=None, error_measure="", reference_error=None,
                conserved_quantity=None, drift=None, nfev=None, wall_time_s=0.0,
                outside_validity=None, checks=[], details={})
    base.update(kw)
    return base


def _rel_max(a, b) -> float:
    """max |a - b| / max |b| over the common samples (NaN-safe)."""
    k = min(len(a), len(b))
    if k == 0:
        return float("nan")
    scale = float(np.nanmax(np.abs(b[:k]))) or 1.0
    return float(np.nanmax(np.abs(a[:k] - b[:k]))) / scale


def _warm_planar(scene):
    """Compile/load the planar kernels outside the timed region."""
    from ..scene import RunSettings
    from ..simulate import simulate

    run = scene.run
    tiny = dataclasses.replace(scene, run=RunSettings(duration=min(run.duration, 1e-2),
                                                      sample_rate=1e3, rtol=1e-6, atol=1e-8,
                                                      method=run.method))
    simulate(tiny)


def _shaft(tr):
    return tr.x + 1j * tr.y


def _velocity(tr):
    from ..planar import build_planar_model

    model = build_planar_model(tr.scene)
    k = 2 + tr.scene.balancer.count + (1 if model.free else 0)
    return (tr.state[:, k] + 1j * tr.state[:, k + 1]) * model.length * model.omega_1


def _dot(a, b):
    """Real inner product of complex vectors (x1 x2 + y1 y2)."""
    return (np.conj(a) * b).real


def _mechanics(tr):
    """E_L (energy without the prescribed-rotor cross term) and p_theta, SI.

    Lagrangian of the shaft (total mass M_S, isotropic stiffness c) with the
    rotor's unbalance U turning at the prescribed phi(t) and point-coupled
    weights (m_j, l_j, J_j):  T = M_S |z'|^2/2 + U phi' z'.(i e^{i(phi+beta)})
    + sum [m_j l_j phi_j' z'.(i e^{i phi_j}) + J_j phi_j'^2 / 2],  V = c |z|^2/2.
    """
    sc = tr.scene
    b = sc.balancer
    z, v = _shaft(tr), _velocity(tr)
    Ms, c = sc.total_mass, sc.supports.stiffness_x
    E = 0.5 * Ms * np.abs(v) ** 2 + 0.5 * c * np.abs(z) ** 2
    pz = Ms * v + 1j * sc.rotor.unbalance * tr.rotor_speed * np.exp(
        1j * (tr.rotor_angle + sc.rotor.unbalance_angle))
    ptheta = np.zeros_like(E)
    for j in range(b.count):
        ml, J = b.mass[j] * b.radius[j], b.inertia[j]
        ph, w = tr.weight_angle[:, j], tr.weight_speed[:, j]
        ie = 1j * np.exp(1j * ph)
        cross = ml * w * _dot(v, ie)
        E = E + cross + 0.5 * J * w ** 2
        pz = pz + ml * w * ie
        ptheta = ptheta + ml * _dot(v, ie) + J * w
    ptheta = ptheta + _dot(pz, 1j * z)
    return E, ptheta


# ------------------------------------------------------------------ kind: dimensionless
def _dimensionless_scene(p):
    from ..scene import InitialState, RunSettings, SpeedDrive
    from ..scene_file import scene_from_dimensionless

    if p["programme"] is not None:
        prog = np.array(p["programme"], float)
    else:
        prog = np.array([[0.0, p["R"]]])
    n = p["n"]
    angles = (np.radians(p["initial_angles_deg"]) if p["initial_angles_deg"] is not None
              else np.linspace(0.1, 6.0, n) if n > 2 else np.array([2.0, 4.0])[:n])
    run = RunSettings(duration=p["duration_tau"], sample_rate=p["sample_rate"], rtol=p["rtol"],
                      atol=p["atol"] if p["atol"] is not None else p["rtol"] * 1e-2,
                      method=p["method"], max_steps=p["max_steps"])
    sc = scene_from_dimensionless(n, p["Rt"], p["h"], p["H"], p["e0"], R_omega2=p["R_omega2"],
                                  drive=SpeedDrive(programme=prog), run=run,
                                  initial_angles=list(angles))
    L = sc.length_scale
    speeds = np.full(n, float(p["initial_speeds"]))  # omega_1 = 1 rad/s
    return dataclasses.replace(sc, initial=InitialState(x=p["initial_x"] * L),
                               balancer=dataclasses.replace(sc.balancer, initial_speeds=speeds))


def _top_speed(p):
    return float(p["R"]) if p["R"] is not None else max(r[1] for r in p["programme"])


def _run_planar(case, scene, res):
    from ..simulate import simulate

    tr = simulate(scene, method=scene.run.method)
    st = tr.stats
    res.update(method=st.method, method_reason=st.method_reason, solver_success=bool(st.success),
               solver_message=st.message, nfev=int(st.nfev), wall_time_s=float(st.wall_time))
    res["details"].update(n_steps=int(st.n_steps), n_rejected=int(st.n_rejected),
                          stiffness_ratio=float(st.stiffness_ratio), rtol=st.rtol, atol=st.atol,
                          samples=int(len(tr.t)))
    return tr


def _reference(case, scene, tr, res):
    """Rerun at ``reference_rtol`` (same method): estimated error of the run."""
    from ..simulate import simulate

    rr = case["reference_rtol"]
    if rr is None:
        return None
    ref = simulate(scene, method=tr.stats.method, rtol=rr, atol=rr * 1e-2)
    d = _rel_max(_shaft(tr), _shaft(ref))
    res["details"].update(reference_rtol=rr, reference_difference=d,
                          reference_wall_time_s=float(ref.stats.wall_time),
                          reference_success=bool(ref.stats.success))
    return ref, d


def _kind_dimensionless(case, res):
    from ..accuracy import closed_form_no_balancer
    from ..scene import Balancer, Rotor
    from ..planar_theory.main_motion import StabilityWarning, d_from_angles, d_two_balls, is_stable

    p, chk = case["params"], case["check"]
    scene = _dimensionless_scene(p)
    tr = _run_planar(case, scene, res)
    S = scene.balancer.capacity
    invalid = []
    if chk == "balanced":
        psi = np.abs(tr.residual_unbalance()) / S
        R = _top_speed(p)
        expected = max(p["e0"] - 1.0, 0.0)
        if p["e0"] > 1.0:
            invalid.append(f"e0 = {p['e0']:g} > 1: the unbalance exceeds the balancer's capacity S, so "
                           "no balancing main motion exists (the main motion needs e0 <= 1, (5.50)); "
                           f"oracle used instead: all weights on the light side, residual (e0 - 1) S = "
                           f"{expected:g} S (digest 4.5)")
        d = (d_two_balls(min(p["e0"], 1.0)) if p["n"] == 2
             else d_from_angles(tr.relative_angle[-1]) if len(tr.t) else 0.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", StabilityWarning)
            stable = is_stable(R, p["Rt"], p["h"], p["H"], d) if p["e0"] <= 1 else None
        if stable is False:
            invalid.append(f"the main motion is not asymptotically stable at R_omega = {R:g} "
                           f"(Rt = {p['Rt']:g}, h = {p['h']:g}, H = {p['H']:g}, d = {d:.3g}; "
                           "stand.planar_theory.main_motion.is_stable): balancing is not predicted")
        final = float(psi[-1]) if len(psi) else float("nan")
        res.update(oracle=f"main motion of the theory: residual {expected:g} S at R_omega = {R:g}"
                   + ("" if stable is None else f" (stable: {stable})"),
                   error=abs(final - expected),
                   error_measure="|residual unbalance / S - expected| at the end of the run [-]",
                   conserved_quantity="balanced state's residual |psi|/S (constant once balanced)",
                   drift=float(np.max(psi[-max(2, len(psi) // 10):]) - np.min(psi[-max(2, len(psi) // 10):]))
                   if len(psi) > 1 else None)
        res["details"].update(final_residual=final, expected_residual=expected, d=float(d))
        res["_drift_checked"] = False
    elif chk == "locked":
        b = scene.balancer
        U = scene.rotor.unbalance * np.exp(1j * scene.rotor.unbalance_angle) + np.sum(
            b.mass * b.radius * np.exp(1j * b.initial_angles))
        locked = dataclasses.replace(scene, balancer=Balancer(),
                                     rotor=Rotor(mass=scene.total_mass, eccentricity=abs(U) / scene.total_mass,
                                                 unbalance_angle=float(np.angle(U))))
        ref = closed_form_no_balancer(locked, tr.t)
        if ref is None:
            raise CatalogueError(f"case {case['name']!r}: check 'locked' needs a constant speed and "
                                 "isotropic supports (params.R, params.R_omega2 = 1)")
        R = _top_speed(p)
        bound = 2 * p["Rt"] * R ** 2 / max(p["h"], 1e-300)
        if p["h"] < 100 * R:
            invalid.append(f"h = {p['h']:g} is not >> R_omega = {R:g}: the locked-weight limit "
                           "(h -> inf) is not a valid oracle")
        err = _rel_max(_shaft(tr), ref)
        slip = np.max(np.abs(np.angle(np.exp(1j * (tr.relative_angle - b.initial_angles)))))
        res.update(oracle="closed form of the rotor with the weights locked at their initial angles "
                   f"(limit h -> inf; model error of order mu R^2/h ~ {bound:.1g})",
                   error=err, error_measure="max |r - r_locked| / max |r_locked| [-]",
                   conserved_quantity="weight angles relative to the rotor (locked)", drift=float(slip))
        res["details"].update(max_weight_slip_rad=float(slip))
        res["_drift_checked"] = False
    elif chk in ("energy", "jacobi"):
        if p["h"] != 0 or p["H"] != 0:
            invalid.append(f"h = {p['h']:g}, H = {p['H']:g}: with damping there is no conserved "
                           f"{'energy' if chk == 'energy' else 'Jacobi integral'}")
        if p["R_omega2"] != 1.0:
            invalid.append(f"R_omega2 = {p['R_omega2']:g}: anisotropic supports break the rotation "
                           "invariance the conserved quantity rests on")
        if chk == "energy" and p["e0"] != 0:
            invalid.append(f"e0 = {p['e0']:g}: the unbalanced rotor, turned at a prescribed speed, "
                           "does work on the shaft: energy is not conserved (use check = 'jacobi')")
        E, pt = _mechanics(tr)
        w = p["R"] * 1.0  # omega_1 = 1 rad/s
        Q = E if chk == "energy" else E - w * pt
        scale = float(np.max(np.abs(E)) + (0 if chk == "energy" else w * np.max(np.abs(pt)))) or 1.0
        drift = float(np.max(np.abs(Q - Q[0])) / scale)
        res.update(oracle=("conservation of the total energy (h = H = 0, no unbalance)" if chk == "energy"
                           else "conservation of the Jacobi integral E - omega p_theta (h = H = 0, "
                                "constant speed, isotropic supports)"),
                   error=drift, error_measure="max |Q(t) - Q(0)| / max scale of Q's terms [-]",
                   conserved_quantity=("total energy" if chk == "energy" else "Jacobi integral"),
                   drift=drift)
        res["details"].update(initial_value_J=float(Q[0]), scale_J=scale)
        res["_drift_checked"] = False
    ref = _reference(case, scene, tr, res)
    if chk == "reference":
        if ref is None:
            raise CatalogueError(f"case {case['name']!r}: check 'reference' needs field reference_rtol")
        res.update(oracle=f"converged reference: same method at rtol {case['reference_rtol']:g}",
                   error=ref[1], error_measure="max |r - r_ref| / max |r_ref| [-]")
    if ref is not None:
        res["reference_error"] = ref[1] if chk != "reference" else None
    return invalid


# ------------------------------------------------------------------ kind: scene_file
def _kind_scene_file(case, res):
    from ..accuracy import closed_form_no_balancer, runup_params
    from ..balancers.runup_closed_form import free_whirl_amplitudes, runup_closed_form_state
    from ..scene import SceneError
    from ..scene_file import load_scene

    p, chk = case["params"], case["check"]
    path = Path(p["path"])
    if not path.is_absolute():
        cand = [Path(case.get("_dir", ".")) / path, REPO_ROOT / path]
        path = next((c for c in cand if c.exists()), cand[-1])
    try:
        scene = load_scene(path)
    except SceneError as exc:
        raise CatalogueError(f"case {case['name']!r}: field params.path: {exc}") from None
    run = scene.run
    scene = dataclasses.replace(scene, run=dataclasses.replace(
        run, rtol=p["rtol"] or run.rtol, atol=p["atol"] or (p["rtol"] * 1e-2 if p["rtol"] else run.atol),
        method=p["method"]))
    tr = _run_planar(case, scene, res)
    invalid = []
    if chk == "runup_closed_form":
        ru = runup_params(scene)
        if ru is None:
            invalid.append("the closed-form run-up needs no weights, isotropic supports, a two-node "
                           "speed programme from omega_0 > 0 and the stationary whirl as initial state "
                           "(stand.accuracy.runup_params); none applies")
            res.update(oracle="none (closed form not applicable)", error_measure="")
            return invalid
        prm, t_end = ru
        t = tr.t
        valid = t <= t_end
        Z, Zd = runup_closed_form_state(prm, np.where(valid, t, 0.0))
        z = _shaft(tr)
        err = _rel_max(np.where(valid, z, 0), np.where(valid, Z, 0))
        res.update(oracle=("closed-form run-up (Fresnel integrals)" if prm.n == 0 else
                           "closed-form run-up (Faddeeva function)")
                   + f", {2 * prm.epsilon:g} rad/s^2 from {prm.omega_0:g} rad/s, up to t = {t_end:g} s",
                   error=err, error_measure="max |r - r_exact| / max |r_exact| [-]", reference_error=0.0)
        revs = float(tr.rotor_angle[-1] / (2 * math.pi)) if len(tr.t) else 0.0
        res["details"].update(revolutions=revs)
        if prm.n == 0 and len(t) and valid.any():
            k = int(np.nonzero(valid)[0][-1])
            v = _velocity(tr)
            c_num = free_whirl_amplitudes(prm, t[k:k + 1], z[k:k + 1], v[k:k + 1])[0][0]
            c_ref = free_whirl_amplitudes(prm, t[k:k + 1], Z[k:k + 1], Zd[k:k + 1])[0][0]
            res.update(conserved_quantity="free-whirl amplitude |c+| after the passage (undamped)",
                       drift=float((c_num - c_ref) / c_ref))
            res["_drift_checked"] = True
    elif chk == "closed_form":
        ref = closed_form_no_balancer(scene, tr.t)
        if ref is None:
            invalid.append("the constant-speed closed form needs no weights, one programme node and "
                           "isotropic supports (stand.accuracy.closed_form_no_balancer)")
            res.update(oracle="none (closed form not applicable)")
            return invalid
        res.update(oracle="closed form (no weights, constant speed, isotropic supports)",
                   error=_rel_max(_shaft(tr), ref), error_measure="max |r - r_exact| / max |r_exact| [-]",
                   reference_error=0.0)
    ref = _reference(case, scene, tr, res)
    if chk == "reference":
        if ref is None:
            raise CatalogueError(f"case {case['name']!r}: check 'reference' needs field reference_rtol")
        res.update(oracle=f"converged reference: same method at rtol {case['reference_rtol']:g}",
                   error=ref[1], error_measure="max |r - r_ref| / max |r_ref| [-]")
    return invalid


# ------------------------------------------------------------------ kind: liquid_runup
def _kind_liquid(case, res):
    from ..balancers.liquid_float import LiquidFloatParams, simulate as lf_simulate
    from ..balancers.runup_closed_form import free_whirl_amplitudes, runup_closed_form_state

    p = case["params"]
    try:
        prm = LiquidFloatParams(Omega_0=p["Omega_0"], psi=p["psi"], n=p["n"], e=p["e"],
                                omega_0=p["omega_0"], epsilon=0.5 * p["acceleration"])
    except ValueError as exc:
        raise CatalogueError(f"case {case['name']!r}: params: {exc}") from None
    t = np.arange(0.0, p["t_end"] + 0.5 / p["sample_rate"], 1.0 / p["sample_rate"])
    t = t[t <= p["t_end"]]
    tic = time.perf_counter()
    run = lf_simulate(prm, t_eval=t, frame=p["frame"], method=p["method"], rtol=p["rtol"])
    wall = time.perf_counter() - tic
    res.update(method=f"scipy {p['method']} ({p['frame']} frame)",
               method_reason=("liquid_float.simulate has no automatic choice: model M1 is linear and "
                              "non-stiff (damping ratio "
                              f"{prm.zeta:.3g}), the explicit 8th-order method is used"),
               solver_success=bool(np.all(np.isfinite(run.Z)) and len(run.t) == len(t)),
               solver_message="reached the end" if len(run.t) == len(t) else "stopped early",
               nfev=int(run.nfev), wall_time_s=float(wall))
    Z, Zd = runup_closed_form_state(prm, run.t)
    err = _rel_max(run.Z, Z)
    res.update(oracle=(f"closed-form run-up of model M1 (psi = {prm.psi:g}: Omega = Omega_0 sqrt(psi) = "
                       f"{prm.Omega:.4g} rad/s, {'Fresnel' if prm.n == 0 else 'Faddeeva'})"),
               error=err, error_measure="max |Z - Z_exact| / max |Z_exact| [-]", reference_error=0.0)
    res["details"].update(critical_speed_rad_s=prm.Omega, final_speed_rad_s=float(run.omega[-1]),
                          revolutions=float(run.beta[-1] / (2 * math.pi)))
    if prm.n == 0:
        c_num = free_whirl_amplitudes(prm, run.t[-1:], run.Z[-1:], run.Zdot[-1:])[0][0]
        c_ref = free_whirl_amplitudes(prm, run.t[-1:], Z[-1:], Zd[-1:])[0][0]
        res.update(conserved_quantity="free-whirl amplitude |c+| (undamped)",
                   drift=float((c_num - c_ref) / c_ref))
        res["_drift_checked"] = True
    invalid = []
    if run.omega[-1] < 1.5 * prm.Omega:
        invalid.append(f"the run ends at {run.omega[-1]:.4g} rad/s, before 1.5 x the critical speed "
                       f"{prm.Omega:.4g} rad/s: the passage is not completed")
    return invalid


# ------------------------------------------------------------------ kind: platform
def _kind_platform(case, res):
    from ..rotors.coupled import PlaneWeights, simulate_coupled
    from ..rotors.platform import platform_rotor
    from ..scene import Balancer

    p, chk = case["params"], case["check"]
    rot = platform_rotor()
    w = p["speed"]
    u = rot.unbalances[0]
    atol = p["atol"] if p["atol"] is not None else p["rtol"] * 1e-2
    wn = rot.natural_frequencies(0.0)
    wn = wn[wn > 0]
    ratio = float((wn[-1] / wn[0]) ** 2)
    weights = []
    q0 = qd0 = None
    Q = None
    if chk == "steady_response":
        F = u.s * w * w * np.exp(1j * u.angle) * (rot.force_map(u.plane).T @ np.array([1.0, -1j]))
        Q = np.linalg.solve(rot.dynamic_stiffness(w), F)
        q0, qd0 = Q.real, (1j * w * Q).real
    else:
        m, l = p["ball_mass"], p["ball_radius"]
        b = Balancer(type="balls", mass=np.full(2, m), radius=np.full(2, l),
                     drag=np.full(2, p["ball_drag"]), inertia=np.full(2, m * l * l),
                     initial_angles=np.radians(p["initial_angles_deg"]), initial_speeds=np.zeros(2))
        weights = [PlaneWeights("balancer", b)]
    tic = time.perf_counter()
    run = simulate_coupled(rot, weights, [[0.0, w]], p["duration"], p["sample_rate"], rtol=p["rtol"],
                           atol=atol, q0=q0, qd0=qd0)
    wall = time.perf_counter() - tic
    st = run.stats
    res.update(method="DOP853 (compiled, simulate_coupled)",
               method_reason=(f"simulate_coupled integrates with the compiled explicit DOP853 only; "
                              f"stiffness ratio (w_max/w_min)^2 = {ratio:.3g} at rest, so the step is "
                              "bounded by stability at the fastest mode"),
               solver_success=bool(st["success"]), solver_message=str(st["message"]),
               nfev=int(st["nfev"]), wall_time_s=float(wall))
    res["details"].update(stiffness_ratio=ratio, n_steps=st["n_steps"], n_rejected=st["n_rejected"],
                          lowest_mode_rad_s=float(wn[0]), highest_mode_rad_s=float(wn[-1]))
    invalid = []
    rmax = float(np.max(np.abs(run.q[:, 3:]))) if len(run.t) else 0.0
    res["details"]["max_rotation_rad"] = rmax
    if rmax > p["max_rotation"]:
        invalid.append(f"platform rotations reach {rmax:.3g} rad > {p['max_rotation']:g} rad: the "
                       "linearised model (38) of paper 004 assumes small rotations")
    if chk == "steady_response":
        ex = (Q[None, :] * np.exp(1j * w * run.t)[:, None]).real
        scale = np.abs(Q)
        err = float(np.max(np.abs(run.q - ex) / np.maximum(scale, 1e-300 + 1e-12 * scale.max())))
        res.update(oracle=f"exact steady unbalance response at {w:g} rad/s "
                          "((K - w^2 M + i w (D + w G)) Q = F); the run starts on it",
                   error=err, error_measure="max over coordinates of |q - q_exact| / |Q| [-]",
                   reference_error=0.0)
    else:
        resid = np.hypot(run.static_residual[:, 0], run.static_residual[:, 1]) / u.s
        final = float(resid[-1]) if len(resid) else float("nan")
        res.update(oracle="balancing predicted by the engineering criterion (2.15) at this speed "
                          "(working range (2.85, 713) rad/s): static residual -> 0",
                   error=final, error_measure="static residual unbalance / rotor unbalance at the end [-]",
                   conserved_quantity="balanced state's residual", drift=None)
        res["details"]["final_static_residual"] = final
    return invalid


# ------------------------------------------------------------------ kind: qp_threshold
def _qp_scene(p):
    """The stuck-ball (QP) motion of the theory as an initial state, e0 = 0."""
    from ..scene import InitialState, RunSettings, SpeedDrive
    from ..scene_file import scene_from_dimensionless
    from ..planar_theory.qp import escape_speed, qp_roots

    Rt, h, H = p["Rt"], p["h"], p["H"]
    Rs = escape_speed(Rt, h, H)
    R = Rs + p["offset"]
    roots = qp_roots(R, Rt, h, H)
    Om = float(roots[0])
    s = Om ** 2 / (1 - Om ** 2 + 1j * H * Om)
    sep = p["separation"]
    run = RunSettings(duration=p["duration_tau"], sample_rate=p["sample_rate"], rtol=p["rtol"],
                      atol=p["atol"] if p["atol"] is not None else p["rtol"] * 1e-2, method=p["method"])
    sc = scene_from_dimensionless(2, Rt, h, H, 0.0, drive=SpeedDrive(programme=np.array([[0.0, R]])),
                                  run=run, initial_angles=[-sep / 2, sep / 2])
    L = sc.length_scale
    v = 1j * Om * s * L
    sc = dataclasses.replace(sc, initial=InitialState(x=L * s.real, y=L * s.imag, vx=v.real, vy=v.imag),
                             balancer=dataclasses.replace(sc.balancer,
                                                          initial_speeds=np.full(2, Om - R)))
    return sc, Rs, R, roots, Om, s


def _kind_qp(case, res):
    from ..planar_theory.qp import qp_stability

    p, chk = case["params"], case["check"]
    Rt, h, H = p["Rt"], p["h"], p["H"]
    sc, Rs, R, roots, Om, s = _qp_scene(p)
    sep = p["separation"]
    L = sc.length_scale
    tr = _run_planar(case, sc, res)
    stab = qp_stability(Om, R, Rt, h, H)
    res["details"].update(escape_speed=Rs, R_omega=R, Omega_1=Om, qp_roots=[float(r) for r in roots],
                          qp_stable=bool(getattr(stab, "stable", False)))
    invalid = []
    if chk == "qp_persists" and p["offset"] >= 0:
        invalid.append(f"offset = {p['offset']:g} >= 0: above R*_omega the QP motion is unstable (5.226)")
    if chk == "escape" and p["offset"] <= 0:
        invalid.append(f"offset = {p['offset']:g} <= 0: below R*_omega the stable QP motion exists (5.226)")
    if not len(tr.t):
        return invalid
    if chk == "qp_persists":
        k = len(tr.t) // 2
        ang = np.unwrap(tr.weight_angle[k:].mean(axis=1))
        slope = float(np.polyfit(tr.t[k:], ang, 1)[0])
        rad = np.abs(_shaft(tr)) / L
        err_w = abs(slope - Om) / Om
        err_r = float(np.max(np.abs(rad - abs(s)))) / abs(s)
        gap = float(np.max(np.abs(np.angle(np.exp(1j * (tr.weight_angle[:, 0] - tr.weight_angle[:, 1]))))))
        res.update(oracle=f"stable QP motion of the theory: precession Omega_1 = {Om:.10g} (root of (5.181)), "
                          f"whirl radius |s| = {abs(s):.6g} r*",
                   error=max(err_w, err_r),
                   error_measure="max(|Omega_run - Omega_1| / Omega_1 over the 2nd half, "
                                 "max | |r|/r* - |s| | / |s|) [-]",
                   conserved_quantity="separation of the stuck balls [rad] (max over the run; starts at "
                                      f"{sep:g})", drift=gap)
        res["details"].update(Omega_run=slope, precession_error=err_w, radius_error=err_r,
                              max_separation_rad=gap)
        if gap > max(10 * sep, 1e-2):
            res["checks"].append(f"the balls separated by {gap:.3g} rad: the QP motion did not persist")
    else:
        psi = np.abs(tr.residual_unbalance()) / sc.balancer.capacity
        res.update(oracle="above R*_omega the QP motion is unstable; the balls escape and balance "
                          "(residual -> 0, main motion with e0 = 0)",
                   error=float(psi[-1]), error_measure="residual unbalance / S at the end [-]",
                   conserved_quantity="balanced state's residual |psi|/S")
        res["details"]["final_residual"] = float(psi[-1])
        above = np.nonzero(psi < 0.5)[0]
        res["details"]["escape_time_tau"] = float(tr.t[above[0]]) if above.size else None
    return invalid


_RUNNERS: dict[str, Callable] = {
    "dimensionless": _kind_dimensionless,
    "scene_file": _kind_scene_file,
    "liquid_runup": _kind_liquid,
    "platform": _kind_platform,
    "qp_threshold": _kind_qp,
}


# ------------------------------------------------------------------ warm-up
def _warm(case):
    """Compile / load the case's kernels (numba) before its timed region."""
    kind, p = case["kind"], case["params"]
    if kind == "dimensionless":
        _warm_planar(_dimensionless_scene(p))
    elif kind == "qp_threshold":
        _warm_planar(_qp_scene(p)[0])
    elif kind == "scene_file":
        from ..scene_file import load_scene

        path = Path(p["path"])
        if not path.is_absolute():
            cand = [Path(case.get("_dir", ".")) / path, REPO_ROOT / path]
            path = next((c for c in cand if c.exists()), cand[-1])
        sc = load_scene(path)
        _warm_planar(dataclasses.replace(sc, run=dataclasses.replace(sc.run, method=p["method"])))
    elif kind == "platform":
        from ..rotors.coupled import PlaneWeights, simulate_coupled
        from ..rotors.platform import platform_rotor
        from ..scene import Balancer

        b = Balancer(type="balls", mass=np.full(2, 0.1), radius=np.full(2, 0.1), drag=np.full(2, 1.0),
                     inertia=np.full(2, 1e-3), initial_angles=np.zeros(2), initial_speeds=np.zeros(2))
        rot = platform_rotor()
        for weights in ([], [PlaneWeights("balancer", b)]):
            simulate_coupled(rot, weights, [[0.0, 10.0]], 1e-3, 1e3, rtol=1e-6, atol=1e-8)


# ------------------------------------------------------------------ one case
def _run_case(case: dict) -> dict:
    res = _outcome()
    t_warm = time.perf_counter()
    try:
        _warm(case)
    except Exception:  # the timed run reports the problem
        pass
    res["details"]["warm_up_s"] = time.perf_counter() - t_warm
    tic = time.perf_counter()
    invalid: list = []
    exc_msg = None
    try:
        invalid = _RUNNERS[case["kind"]](case, res) or []
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
        if abs(res["drift"]) > tol:
            reasons_fail.append(f"drift of the {res['conserved_quantity']} {res['drift']:.3g} > "
                                f"tolerance {tol:g}")
        else:
            reasons_ok.append(f"drift {res['drift']:.3g} <= tolerance")
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
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = [c["name"] for c in cases]
    y = np.arange(len(cases))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 0.35 * len(cases) + 1.5), sharey=True)
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
    all_cases = load_catalogue(catalogue_path)
    if cases is None:
        todo = all_cases
    elif isinstance(cases, str) and cases == "fast":
        todo = [c for c in all_cases if c["fast"]]
    else:
        if isinstance(cases, str):
            cases = [cases]
        names = {c["name"] for c in all_cases}
        for nm in cases:
            if nm not in names:
                raise CatalogueError(f"{catalogue_path}: no case named {nm!r} (cases: "
                                     f"{', '.join(sorted(names))})")
        want = set(cases)
        todo = [c for c in all_cases if c["name"] in want]
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
    plain = jsonable(doc)
    if html_path:
        figs = {"case time against budget; error against tolerance (green: pass, red: fail)":
                figure_png(_figure(out))} if out else None
        write_report(TITLE, plain, html_path=html_path, json_path=json_path, figures=figs,
                     sections=["summary", "cases"])
    elif json_path:
        write_report(TITLE, plain, json_path=json_path)
    return plain
