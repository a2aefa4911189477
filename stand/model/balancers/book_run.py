"""Run a book weight model (``[weight_model]`` scene) and return the common :class:`Run`.

The models of chapters 6-7 (two-axis pendulum, coupled pair, autobalancer-
damper) are written in the books' dimensionless variables: time
``tau = omega_0 t`` and lengths in the model's own unit.  Their run is
recorded with ``omega_0 = 1 rad/s`` and a unit length (stated in
:attr:`Run.notes`); the liquid float balancer of paper 001 is in SI.  The
right-hand sides are the modules' own (Python), stepped by scipy's solvers
through the one integrator path (:func:`stand.integrate.driver.run_scipy`).

The liquid chamber balancer of thesis 002 is a quasi-static model: its run is
the rotor (total mass M + m, critical speed omega_cr, decay rate n) at the
constant speed ``[run] speed`` carrying the residual unbalance ``(M + m) e_c``
of the liquid's quasi-static equilibrium (corrected (2.13), section 2.2.2.1),
integrated on the planar kernel; the transient of the liquid itself is not
modelled (issue "Weight family inside the stand").
"""
from __future__ import annotations

import dataclasses
import importlib
import math
import time as _time

import numpy as np

from stand.integrate.driver import run_scipy
from stand.integrate.result import Run, SolverStats
from stand.integrate.runs import generic_run, integrate_model, sample_times
from stand.scene.model import SceneError

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


class _PythonModel:
    """The model protocol of :mod:`stand.integrate.driver` for a Python right-hand side."""

    kind = -1
    sp = wt = prog = np.zeros(0)
    impulses = None
    omega_1 = 1.0

    def __init__(self, fun, size):
        self.python_rhs = fun
        self.size = size

    def breakpoints(self):
        return np.zeros(0)

    def angle_mask(self):
        return np.zeros(self.size, bool)


def _rhs(kind, p):
    mod = importlib.import_module(MODULES[kind])
    if kind == "liquid_float":
        return mod.rhs_fixed(p)
    if kind == "two_axis":
        return lambda t, y: mod.rhs_fixed(t, y, p)
    return lambda t, y: mod.rhs(t, y, p)


def run_book(scene, method: str = "DOP853", rtol=None, atol=None, compiled: bool = True) -> Run:
    """Integrate a ``[weight_model]`` scene; returns the common :class:`Run`.

    ``compiled=True`` (default): the model's generic composition (planar rotor x body
    weight, :mod:`stand.model.balancers.composition`) on the compiled kernel; ``False``: the
    book's own right-hand side (Python) on scipy's solver -- the oracle path.
    """
    bm = scene.structure
    kind, p, run = bm.type, bm.params, scene.run
    if kind == "liquid_chamber" and not compiled:
        return _run_chamber(scene, method, rtol, atol)
    method = "DOP853" if method in ("auto", "numpy-DOP853") else method
    rtol = run.rtol if rtol is None else rtol
    atol = run.atol if atol is None else atol
    if kind == "liquid_chamber":
        w = float(bm.options.get("speed", 0.5 * p.critical_speed))
        if not (math.isfinite(w) and w > 0):
            raise SceneError(f"run.speed = {w!r}: must be > 0 (rad/s)")
        return _run_composed(scene, w, method, rtol, atol)
    y0 = initial_state(kind, p, bm.options)
    if compiled and not (kind == "damper" and p.friction is not None):
        return _run_composed(scene, y0, method, rtol, atol)
    ts = sample_times(run.duration, run.sample_rate)
    out = np.full((ts.size, y0.size), np.nan)
    out[0] = y0
    stats = SolverStats(method=method, rtol=rtol, atol=atol,
                        method_reason="book model: its own right-hand side (Python) on scipy's "
                                      f"{method}")
    t0 = _time.perf_counter()
    k = run_scipy(_PythonModel(_rhs(kind, p), y0.size), y0, run.duration, rtol, atol, ts, out,
                  stats, method, run.max_steps)
    stats.wall_time = _time.perf_counter() - t0
    return _book_channels(scene, ts[:k], out[:k], stats)


def _run_composed(scene, y0, method, rtol, atol) -> Run:
    """The book model as a generic composition on the compiled kernel (same samples,
    same ``state/<column>`` coordinates as the oracle path)."""
    from stand.model.rotors.coupled import build_model, initial_state as generic_initial
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


def _book_channels(scene, t, y, stats) -> Run:
    bm = scene.structure
    kind, p = bm.type, bm.params
    cols = STATE_COLUMNS[kind]
    names = [c.split(" [")[0] for c in cols]
    notes = ()
    if kind == "liquid_float":
        sp = p.speed()
        phi, speed = np.asarray(sp.beta(t), float) * np.ones_like(t), \
            np.asarray(sp.omega(t), float) * np.ones_like(t)
        xy = y[:, :2]
        weights = {}
    else:
        notes = (DIMENSIONLESS_NOTE,)
        phi, speed = p.R_omega * t, np.full_like(t, p.R_omega)
        xy = y[:, [names.index("x"), names.index("y")]]
        if kind == "damper":
            a = np.arctan2(y[:, names.index("n_y")], y[:, names.index("n_x")])
            weights = {"damper1": {"angle": np.unwrap(a) if a.size else a}}
        else:
            weights = {"pendulum1": {"angle": y[:, names.index("alpha")],
                                     "speed": y[:, names.index("alpha'")]}}
    coords = {f"state/{n}": (y[:, i], (c.split(" [")[1].rstrip("]") if " [" in c else "1"))
              for i, (n, c) in enumerate(zip(names, cols))}
    run = Run(t=t, planes={"balancer": xy}, main_plane="balancer", rotor_angle=phi,
              rotor_speed=speed, weights=weights, weight_planes={w: "balancer" for w in weights},
              stats=stats, scene=scene, coordinates=coords, state=y, notes=notes)
    return run


def _run_chamber(scene, method, rtol, atol) -> Run:
    """The quasi-static liquid chamber (module docstring) on the planar kernel."""
    from stand.scene.model import Balancer, Rotor, RunSettings, Scene, SpeedDrive, Supports
    from stand.integrate.simulate import simulate

    p = scene.structure.params
    mod = importlib.import_module(MODULES["liquid_chamber"])
    w = float(scene.structure.options.get("speed", 0.5 * p.critical_speed))
    if not (math.isfinite(w) and w > 0):
        raise SceneError(f"run.speed = {w!r}: must be > 0 (rad/s)")
    qs = mod.quasi_static_efficiency(p, w)
    Mt = p.total_mass
    e_c = float(qs.e_c) if math.isfinite(qs.e_c) else float(p.rotor_unbalance / Mt)
    c = Mt * p.critical_speed ** 2
    d = 2.0 * p.n * Mt
    r = scene.run
    planar = Scene(rotor=Rotor(mass=Mt, eccentricity=e_c), supports=Supports(c, c, d, d),
                   balancer=Balancer(), drive=SpeedDrive(np.array([[0.0, w]])),
                   run=RunSettings(r.duration, r.sample_rate, r.rtol, r.atol),
                   name=scene.name)
    res = simulate(planar, method=None if method == "auto" else method, rtol=rtol, atol=atol)
    res.scene = scene
    res.notes = (f"quasi-static liquid chamber (thesis 002, corrected (2.13)) at {w:.6g} rad/s: "
                 f"the rotor carries the residual unbalance (M + m) e_c = {Mt * e_c:.6g} kg m "
                 f"(efficiency lambda0 = {qs.lambda0:.4g}, valid = {qs.valid}); the liquid's "
                 "transient is not modelled",)
    res.truth = {"residual/balancer": (np.tile([Mt * e_c, 0.0], (len(res.t), 1)), "kg*m")}
    return dataclasses.replace(res)
