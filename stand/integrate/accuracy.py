"""Error against run time: a scene at a ladder of tolerances and methods.

Each run is compared with an exact solution where one exists -- a rotor with
no weights on isotropic supports at constant speed (the linear oscillator
driven by the unbalance, solved in closed form from the scene's initial
state), or in a run-up at constant angular acceleration from its stationary
state (the Lewis/Dimentberg closed form of papers digest section 4.2: Fresnel
integrals, or the Faddeeva function with damping; the paper-001 scene) -- or
with a much tighter reference run, whose own error is estimated by comparing
it with a second reference ten times looser.

Fixed-step RK4 (``methods`` containing "RK4", steps from ``rk4_steps``) shows
the numerical damping of an undamped free whirl: for run-up references the
report also gives the drift of the free-whirl amplitude |c+| after the
passage through resonance (constant in the exact motion).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from stand.model.planar import build_planar_model, initial_state
from stand.scene.model import Scene
from stand.integrate.simulate import Trajectory, simulate

DEFAULT_RTOLS = (1e-4, 1e-6, 1e-8, 1e-10)


def _free_isotropic(scene: Scene, n_nodes: int) -> bool:
    """A planar rotor without weights on isotropic supports, driven by a speed programme of
    ``n_nodes`` nodes without coast-down: where the closed forms hold."""
    if scene.kind != "planar" or len(scene.bodies) > 1 or (
            scene.bodies and _lever(scene) is None):
        return False
    d, s = scene.drive, scene.supports
    return not (scene.balancer.count or d.kind != "speed" or len(d.programme) != n_nodes
                or d.coast_down_start is not None or s.stiffness_x != s.stiffness_y
                or s.damping_x != s.damping_y)


def _lever(scene: Scene):
    """(mass [kg], lever lambda [-]) of the scene's one liquid whose centre of mass follows the
    shaft at once (paper 001's M1 float, or a chamber without relaxation), else None."""
    from stand.model.rotors.bodies import LiquidWeight

    (pb,) = scene.bodies
    b = pb.body
    if isinstance(b, LiquidWeight) and b.relaxation_time == 0.0:
        return b.mass, b.lever
    return None


def runup_params(scene: Scene):
    """The closed-form run-up parameters of a scene, or None when it does not apply.

    Applies to: no weights, isotropic supports, a speed programme of two nodes
    (constant angular acceleration a > 0 from omega_0 >= 0, held afterwards, no
    coast-down), an initial state equal to the stationary whirl at omega_0
    ((7) of paper 001), unbalance angle 0.  The scene is then model M1 of
    paper 001 with psi = 1: Omega^2 = c / M, n = d / M, e = s / M, or -- with one
    liquid body whose centre of mass follows the shaft at once (float, or chamber
    without relaxation) -- M1 itself, psi = M / (M + m lambda),
    epsilon = a / 2 (papers digest 4.1).  The closed form holds until the
    programme's last node.
    """
    from stand.model.balancers.liquid_float import LiquidFloatParams, initial_state as lf_initial

    if not _free_isotropic(scene, 2) or scene.rotor.unbalance_angle != 0.0 or scene.perturbations:
        return None
    d, s = scene.drive, scene.supports
    (t0, w0), (t1, w1) = d.programme
    if t0 != 0.0 or not (w0 >= 0 and w1 > w0):   # from rest too: Z(0) = Z'(0) = 0
        return None
    M = scene.total_mass
    psi = 1.0
    if scene.bodies:       # model M1 itself: rotor m1 carrying e, liquid lever m2 lambda
        m2, lam = _lever(scene)
        M = scene.rotor.mass
        psi = M / (M + m2 * lam)
    try:
        p = LiquidFloatParams(Omega_0=float(np.sqrt(s.stiffness_x / M)), psi=psi,
                              n=s.damping_x / M, e=scene.rotor.unbalance / M, omega_0=w0,
                              epsilon=0.5 * (w1 - w0) / t1, m1=M)
    except ValueError:
        return None
    y0 = lf_initial(p, frame="fixed")
    ini = scene.initial
    have = np.array([ini.x, ini.y, ini.vx, ini.vy])
    scale = np.array([1.0, 1.0, w0, w0]) * abs(complex(y0[0], y0[1]))
    if not np.all(np.abs(have - y0) <= 1e-9 * scale + 1e-300):
        return None
    return p, float(t1)


def closed_form_no_balancer(scene: Scene, t: np.ndarray) -> np.ndarray | None:
    """Exact shaft motion x + i y [m] of a rotor without weights, or None.

    Applies when there are no weights, the speed is prescribed and constant
    (one programme node, no coast-down) and the supports are isotropic.  In
    units of tau = omega_1 t:  z'' + H z' + z = eps0 R^2 e^{i(R tau + beta)},
    whose steady part has the amplitude e R^2 / sqrt((1 - R^2)^2 + (H R)^2)
    (digest ch5 section 8.2), plus the free response fixed by z(0), z'(0).
    """
    if not _free_isotropic(scene, 1):
        return None
    d, s = scene.drive, scene.supports
    model = build_planar_model(scene)
    w1, L = model.omega_1, model.length
    H = s.damping_x / (w1 * scene.total_mass)
    R = d.programme[0, 1] / w1
    eps0 = scene.rotor.unbalance / (scene.total_mass * L)
    A = eps0 * R ** 2 * np.exp(1j * scene.rotor.unbalance_angle) / (1 - R ** 2 + 1j * H * R)
    y0 = initial_state(scene, model)
    z0, v0 = y0[0] + 1j * y0[1], y0[2] + 1j * y0[3]
    disc = np.sqrt(complex(H * H / 4 - 1))
    l1, l2 = -H / 2 + disc, -H / 2 - disc
    # c1 + c2 = z0 - A ; l1 c1 + l2 c2 = v0 - i R A
    c1 = ((v0 - 1j * R * A) - l2 * (z0 - A)) / (l1 - l2)
    c2 = (z0 - A) - c1
    tau = np.asarray(t) * w1
    z = A * np.exp(1j * R * tau) + c1 * np.exp(l1 * tau) + c2 * np.exp(l2 * tau)
    return z * L


@dataclass
class AccuracyRow:
    method: str
    rtol: float
    atol: float
    max_error_m: float
    relative_error: float
    wall_time_s: float
    nfev: int
    n_steps: int
    success: bool
    step_s: float = float("nan")                 #: fixed step (RK4) [s]
    free_whirl_drift: float = float("nan")       #: relative change of |c+| after the passage


@dataclass
class AccuracyReport:
    scene: str
    reference: str
    reference_error_m: float
    scale_m: float
    rows: list
    notes: list = None
    compared_to_s: float = float("nan")   #: the errors are over t = 0 .. this [s] (the run compared)

    def to_dict(self) -> dict:
        d = asdict(self)
        d["rows"] = [asdict(r) if not isinstance(r, dict) else r for r in self.rows]
        d["notes"] = list(self.notes or [])
        return d

    def table(self) -> str:
        span = (f"compared over t = 0 to {self.compared_to_s:.4g} s: "
                if np.isfinite(self.compared_to_s) else "")
        lines = [f"scene: {self.scene}",
                 f"reference: {self.reference} (its own error ~ {self.reference_error_m:.3g} m); "
                 f"{span}max |r| = {self.scale_m:.4g} m",
                 f"{'method':<8} {'rtol/step':>9} {'atol':>8} {'max error [m]':>14} {'rel. error':>11} "
                 f"{'wall [s]':>9} {'RHS evals':>10} {'steps':>8} {'free-whirl drift':>17}"]
        for r in self.rows:
            tol = f"{r.step_s:>8.1e}s" if r.method == "RK4" else f"{r.rtol:>9.0e}"
            atol = "" if r.method == "RK4" else f"{r.atol:.0e}"
            drift = "" if not np.isfinite(r.free_whirl_drift) else f"{r.free_whirl_drift:.2e}"
            lines.append(f"{r.method:<8} {tol} {atol:>8} {r.max_error_m:>14.3e} "
                         f"{r.relative_error:>11.3e} {r.wall_time_s:>9.3f} {r.nfev:>10d} {r.n_steps:>8d} "
                         f"{drift:>17}" + ("" if r.success else "  FAILED"))
        lines += [n if n.startswith("not applicable") else f"note: {n}" for n in self.notes or []]
        return "\n".join(lines)


def _position(tr: Trajectory) -> np.ndarray:
    return tr.x + 1j * tr.y


#: fixed RK4 steps one accuracy row may take (checked before the run: about 10 s of work)
MAX_RK4_STEPS = 5e7


def default_rk4_steps(scene: Scene) -> tuple:
    """RK4 steps [s]: 1/20 and 1/40 of the period at the top speed (a torque drive: of
    1 rad/s); a speed programme that stays at rest (e.g. one node ``[[0, 0]]``, a constant
    speed of 0) has no revolution: the natural period of the planar rotor instead."""
    import math

    top = float(np.max(scene.drive.programme[:, 1])) if scene.drive.kind == "speed" else 1.0
    if not top > 0:
        top = scene.natural_frequency if scene.kind == "planar" else 1.0
    return (2 * math.pi / top / 20, 2 * math.pi / top / 40)


def _rk4_run(scene: Scene, step_s: float, t_samples: np.ndarray):
    """Fixed-step RK4 on the compiled planar RHS; samples at ``t_samples``."""
    import time

    from stand.model.kernels import PLANAR
    from stand.integrate.rk4 import rk4_loop

    model = build_planar_model(scene)
    if model.free or model.impulses.size:
        raise ValueError("RK4 error reports: prescribed-speed scenes without impulses only")
    dt = float(t_samples[1] - t_samples[0]) if t_samples.size > 1 else float(step_s)
    every = max(1, int(round(dt / step_s)))
    h = dt / every
    n_steps = every * (t_samples.size - 1)
    if n_steps > MAX_RK4_STEPS:
        raise ValueError(f"RK4 step {step_s:.3g} s over run.duration = {scene.run.duration:g} s: "
                         f"{n_steps:.3g} steps, more than the limit {MAX_RK4_STEPS:.0e}; take a "
                         "larger step (--rk4-steps) or shorten run.duration")
    y = initial_state(scene, model).astype(float)
    out = np.full((t_samples.size, y.size), np.nan)
    rk4_loop(PLANAR, model.sp, model.wt, model.prog, y.copy(), 0.0, 0, 1, out[:1].copy())  # compile
    t0 = time.perf_counter()
    nfev = rk4_loop(PLANAR, model.sp, model.wt, model.prog, y, h * model.omega_1, n_steps, every, out)
    wall = time.perf_counter() - t0
    L, w1 = model.length, model.omega_1
    Z = (out[:, 0] + 1j * out[:, 1]) * L
    Zd = (out[:, 2] + 1j * out[:, 3]) * L * w1
    return Z, Zd, wall, int(nfev), n_steps, h


def _velocity(tr: Trajectory) -> np.ndarray:
    model = build_planar_model(tr.scene)
    st = tr.state
    n = tr.scene.balancer.count
    k = 2 + n + (1 if model.free else 0)
    return (st[:, k] + 1j * st[:, k + 1]) * model.length * model.omega_1


#: steps the whole ladder and its reference runs may take, in run budgets (run.max_steps)
LADDER_BUDGET_RUNS = 4


class _LadderBudget:
    """The runs of one accuracy report share a step budget of :data:`LADDER_BUDGET_RUNS`
    times the scene's ``run.max_steps``; each run gets what is left (at most one run's
    budget).  A run that exhausts it stops the report (:class:`stand.errors.BudgetExceeded`):
    its error would measure where it stopped, not the method."""

    def __init__(self, scene: Scene):
        self.scene, self.total = scene, LADDER_BUDGET_RUNS * int(scene.run.max_steps)
        self.left = self.total

    def simulate(self, **kw) -> Trajectory:
        import dataclasses

        from stand.errors import BudgetExceeded

        cap = min(int(self.scene.run.max_steps), self.left)
        sc = self.scene
        if cap < sc.run.max_steps:
            sc = dataclasses.replace(sc, run=dataclasses.replace(sc.run, max_steps=max(cap, 1)))
        tr = simulate(sc, **kw)
        st = tr.stats
        self.left -= int(st.n_steps) + int(st.n_rejected)
        if st.status == -3:
            raise BudgetExceeded(
                f"the accuracy runs ({kw.get('method')} at rtol {kw.get('rtol'):.0e}) ran out of "
                f"their step budget: {cap} steps of {self.total} ({LADDER_BUDGET_RUNS} x "
                f"run.max_steps = {self.scene.run.max_steps}) before the end of run.duration = "
                f"{self.scene.run.duration:g} s")
        return tr


#: a reference rung stops the ladder (round-off floor) when its steps (accepted + rejected) grow
#: by more than this factor over the previous rung's (a method of order p needs 10^(1/p) <= 1.6
#: for a tolerance 10x tighter)
ROUNDOFF_GROWTH = 3.0


def reference_ladder(budget: _LadderBudget, method: str, tight: float, loosest: float, seed=None):
    """The reference run of a scene without closed form, and its own error.

    Runs ``method`` (chosen by the scene's stiffness, :func:`stand.integrate.simulate.auto_method`:
    the compiled DOP853, or scipy's Radau with the compiled Jacobian when stiff) on a ladder of
    tolerances, ten times tighter each rung, from ``max(loosest / 100, tight * 10)`` down to
    ``tight``.  The ladder stops early, with a note, when the next rung would not fit the
    steps left in ``budget`` (predicted from the growth between the last two rungs), when a rung
    ran out of them, failed, or shows the round-off floor (:data:`ROUNDOFF_GROWTH`); a ladder
    stopped after its first rung measures it against one rung ten times looser.  ``seed``: an
    ``(rtol, run)`` of ``method`` already made (e.g. the run under test), the ladder's first rung.

    Returns
    -------
    tuple
        ``(run, name, own error [m], notes)``: the tightest rung (the one before a rung at the
        round-off floor), its name (method, tolerance, why this method), ``max |r_k - r_(k-1)|``
        over the samples (the last two rungs: an estimate of the reference's error, dominated
        by the looser's) and the notes.
    """
    from stand.errors import BudgetExceeded

    rungs, notes, why, floor = [], [], None, False
    rt = max(loosest * 1e-2, tight * 10)
    if seed is not None and seed[0] > tight and seed[1].stats.success:
        rungs.append((seed[0], seed[1], int(seed[1].stats.n_steps) + int(seed[1].stats.n_rejected)))
        rt = max(seed[0] / 10, tight)
    while why is None:
        try:
            tr = budget.simulate(method=method, rtol=rt, atol=rt * 1e-2)
        except BudgetExceeded as exc:
            why = f"the rung at rtol {rt:.0e} ran out of the step budget ({exc})"
            break
        st = tr.stats
        if not st.success:
            why = f"the rung at rtol {rt:.0e} failed ({st.message})"
            break
        steps = int(st.n_steps) + int(st.n_rejected)
        growth = steps / rungs[-1][2] if rungs else 1.0
        rungs.append((rt, tr, steps))
        if rt <= tight * 1.0001:
            break
        if growth > ROUNDOFF_GROWTH:
            floor = True
            why = (f"the rung at rtol {rt:.0e} reached the round-off floor ({steps} steps, "
                   f"{growth:.3g} x the previous rung's)")
        elif steps * max(growth, 1.5) > min(budget.left, budget.scene.run.max_steps):
            why = (f"the next rung (rtol {rt / 10:.0e}) would take ~{steps * max(growth, 1.5):.3g} "
                   f"steps, more than the {budget.left} left of the budget ({LADDER_BUDGET_RUNS} x "
                   f"run.max_steps = {budget.scene.run.max_steps})")
        rt = max(rt / 10, tight)
    if len(rungs) == 1:      # one rung: its own error against a looser one
        rt0 = rungs[0][0] * 10
        rungs.insert(0, (rt0, budget.simulate(method=method, rtol=rt0, atol=rt0 * 1e-2), 0))
    if not rungs:
        raise BudgetExceeded(f"no reference for the accuracy report: {why}")
    if floor and seed is not None and rungs[-2][1] is seed[1]:
        floor = False       # the rung before the floor is the run under test itself
    (rt, tr, _), (rt0, tr0, _) = rungs[-2:][::-1] if not floor else rungs[-2:]
    k = min(len(tr.t), len(tr0.t))
    err = float(np.max(np.abs(_position(tr)[:k] - _position(tr0)[:k])))
    ratio = tr.stats.stiffness_ratio
    name = (f"{method} at rtol {rt:.0e}, from a ladder {rungs[0][0]:.0e} .. {rungs[-1][0]:.0e}"
            + (f" (stiffness ratio {ratio:.3g}: {'stiff' if method != 'DOP853' else 'non-stiff'})"
               if ratio else ""))
    if why is not None:
        notes.append(f"reference at rtol {rt:.0e}, not the requested {tight:.0e}: {why}"
                     + ("; the rung before it is the reference" if floor else "") + "; its own "
                     f"error ~ {err:.3g} m (against the rung at rtol {rt0:.0e})")
    return tr, name, err, notes


#: the fast ladder (``stand accuracy --fast``): tolerances and the reference's
FAST_RTOLS = (1e-4, 1e-6)
FAST_REFERENCE_RTOL = 1e-10


def accuracy(scene: Scene, rtols=DEFAULT_RTOLS, methods=None, rk4_steps=None,
             reference_rtol: float | None = None) -> AccuracyReport:
    """Run ``scene`` at each tolerance and method; errors vs exact or reference.

    Parameters
    ----------
    scene : Scene
    rtols : sequence of float
        Relative tolerances; atol = rtol / 100 on the dimensionless state.
    methods : sequence of str, optional
        Default: the automatically chosen method, plus "Radau" for stiff scenes.
        "RK4" adds fixed-step RK4 runs, one per entry of ``rk4_steps``.
    rk4_steps : sequence of float, optional
        RK4 steps [s] (default: 1/20 and 1/40 of the period at the top speed).
    reference_rtol : float, optional
        Tolerance of the reference run where no closed form exists (default
        1e-13 for DOP853, 1e-11 for the implicit methods, 1e-12 for a book model).

    Every scene: the planar rotor's closed forms where they exist (no weights),
    else a much tighter reference run of the same scene; fixed-step RK4 rows for
    the planar rotor only (a note says so otherwise).
    """

    from stand.model.balancers.runup_closed_form import free_whirl_amplitudes, runup_closed_form_state

    from stand.integrate.simulate import auto_method

    notes = []
    auto = auto_method(scene)
    if methods is None:
        methods = [auto] if auto == "DOP853" else ["Radau", "BDF"]
    methods = list(methods)
    want_rk4 = "RK4" in methods
    methods = [m for m in methods if m != "RK4"]
    if want_rk4 and (scene.kind != "planar" or scene.friction is not None):
        want_rk4 = False
        notes.append("not applicable: RK4 rows: the fixed-step RK4 loop runs the planar rotor's "
                     f"kernel only (this scene runs on the generic kernel: {scene.generic_kernel})")
    if scene.kind == "book" and "numpy-DOP853" in methods:
        methods.remove("numpy-DOP853")
    ref_method = "DOP853" if auto == "DOP853" else "Radau"
    budget = _LadderBudget(scene)
    runs = {}
    for m in methods:
        for rt in rtols:
            runs[(m, rt)] = budget.simulate(method=m, rtol=rt, atol=rt * 1e-2)
    if runs:
        t = next(iter(runs.values())).t
    else:
        from stand.integrate.simulate import sample_times
        t = sample_times(scene.run.duration, scene.run.sample_rate)
    ru = runup_params(scene)
    exact = closed_form_no_balancer(scene, t)
    ref_vel = None
    valid = np.ones(t.size, bool)
    if ru is not None:
        params, t_end = ru
        valid = t <= t_end
        ref, ref_vel = runup_closed_form_state(params, np.where(valid, t, 0.0))
        ref = np.where(valid, ref, np.nan)
        kern = "Fresnel integrals" if params.n == 0 else "Faddeeva function"
        what = "paper 001 model M1, liquid lever" if scene.bodies else "no weights"
        ref_name = (f"closed form run-up ({kern}; {what}, constant acceleration "
                    f"{2 * params.epsilon:g} rad/s^2 from the stationary whirl; valid to "
                    f"t = {t_end:g} s)")
        ref_err = 0.0
    elif exact is not None:
        ref = exact
        ref_name = "closed form (no weights, constant speed, isotropic supports)"
        ref_err = 0.0
    else:
        tight = reference_rtol or (1e-12 if scene.kind == "book"
                                   else 1e-13 if ref_method == "DOP853" else 1e-11)
        r1, ref_name, ref_err, more = reference_ladder(budget, ref_method, tight,
                                                       min(rtols, default=tight * 1e3))
        ref = _position(r1)
        notes += more
    scale = float(np.nanmax(np.abs(ref))) or 1.0
    # free-whirl constants (undamped run-up): compare at the last valid sample
    drift_ok = ru is not None and ru[0].n == 0.0
    if drift_ok:
        kl = int(np.nonzero(valid)[0][-1])
        c_ref = float(free_whirl_amplitudes(ru[0], t[kl:kl + 1], ref[kl:kl + 1], ref_vel[kl:kl + 1])[0][0])

    def drift(Z, Zd):
        if not drift_ok or not np.isfinite(Z[kl]):
            return float("nan")
        c = float(free_whirl_amplitudes(ru[0], t[kl:kl + 1], Z[kl:kl + 1], Zd[kl:kl + 1])[0][0])
        return (c - c_ref) / c_ref

    rows = []
    for (m, rt), tr in runs.items():
        k = min(len(tr.t), len(ref))
        pos = _position(tr)[:k]
        err = float(np.nanmax(np.abs(pos - ref[:k]))) if k else float("nan")
        dr = drift(_position(tr), _velocity(tr)) if drift_ok and k > kl else float("nan")
        rows.append(AccuracyRow(m, rt, rt * 1e-2, err, err / scale, tr.stats.wall_time,
                                tr.stats.nfev, tr.stats.n_steps, tr.stats.success,
                                free_whirl_drift=dr))
    if want_rk4:
        if rk4_steps is None:
            rk4_steps = default_rk4_steps(scene)
        for h in rk4_steps:
            Z, Zd, wall, nfev, nst, hh = _rk4_run(scene, float(h), t)
            err = float(np.nanmax(np.abs(Z - ref)))
            rows.append(AccuracyRow("RK4", float("nan"), float("nan"), err, err / scale, wall,
                                    nfev, nst, bool(np.all(np.isfinite(Z))), step_s=hh,
                                    free_whirl_drift=drift(Z, Zd)))
    smallest = min((r.max_error_m for r in rows if r.success), default=np.inf)
    if ref_err > 0 and not ref_err < 0.1 * smallest:
        notes.append(f"the reference's own error ({ref_err:.3g} m) is not 10 x below the runs' "
                     f"errors (the smallest {smallest:.3g} m): they do not measure the methods (the "
                     "runs reach the round-off floor, or the motion is sensitive to the tolerance, "
                     "e.g. weights settling elsewhere)")
    span = float(t[valid][-1]) if valid.any() else float("nan")   # the run, within the reference
    return AccuracyReport(scene.name, ref_name, ref_err, scale, rows, notes, compared_to_s=span)
