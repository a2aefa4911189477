#!/usr/bin/env python
"""Core performance benchmark of the stand's compiled integrator (a script, not a test).

Everything is measured in one run on this machine and printed as plain text,
then as markdown tables for the README:

(a) ``stand.integrate.simulate(method="DOP853")`` (compiled Dormand-Prince 8(5,3) with the
    O(n) compiled right-hand side) against ``scipy.integrate.solve_ivp(method=
    "DOP853")`` on the plain-numpy right-hand side that solves the full (n+2)
    linear system (``stand.model.planar.rhs_planar_numpy``);
(b) the same problem against a compiled LSODA: numbalsoda's C++ LSODA calling a
    numba ``cfunc`` wrapper of ``stand.model.planar.rhs_planar`` (plus two clearly
    labelled extra peers: numbalsoda's Fortran DOP853 on the same cfunc, and
    scipy's ``odeint`` -- Fortran LSODA calling the compiled RHS through Python);
(c) the cost per rotor revolution for n = 2, 8, 32, 64 weights.

Every contender's answer is checked against the reference before its time is
printed (``benchmarks/_peers.py``): one full run first, and a contender whose
error exceeds ``TOL_FACTOR * (rtol * max|xi, eta| + atol)`` is printed as
"invalid (error X > tolerance Y)" and is neither timed nor compared.

Problem (a)/(b): n = 2 identical balls, Rt = 0.01, h = 0.5, H = 0.1, e0 = 0.3,
constant prescribed speed R_omega = 3, balls starting at +-2 rad from the
reference mark (they balance the rotor), 1000 revolutions, 2 samples per
revolution, rtol 1e-8 / atol 1e-10 for every solver.  Errors: max abs error of
the shaft position (xi, eta) at the samples against our DOP853 at rtol 1e-13 /
atol 1e-15.  Numba compile time is excluded (every solver is warmed up with the
exact call it is timed with); compiled runs are timed best of ``--repeats`` rounds in
which the contenders run in turn, since the machine's speed drifts.

``--scene FILE [--duration S]`` runs (a) and (b) on a planar scene file instead
(e.g. data_samples/scenes/ball_runup.toml: a speed programme of several rows),
at the scene's own rtol/atol and sample rate; (c) is skipped.

Run:  python benchmarks/bench_core.py            (about half a minute)
      python benchmarks/bench_core.py --scene data_samples/scenes/ball_runup.toml --duration 12
"""
from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
from dataclasses import replace
from importlib import metadata

import numpy as np

try:  # run from a checkout without ``pip install -e .``
    import stand  # noqa: F401
except ImportError:  # pragma: no cover
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if os.path.dirname(os.path.abspath(__file__)) not in sys.path:   # imported by a test
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from _peers import best_of, check_peer  # noqa: E402

from numba import njit
from scipy.integrate import odeint, solve_ivp

from stand.model.planar import build_planar_model, initial_state, rhs_planar, rhs_planar_numpy
from stand.scene.model import RunSettings, SpeedDrive
from stand.scene.parse import load_scene, scene_from_dimensionless
from stand.integrate.simulate import simulate

# ---------------------------------------------------------------- the problem
R_OMEGA = 3.0                     # rad/s = dimensionless (omega_1 = 1 rad/s)
PHYS = dict(Rt=0.01, h=0.5, H=0.1, e0=0.3)
ANGLES_2 = (2.0, -2.0)            # rad from the reference mark: the balls balance
SAMPLES_PER_REV = 2
RTOL, ATOL = 1e-8, 1e-10
REF_RTOL, REF_ATOL = 1e-13, 1e-15
REVS_A = 1000
REVS_C = 200
NS_C = (2, 8, 32, 64)
CLUMP_SPREAD = 0.05               # rad, half-width of each starting clump in (c)
MXSTEP = 1_000_000                # per output interval, numbalsoda / odeint
#: a contender is valid when its max error of (xi, eta) is at most
#: TOL_FACTOR * (rtol * max|xi, eta of the reference| + atol): the global error of a
#: correct solver at these tolerances stays within a few local tolerances (the
#: default problem: 1e-9 .. 4e-9 against a tolerance of 3.4e-7; the run-up scene:
#: 1.9e-7 .. 4.4e-7 against 6.8e-6)
TOL_FACTOR = 100.0


def make_scene(n: int, revs: float, angles) -> object:
    """n identical balls, constant speed R_OMEGA, ``revs`` revolutions."""
    duration = revs * 2.0 * math.pi / R_OMEGA
    run = RunSettings(duration=duration, sample_rate=SAMPLES_PER_REV * R_OMEGA / (2.0 * math.pi),
                      rtol=RTOL, atol=ATOL, method="DOP853")
    return scene_from_dimensionless(n, drive=SpeedDrive(programme=np.array([[0.0, R_OMEGA]])),
                                    run=run, initial_angles=angles, **PHYS)


def short(scene, revs: float = 2.0):
    """The same scene cut to ``revs`` revolutions at its top speed (a warm-up run)."""
    rev_s = revs * 2.0 * math.pi / max(scene.top_speed, 1e-9)
    return replace(scene, run=replace(scene.run, duration=min(scene.run.duration, rev_s)))


def clumped_angles(n: int) -> np.ndarray:
    """n/2 balls around each of the two n = 2 starting angles (spread +-CLUMP_SPREAD).

    Total ball mass is fixed by Rt, so the shaft sees (almost) the same
    transient for every n: the cost difference is the per-weight cost.
    """
    g = n // 2
    off = np.linspace(-CLUMP_SPREAD, CLUMP_SPREAD, g) if g > 1 else np.zeros(1)
    return np.concatenate([ANGLES_2[0] + off, ANGLES_2[1] + off])


def sample_times(scene, model, count: int) -> np.ndarray:
    """Dimensionless sample times, exactly as ``simulate`` places them."""
    return np.arange(count) * (model.omega_1 / scene.run.sample_rate)


def peer_tolerance(ref: np.ndarray, rtol: float, atol: float) -> float:
    """Largest acceptable max error of (xi, eta): TOL_FACTOR x (rtol x max|xi, eta| + atol)."""
    return TOL_FACTOR * (rtol * float(np.max(np.abs(ref[:, :2]))) + atol)


def shaft_error(states: np.ndarray, ref: np.ndarray) -> float:
    """Max abs error of (xi, eta) over the samples (inf if a solver stopped early)."""
    if states.shape[0] != ref.shape[0] or not np.all(np.isfinite(states[:, :2])):
        return math.inf
    return float(np.max(np.abs(states[:, :2] - ref[:, :2])))


def version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


# ------------------------------------------------------------ our simulator
def run_ours(scene, rtol=RTOL, atol=ATOL):
    tr = simulate(scene, method="DOP853", rtol=rtol, atol=atol)
    if not tr.success:
        raise RuntimeError(f"stand DOP853 failed: {tr.stats.message}")
    return tr


class Ours:
    """Timed callable for :func:`interleaved`: one ``simulate()`` call, keeps the best
    integration-only time (``stats.wall_time``) besides the whole-call time."""

    def __init__(self, scene, rtol=RTOL, atol=ATOL):
        self.scene, self.rtol, self.atol = scene, rtol, atol
        self.best_integration = math.inf
        run_ours(short(scene), rtol, atol)  # warm-up: compile / load the kernel

    def __call__(self):
        tr = run_ours(self.scene, self.rtol, self.atol)
        self.best_integration = min(self.best_integration, tr.stats.wall_time)
        return tr


def interleaved(fns: dict, rounds: int):
    """Best wall time of each callable over ``rounds`` round-robin rounds, and its last result.

    The machine's speed drifts (other processes, shared cores): running the
    contenders in turn puts them under the same conditions.
    """
    best = {k: math.inf for k in fns}
    last = {}
    for _ in range(rounds):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            last[k] = fn()
            best[k] = min(best[k], time.perf_counter() - t0)
    return best, last


@njit(cache=False)
def _rhs_loop(k, y, sp, wt, prog):
    dy = np.empty_like(y)
    acc = 0.0
    for i in range(k):
        y[0] = 1e-3 * (i % 7)
        rhs_planar(0.37 * i, y, dy, sp, wt, prog)
        acc += dy[y.shape[0] - 1]
    return acc


class RhsAlone:
    """Timed callable for :func:`interleaved`: ``calls`` compiled RHS calls in a numba loop
    (no stepper); ``ns(best)`` converts its best time to ns per call."""

    def __init__(self, model, y0):
        self.model, self.y = model, y0.copy()
        self.calls = max(10_000, int(5e6 / (50 + 40 * model.n)))
        _rhs_loop(10, self.y, model.sp, model.wt, model.prog)  # compile / warm-up

    def __call__(self):
        m = self.model
        return _rhs_loop(self.calls, self.y, m.sp, m.wt, m.prog)

    def ns(self, best: float) -> float:
        return best / self.calls * 1e9


# ------------------------------------------------------------------ peers
def run_numpy_dop853(model, y0, tau, rtol=RTOL, atol=ATOL):
    sp, wt, prog = model.sp, model.wt, model.prog
    sol = solve_ivp(lambda t, y: rhs_planar_numpy(t, y, sp, wt, prog), (0.0, tau[-1]), y0,
                    method="DOP853", t_eval=tau, rtol=rtol, atol=atol)
    return sol.y.T, int(sol.nfev)


def run_odeint(model, y0, tau, rtol=RTOL, atol=ATOL):
    sp, wt, prog = model.sp, model.wt, model.prog

    def f(t, y):
        dy = np.empty_like(y)
        rhs_planar(t, y, dy, sp, wt, prog)
        return dy

    ys, info = odeint(f, y0, tau, rtol=rtol, atol=atol, tfirst=True, mxstep=MXSTEP,
                      full_output=True)
    if info["message"] != "Integration successful.":
        ys = ys[:0]
    return ys, int(info["nfe"][-1])


#: numbalsoda's ``data`` array: a header, then sp, wt and prog (row-major)
HDR = 6
H_N, H_NSP, H_WTC, H_ROWS, H_COLS, H_CALLS = range(HDR)   # n, len(sp), wt columns, prog rows,
                                                           # prog columns, RHS-call counter


def pack_model(model) -> np.ndarray:
    """sp, wt, prog (and a call counter) in one float array for numbalsoda's ``data``.

    The header holds the shapes as they are -- ``prog`` has one row per point of the
    speed programme (plus unbalance/force rows) and the model's own number of
    columns -- so that :func:`make_rhs_cfunc` rebuilds exactly ``model.sp``,
    ``model.wt`` and ``model.prog``.
    """
    wt, prog = np.atleast_2d(model.wt), np.atleast_2d(model.prog)
    head = np.zeros(HDR)
    head[[H_N, H_NSP, H_WTC, H_ROWS, H_COLS]] = (wt.shape[0], model.sp.size, wt.shape[1],
                                                 prog.shape[0], prog.shape[1])
    return np.concatenate([head, model.sp, wt.ravel(), prog.ravel()]).astype(np.float64)


def make_rhs_cfunc():
    """numba ``cfunc`` (numbalsoda's signature) of ``rhs_planar`` on a :func:`pack_model` array.

    Raises ImportError (or a compile error) when numbalsoda/numba cannot provide it.
    """
    from numba import carray, cfunc
    from numbalsoda import lsoda_sig

    @cfunc(lsoda_sig)
    def rhs_cfunc(t, u, du, p):
        hdr = carray(p, (HDR,))
        n = int(hdr[H_N])
        nsp = int(hdr[H_NSP])
        wtc = int(hdr[H_WTC])
        rows = int(hdr[H_ROWS])
        cols = int(hdr[H_COLS])
        d = carray(p, (HDR + nsp + n * wtc + rows * cols,))
        d[H_CALLS] += 1.0
        sp = d[HDR:HDR + nsp]
        wt = d[HDR + nsp:HDR + nsp + n * wtc].reshape((n, wtc))
        prog = d[HDR + nsp + n * wtc:].reshape((rows, cols))
        m = 2 * (2 + n)
        rhs_planar(t, carray(u, (m,)), carray(du, (m,)), sp, wt, prog)

    return rhs_cfunc


def make_numbalsoda():
    """(lsoda, dop853, cfunc address) or raise ImportError/Exception with the reason."""
    from numbalsoda import dop853, lsoda

    return lsoda, dop853, make_rhs_cfunc().address


def run_numbalsoda(solver, addr, data, y0, tau, rtol=RTOL, atol=ATOL):
    data[H_CALLS] = 0.0
    ys, ok = solver(addr, y0.copy(), tau, data=data, rtol=rtol, atol=atol, mxstep=MXSTEP)
    return (ys if ok else ys[:0]), int(data[H_CALLS])


# ------------------------------------------------------------------ report
def fmt_ms(s: float) -> str:
    return f"{s * 1e3:.3g} ms" if s < 1 else f"{s:.3g} s"


def default_problem():
    """The benchmark's own problem: (scene, description)."""
    scene = make_scene(2, REVS_A, ANGLES_2)
    text = (f"n = 2 balls, Rt = {PHYS['Rt']}, h = {PHYS['h']}, H = {PHYS['H']}, e0 = {PHYS['e0']}, "
            f"constant R_omega = {R_OMEGA:g}, balls start at {ANGLES_2} rad, {REVS_A} rev, "
            f"{SAMPLES_PER_REV} samples/rev")
    return scene, text


def scene_problem(path: str, duration=None):
    """A planar scene file, optionally cut to ``duration`` s: (scene, description)."""
    scene = load_scene(path)
    if duration is not None:
        scene = replace(scene, run=replace(scene.run, duration=float(duration)))
    prog = scene.drive.programme if scene.drive is not None and scene.drive.kind == "speed" else None
    rows = "" if prog is None else f", speed programme of {prog.shape[0]} rows"
    text = (f"scene {path} ({scene.name}{rows}), {scene.run.duration:g} s at "
            f"{scene.run.sample_rate:g} samples/s")
    return scene, text


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=15,
                    help="interleaved timing rounds of the compiled runs (best of)")
    ap.add_argument("--numpy-repeats", type=int, default=2, help="timing repeats of the numpy peer")
    ap.add_argument("--scene", default=None,
                    help="run (a) and (b) on this planar scene file (its rtol/atol); skips (c)")
    ap.add_argument("--duration", type=float, default=None,
                    help="with --scene: the run's duration [s] (default: the scene's)")
    args = ap.parse_args(argv)
    t_start = time.perf_counter()

    if args.scene is None:
        scene, problem = default_problem()
        rtol, atol = RTOL, ATOL
    else:
        scene, problem = scene_problem(args.scene, args.duration)
        rtol, atol = scene.run.rtol, scene.run.atol
    tol = dict(rtol=rtol, atol=atol)

    print("autobalancer-stand core benchmark")
    print(f"python {platform.python_version()} on {platform.machine()} ({os.cpu_count()} cores), "
          f"numpy {np.__version__}, scipy {version('scipy')}, numba {version('numba')}, "
          f"numbalsoda {version('numbalsoda')}")
    print(f"problem: {problem}, rtol {rtol:g} atol {atol:g} for every solver")
    print("timings exclude numba compilation (warm-up with the same call); compiled runs: best of "
          f"{args.repeats} rounds, the contenders run in turn in each round; numpy peer best of "
          f"{args.numpy_repeats}\n")

    # ---------------- reference
    model = build_planar_model(scene)
    y0 = initial_state(scene, model)
    run_ours(short(scene), REF_RTOL, REF_ATOL)
    t_ref, ref_tr = best_of(lambda: run_ours(scene, REF_RTOL, REF_ATOL), 1)
    ref = ref_tr.state
    tau = sample_times(scene, model, ref.shape[0])
    fin = ref_tr.final
    print(f"reference: stand DOP853 rtol {REF_RTOL:g} atol {REF_ATOL:g}: {fmt_ms(t_ref)}, "
          f"{ref_tr.stats.nfev} RHS evals, {ref.shape[0]} samples; max |xi, eta| = "
          f"{np.max(np.abs(ref[:, :2])):.3g}; final residual unbalance {fin['residual_unbalance']:.2g} "
          f"of capacity, balls at {[round(a, 2) for a in fin['weights_relative_angle_deg']]} deg")
    ref12 = run_ours(scene, 1e-12, 1e-14).state
    print(f"  reference check: |ref - stand DOP853 @ rtol 1e-12| = {shaft_error(ref12, ref):.2g}")
    tolerance = peer_tolerance(ref, rtol, atol)
    print(f"  every contender is checked first: valid when max |error of xi, eta| <= "
          f"{TOL_FACTOR:g} x (rtol x {np.max(np.abs(ref[:, :2])):.3g} + atol) = {tolerance:.2g}")

    # ---------------- check every contender with one full run (the warm-up), then time the
    # valid ones together
    peers, answers, fns = {}, {}, {}

    def admit(key, label, fn):
        t0 = time.perf_counter()
        out = fn()
        ys = out.state if key == "ours" else out[0]
        peers[key] = check_peer(label, shaft_error(ys, ref), tolerance)
        answers[key] = (out, time.perf_counter() - t0)
        if peers[key].valid:
            fns[key] = fn

    ours = Ours(scene, rtol, atol)
    admit("ours", "stand DOP853", ours)
    ours.best_integration = math.inf
    nb_reason = None
    try:
        lsoda, nb_dop853, addr = make_numbalsoda()
    except Exception as exc:  # ImportError, or a broken build
        nb_reason = f"numbalsoda unavailable ({type(exc).__name__}: {exc})"
    else:
        data = pack_model(model)
        for key, label, solver in (("lsoda", "numbalsoda LSODA (C++)", lsoda),
                                   ("nb_dop853", "extra: numbalsoda DOP853 (Fortran)", nb_dop853)):
            admit(key, label, lambda solver=solver: run_numbalsoda(solver, addr, data, y0, tau, **tol))
    label_ode = "extra: scipy odeint (Fortran LSODA, RHS via Python)"
    admit("odeint", label_ode, lambda: run_odeint(model, y0, tau, **tol))
    best, last = interleaved(fns, args.repeats)
    for key in peers:
        if key not in last:               # invalid: its one checking run is all there is
            last[key] = answers[key][0]
    ok_ours = peers["ours"].valid
    tr = last["ours"]
    t_ours, t_ours_int = best.get("ours", math.nan), ours.best_integration
    err_ours, nfev_ours = peers["ours"].error, tr.stats.nfev
    if not ok_ours:
        print(f"  stand DOP853: {peers['ours'].verdict}: no time or ratio is printed for anyone")

    # ---------------- (a)
    print("\n(a) stand DOP853 (compiled) vs scipy solve_ivp DOP853 + numpy RHS (full linear system)")
    run_numpy_dop853(model, y0, tau[:5], **tol)  # warm-up
    t_np, (ys_np, nfev_np) = best_of(lambda: run_numpy_dop853(model, y0, tau, **tol), 1)
    peers["numpy"] = check_peer("scipy DOP853+numpy", shaft_error(ys_np, ref), tolerance)
    if peers["numpy"].valid and args.numpy_repeats > 1:
        t_np = min(t_np, best_of(lambda: run_numpy_dop853(model, y0, tau, **tol),
                                 args.numpy_repeats - 1)[0])
    err_np = peers["numpy"].error
    print("  " + peers["ours"].line(
        f"{fmt_ms(t_ours)} whole simulate() call ({fmt_ms(t_ours_int)} integration only), "
        f"{nfev_ours} RHS evals, {tr.stats.n_steps} steps, max err {err_ours:.3g}"))
    print("  " + peers["numpy"].line(f"{fmt_ms(t_np)} (whole run, no scaling), {nfev_np} RHS evals, "
                                     f"max err {err_np:.3g}"))
    if ok_ours and peers["numpy"].valid:
        speedup = t_np / t_ours
        ok_a = speedup >= 30 and err_ours <= 1.01 * err_np
        print(f"  speed-up {speedup:.0f}x (whole call; {t_np / t_ours_int:.0f}x integration only), "
              f"error ratio ours/scipy {err_ours / err_np:.3f} -> goal >= 30x at equal or smaller "
              f"error (within 1 %): {'MET' if ok_a else 'NOT MET'}")
    else:
        print("  goal >= 30x: not evaluated (a contender is invalid)")

    # ---------------- (b)
    print("\n(b) compiled LSODA peer (same problem, same sample times, rtol/atol as above; "
          "timed interleaved with stand DOP853)")
    rows_b = []          # (label, Peer or None, time, nfev, note)
    if nb_reason is not None:
        print(f"  numbalsoda LSODA: skipped: {nb_reason}")
        rows_b.append(("numbalsoda LSODA (C++)", None, None, None, f"skipped: {nb_reason}"))
    else:
        for key in ("lsoda", "nb_dop853"):
            ys, nfev = last[key]
            peer = peers[key]
            rows_b.append((peer.name, peer, best.get(key), nfev, ""))
            text = f"{nfev} RHS evals, max err {peer.error:.3g}"
            if peer.valid:
                text = f"{fmt_ms(best[key])}, {text}"
                if ok_ours:
                    text += (f"; stand DOP853 / it = {t_ours / best[key]:.2f} (whole call), "
                             f"{t_ours_int / best[key]:.2f} (integration)")
            print(f"  {peer.line(text)}" + ("" if peer.valid else f" after {nfev} RHS evals"))
        ys_nbref, _ = run_numbalsoda(nb_dop853, addr, data, y0, tau, REF_RTOL, REF_ATOL)
        print(f"  reference check: |ref - numbalsoda DOP853 @ rtol {REF_RTOL:g}| = "
              f"{shaft_error(ys_nbref, ref):.2g} (independent implementation)")
    ys_ode, nfev_ode = last["odeint"]
    peer = peers["odeint"]
    rows_b.append((label_ode, peer, best.get("odeint"), nfev_ode, ""))
    text = f"{fmt_ms(best['odeint'])}, " if peer.valid else ""
    print(f"  {peer.line(text + f'{nfev_ode} RHS evals, max err {peer.error:.3g}')}"
          + ("" if peer.valid else f" after {nfev_ode} RHS evals"))
    lsoda_peer = rows_b[0][1]
    if lsoda_peer is not None and lsoda_peer.valid and ok_ours:
        t_lsoda = rows_b[0][2]
        ok_b = t_ours <= 1.5 * t_lsoda
        print(f"  goal stand DOP853 <= 1.5x numbalsoda LSODA time: {t_ours / t_lsoda:.2f}x whole call, "
              f"{t_ours_int / t_lsoda:.2f}x integration only -> {'MET' if ok_b else 'NOT MET'}")
    elif lsoda_peer is not None:
        print(f"  goal stand DOP853 <= 1.5x numbalsoda LSODA time: not evaluated "
              f"({'numbalsoda LSODA' if not lsoda_peer.valid else 'stand DOP853'} invalid)")
    else:
        print("  goal stand DOP853 <= 1.5x compiled LSODA time: not evaluated (numbalsoda skipped; "
              "scipy odeint above is the only LSODA peer and calls the RHS through Python)")

    # ---------------- (c)
    rows_c = []
    if args.scene is None:
        rows_c = scaling(args.repeats)

    # ---------------- markdown
    print("\n---- markdown (paste into README) ----\n")
    print(f"Problem: {problem}, rtol {rtol:g} / atol {atol:g}; error = max |Δξ|, |Δη| at the samples "
          f"vs stand DOP853 at rtol {REF_RTOL:g} / atol {REF_ATOL:g}; a contender whose error exceeds "
          f"{tolerance:.2g} is invalid and not timed. Python {platform.python_version()}, "
          f"{os.cpu_count()} cores; numba compile time excluded; compiled runs best of {args.repeats} "
          f"interleaved rounds.\n")
    print("| solver | RHS | wall time | RHS evals | max error (ξ, η) | time / stand DOP853 |")
    print("|---|---|---:|---:|---:|---:|")

    def md(label, rhs, peer, t, nfev, ratio_of=None):
        ratio = "1" if ratio_of is None else (f"{t / t_ours:.0f}" if ratio_of == "int"
                                              else f"{t / t_ours:.2f}")
        if not ok_ours and ratio_of is not None:
            ratio = "-"
        wall, ratio = peer.cells(fmt_ms(t), ratio)
        print(f"| {label} | {rhs} | {wall} | {nfev} | {peer.error:.2g} | {ratio} |")

    md("**stand DOP853** (`simulate`, whole call)", "compiled O(n)", peers["ours"], t_ours, nfev_ours)
    md("stand DOP853, integration only", "compiled O(n)", peers["ours"], t_ours_int, nfev_ours, "f")
    md("scipy `solve_ivp` DOP853", "numpy, full linear system", peers["numpy"], t_np, nfev_np, "int")
    rhs_b = {"numbalsoda LSODA (C++)": "numba cfunc",
             "extra: numbalsoda DOP853 (Fortran)": "numba cfunc",
             label_ode: "compiled, called from Python"}
    for label, peer, t, nfev, note in rows_b:
        if peer is None:
            print(f"| {label} | - | {note} | - | - | - |")
        else:
            md(label, rhs_b[label], peer, t if t is not None else math.nan, nfev, "f")
    if rows_c:
        base = rows_c[0][1]
        print(f"\nScaling: stand DOP853, identical balls (same total mass), constant R_omega = "
              f"{R_OMEGA:g}, {REVS_C} revolutions, rtol {RTOL:g}, integration time only.\n")
        print("| n | time / rev | RHS evals / rev | time / RHS eval (incl. stepper) | RHS alone | "
              "time(n) / time(2) | n / 2 |")
        print("|---:|---:|---:|---:|---:|---:|---:|")
        for n, tpr, fpr, tpf, ns_rhs, _ in rows_c:
            print(f"| {n} | {tpr * 1e6:.1f} µs | {fpr:.1f} | {tpf * 1e9:.0f} ns | {ns_rhs:.0f} ns | "
                  f"{tpr / base:.2f} | {n / 2:g} |")
    print(f"\n(total benchmark run time {time.perf_counter() - t_start:.0f} s)")
    return 0


def scaling(repeats: int) -> list:
    """(c): cost per revolution for NS_C weights; prints the text lines, returns the rows."""
    print(f"\n(c) cost per revolution vs number of weights (identical balls, same Rt so same total "
          f"ball mass, constant R_omega = {R_OMEGA:g}, {REVS_C} rev, rtol {RTOL:g}; balls start in two "
          f"clumps of n/2 around {ANGLES_2} rad, +-{CLUMP_SPREAD} rad; time = integration only, "
          f"best of {repeats} interleaved rounds)")
    runners = {}
    for n in NS_C:
        sc = make_scene(n, REVS_C, clumped_angles(n))
        m = build_planar_model(sc)
        runners["sim", n] = Ours(sc)
        runners["rhs", n] = RhsAlone(m, initial_state(sc, m))
    best_c, last_c = interleaved(runners, repeats)
    rows_c = []
    for n in NS_C:
        trn, t_int = last_c["sim", n], runners["sim", n].best_integration
        ns_rhs = runners["rhs", n].ns(best_c["rhs", n])
        res = trn.final["residual_unbalance"]
        rows_c.append((n, t_int / REVS_C, trn.stats.nfev / REVS_C, t_int / trn.stats.nfev, ns_rhs, res))
    base = rows_c[0][1]
    for n, tpr, fpr, tpf, ns_rhs, res in rows_c:
        print(f"  n = {n:3d}: {tpr * 1e6:7.2f} us/rev, {fpr:6.1f} RHS evals/rev, "
              f"{tpf * 1e9:6.0f} ns per RHS eval incl. stepper ({ns_rhs:5.0f} ns RHS alone), "
              f"time(n)/time(2) = {tpr / base:5.2f} vs n/2 = {n / 2:g}, final residual unbalance {res:.1g}")
    ok_c = all(tpr / base <= max(1.0, n / 2) for n, tpr, *_ in rows_c)
    print(f"  goal growth no faster than linear: {'MET' if ok_c else 'NOT MET'}")
    return rows_c


if __name__ == "__main__":
    sys.exit(main())
