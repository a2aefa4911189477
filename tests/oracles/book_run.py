"""The books' own right-hand sides behind one calling convention, and a ``[weight_model]``
scene run on them -- the oracle path of :func:`stand.integrate.book_run.run_book`.

:func:`book_rhs` gives ``f(tau, y)`` of a model's fixed frame in the state layout
:data:`stand.integrate.book_run.STATE_COLUMNS` (the three calling conventions of
the books' modules papered over); :func:`run_book_oracle` integrates it with scipy's
solvers through the one integrator path (:func:`stand.integrate.driver.run_scipy`) into
the common :class:`stand.integrate.result.Run`, with the same ``state/<column>``
coordinates as the package's run.  The liquid chamber's oracle is the quasi-static
model of thesis 002: the rotor (total mass M + m, critical speed omega_cr, decay rate
n) at the constant speed ``[run] speed`` carrying the residual unbalance
``(M + m) e_c`` of the liquid's quasi-static equilibrium (corrected (2.13), section
2.2.2.1), on the planar kernel.
"""
from __future__ import annotations

import dataclasses
import importlib
import math
import time as _time

import numpy as np

from stand.integrate.driver import run_scipy
from stand.integrate.result import Run, SolverStats
from stand.integrate.runs import sample_times
from stand.integrate.book_run import DIMENSIONLESS_NOTE, MODULES, STATE_COLUMNS, initial_state
from stand.scene.model import SceneError

__all__ = ["book_rhs", "run_book_oracle"]

#: where each model's book right-hand side lives (moved here model by model; the rest are
#: still in the package's modules, stand.integrate.book_run.MODULES)
ORACLES = {**MODULES, "gravity_pair": "oracles.gravity_pair", "damper": "oracles.damper",
           "two_axis": "oracles.two_axis", "liquid_float": "oracles.liquid_float"}


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


def book_rhs(kind, p):
    """``f(tau, y)``: the book's fixed-frame right-hand side of model ``kind``."""
    mod = importlib.import_module(ORACLES[kind])
    if kind == "liquid_float":
        return mod.rhs_fixed(p)
    if kind == "two_axis":
        return lambda t, y: mod.rhs_fixed(t, y, p)
    return lambda t, y: mod.rhs(t, y, p)


def run_book_oracle(scene, method: str = "DOP853", rtol=None, atol=None):
    """Integrate a ``[weight_model]`` scene on the book's own right-hand side (scipy)."""
    bm = scene.structure
    kind, p, run = bm.type, bm.params, scene.run
    if kind == "liquid_chamber":
        return _run_chamber(scene, method, rtol, atol)
    method = "DOP853" if method in ("auto", "numpy-DOP853") else method
    rtol = run.rtol if rtol is None else rtol
    atol = run.atol if atol is None else atol
    y0 = initial_state(kind, p, bm.options)
    ts = sample_times(run.duration, run.sample_rate)
    out = np.full((ts.size, y0.size), np.nan)
    out[0] = y0
    stats = SolverStats(method=method, rtol=rtol, atol=atol,
                        method_reason="book model: its own right-hand side (Python) on scipy's "
                                      f"{method}")
    t0 = _time.perf_counter()
    k = run_scipy(_PythonModel(book_rhs(kind, p), y0.size), y0, run.duration, rtol, atol, ts,
                  out, stats, method, run.max_steps)
    stats.wall_time = _time.perf_counter() - t0
    return _book_channels(scene, ts[:k], out[:k], stats)


def _book_channels(scene, t, y, stats):
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


def _run_chamber(scene, method, rtol, atol):
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
