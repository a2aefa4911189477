"""Run a book weight model (``[weight_model]`` scene) and return the common :class:`Run`.

Every model runs as its generic composition -- the planar rotor x one body weight
(:mod:`stand.model.balancers.composition`) -- on the compiled generic kernel, through
the run parts every scene shares (:mod:`stand.integrate.runs`).  The models of
chapters 6-7 (two-axis pendulum, coupled pair, autobalancer-damper) are given in
the books' dimensionless variables: time ``tau = omega_0 t`` and lengths in the
model's own unit; their run is recorded with ``omega_0 = 1 rad/s`` and a unit
length (stated in :attr:`Run.notes`); the liquid float balancer of paper 001 is in
SI.  The state columns of the book's fixed frame (:data:`STATE_COLUMNS`) are
recorded as ``state/<column>``.  The liquid chamber of thesis 002 runs as the
dynamic liquid body of :mod:`stand.model.rotors.bodies`.

The books' own right-hand sides are test oracles (``tests/oracles``), not run here.
"""
from __future__ import annotations

import importlib
import math

import numpy as np

from stand.integrate.result import Run, SolverStats
from stand.integrate.runs import generic_run, integrate_model, sample_times
from stand.errors import SceneError

__all__ = ["run_book", "STATE_COLUMNS", "initial_state"]

#: state layout of each model's fixed-frame right-hand side
STATE_COLUMNS = {
    "two_axis": ["phi", "alpha", "x", "y", "phi'", "alpha'", "x'", "y'"],
    "gravity_pair": ["phi", "alpha", "x", "y", "phi'", "alpha'", "x'", "y'"],
    "damper": ["x", "y", "x'", "y'", "n_x", "n_y", "n_z", "W_x", "W_y", "W_z"],
    "liquid_float": ["xi [m]", "eta [m]", "xi' [m/s]", "eta' [m/s]"],
}
MODULES = {"two_axis": "stand.model.balancers.two_axis", "gravity_pair": "stand.model.balancers.gravity_pair",
           "damper": "stand.model.balancers.damper", "liquid_float": "stand.model.balancers.liquid_float",
           "liquid_chamber": "stand.model.balancers.liquid_chamber"}
DIMENSIONLESS_NOTE = ("book model in its dimensionless variables: time is tau = omega_0 t recorded "
                      "as seconds with omega_0 = 1 rad/s, lengths in the model's unit recorded as m")


def initial_state(kind: str, p, options: dict) -> np.ndarray:
    """The model's initial state: ``options["initial"]`` or the module's default."""
    if "initial" in options:
        y0 = np.asarray(options["initial"], dtype=float)
        n = len(STATE_COLUMNS[kind])
        if y0.shape != (n,) or not np.all(np.isfinite(y0)):
            raise SceneError(f"run.initial: {n} finite numbers ({', '.join(STATE_COLUMNS[kind])})")
        return y0
    if kind in ("two_axis", "gravity_pair"):   # weights slightly off neutral, turning with the rotor
        return np.array([0.3, 0.0, 0.0, 0.0, 0.0, p.R_omega, 0.0, 0.0])
    mod = importlib.import_module(MODULES[kind])
    if kind == "damper":
        return mod.state_from_angles(0.3, 0.0, p.R_omega, frame="fixed")
    return mod.initial_state(p, frame="fixed")


def run_book(scene, method: str = "DOP853", rtol=None, atol=None) -> Run:
    """Integrate a ``[weight_model]`` scene; returns the common :class:`Run`.

    The model runs as its generic composition (planar rotor x body weight,
    :mod:`stand.model.balancers.composition`) on the compiled kernel.  The book's own
    right-hand side (Python) is a test oracle (``tests/oracles/book_run.py``).
    """
    bm = scene.structure
    kind, p, run = bm.type, bm.params, scene.run
    method = "DOP853" if method in ("auto", "numpy-DOP853") else method
    rtol = run.rtol if rtol is None else rtol
    atol = run.atol if atol is None else atol
    if kind == "liquid_chamber":
        w = float(bm.options.get("speed", 0.5 * p.critical_speed))
        if not (math.isfinite(w) and w > 0):
            raise SceneError(f"run.speed = {w!r}: must be > 0 (rad/s)")
        return _run_composed(scene, w, method, rtol, atol)
    if kind == "damper" and p.friction is not None:
        raise SceneError("weight_model damper: dry friction (7.79)-(7.84) has no generic "
                         "composition; its book form runs in the tests only")
    return _run_composed(scene, initial_state(kind, p, bm.options), method, rtol, atol)


def _run_composed(scene, y0, method, rtol, atol) -> Run:
    """The book model as a generic composition on the compiled kernel (same samples,
    same ``state/<column>`` coordinates as the oracle path)."""
    from stand.integrate.coupled import build_model, initial_state as generic_initial
    from stand.model.balancers.composition import composition

    bm, run = scene.structure, scene.run
    kind, p = bm.type, bm.params
    comp = composition(kind, p, run.duration, y0)
    book_units = kind not in ("liquid_float", "liquid_chamber")
    model = build_model(comp.rotor, (), comp.programme, 1.0 if book_units else None,
                        (comp.body,))
    y = generic_initial(model, (), comp.q0, comp.qd0)
    if kind == "damper":
        o = model.first_body_state
        y[o:o + 3] = comp.initial_body[:3]
        y[o + 3:o + 6] = comp.initial_body[3:] / model.omega_ref
    w = model.omega_1
    ts = sample_times(run.duration, run.sample_rate) * w
    out = np.full((ts.size, y.size), np.nan)
    out[0] = y
    stats = SolverStats(method=method, rtol=rtol, atol=atol,
                        method_reason="book model as its generic composition (planar rotor x "
                                      "body weight) on the compiled kernel")
    k = integrate_model(scene, model, y, run.duration * w, ts, out, stats, method, False, None, None)
    res = generic_run(scene, model, out[:k], ts[:k], stats)
    xy = res.planes["balancer"]
    v = out[:k, model.n:2 * model.n] * model.scale * w
    name = next(iter(res.weights)) if res.weights else None
    ch = res.weights.get(name, {})
    if kind in ("two_axis", "gravity_pair"):
        cols = [ch["tilt"], ch["angle"], xy[:, 0], xy[:, 1], ch["tilt_rate"], ch["speed"],
                v[:, 0], v[:, 1]]
    elif kind == "liquid_chamber":
        b = comp.body.body
        w_load = math.sqrt(comp.rotor.K[0, 0] / (comp.rotor.M[0, 0] + b.mass * b.lever))
        speed = float(comp.programme[0, 1])
        res.notes = tuple(res.notes) + (
            "liquid chamber as a dynamic model (stand.model.rotors.bodies): free surface concentric "
            "with the bearing axis, liquid centre of mass at r^2/(R^2 - r^2) times the offset "
            "(thesis l.668); its steady state solves (2.12); "
            + (f"below the critical speed of the liquid-loaded rotor ({w_load:.4g} rad/s) it is "
               "the root with the liquid on the heavy side (l.806), not (2.13): the liquid adds "
               "to the unbalance" if speed < w_load else
               f"above the critical speed of the liquid-loaded rotor ({w_load:.4g} rad/s) it is "
               "the corrected (2.13)"),)
        return res
    elif kind == "damper":
        o = model.first_body_state
        W = out[:k, o + 3:o + 6] * w
        cols = [xy[:, 0], xy[:, 1], v[:, 0], v[:, 1], ch["n_x"], ch["n_y"], ch["n_z"],
                W[:, 0], W[:, 1], W[:, 2]]
    else:
        cols = [xy[:, 0], xy[:, 1], v[:, 0], v[:, 1]]
    state = np.column_stack(cols) if k else np.zeros((0, len(STATE_COLUMNS[kind])))
    names = STATE_COLUMNS[kind]
    res.coordinates.update({f"state/{c.split(' [')[0]}": (state[:, i], (c.split(" [")[1].rstrip("]")
                                                          if " [" in c else "1"))
                            for i, c in enumerate(names)})
    res.state = state
    res.notes = tuple(res.notes) + ((DIMENSIONLESS_NOTE,) if book_units else ())
    return res
