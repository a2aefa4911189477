"""Part (b) of ``bench_family.py``: the generic rotor-family kernel against the compiled floor.

The floor is numbalsoda's C++ LSODA (and, as an extra row, its Fortran DOP853) calling a
numba ``cfunc`` that wraps the stand's own generic right-hand side
(:func:`stand.model.rotors.coupled_kernel.rhs_generic`) on the model's packed arrays
(``sp``, ``wt``, ``prog`` in one ``data`` array, with an RHS call counter).  So the floor
and the stand evaluate the same compiled RHS on the same scaled state (coordinates in
units of their capacity response, time tau = omega_ref t) at the same rtol / atol; what
differs is the stepper and what the stand does around it.  The stand is timed as a whole
call of :func:`stand.integrate.coupled.simulate_coupled` and by phases (model
packing, initial state, the compiled DOP853 loop, the SI conversion of the samples), so a
gap to the floor is attributed to a phase.

Each contender's answer is checked (``_peers.check_peer``) against the stand's run at
rtol 1e-12 before its time is shown; the contenders are then timed in turn, round after
round, and each one's best time is kept (:func:`interleaved`).

benchmarks/ is not a package: ``bench_family.py`` imports this file as ``_family_floor``.
"""
from __future__ import annotations

import math
import time

import numpy as np

from _peers import check_peer

__all__ = ["pack_model", "make_rhs_cfunc", "make_numbalsoda", "run_numbalsoda", "stand_phases",
           "interleaved", "floor"]

MXSTEP = 1_000_000               # per output interval (numbalsoda)
#: numbalsoda's ``data`` array: a header, then sp, wt and prog (row-major)
HDR = 7
H_NSP, H_NW, H_WTC, H_ROWS, H_COLS, H_SIZE, H_CALLS = range(HDR)   # len(sp), weights, wt
# columns, prog rows, prog columns, state size, RHS-call counter


def pack_model(model) -> np.ndarray:
    """``model.sp``, ``model.wt``, ``model.prog`` (and a call counter) in one float array.

    Parameters
    ----------
    model : stand.model.rotors.coupled_kernel.CoupledModel

    Returns
    -------
    ndarray
        ``[header(HDR), sp, wt.ravel(), prog.ravel()]``; :func:`make_rhs_cfunc` rebuilds the
        three arrays from it (shapes in the header).  ``sp`` ends with the RHS's scratch
        block, so one array serves one integration at a time.
    """
    wt, prog = np.atleast_2d(model.wt), np.atleast_2d(model.prog)
    if wt.size == 0:
        wt = np.zeros((0, model.wt.shape[-1] if model.wt.ndim == 2 else 0))
    head = np.zeros(HDR)
    head[[H_NSP, H_NW, H_WTC, H_ROWS, H_COLS, H_SIZE]] = (
        model.sp.size, wt.shape[0], wt.shape[1], prog.shape[0], prog.shape[1], model.size)
    return np.concatenate([head, model.sp, wt.ravel(), prog.ravel()]).astype(np.float64)


def make_rhs_cfunc():
    """numba ``cfunc`` (numbalsoda's ``lsoda_sig``) of ``rhs_generic`` on a :func:`pack_model`
    array; it counts its calls in ``data[H_CALLS]``.

    Raises
    ------
    ImportError
        When numba or numbalsoda is missing.
    """
    from numba import carray, cfunc
    from numbalsoda import lsoda_sig

    from stand.model.rotors.coupled_kernel import rhs_generic

    @cfunc(lsoda_sig)
    def rhs_cfunc(t, u, du, p):
        hdr = carray(p, (HDR,))
        nsp = int(hdr[H_NSP])
        nw = int(hdr[H_NW])
        wtc = int(hdr[H_WTC])
        rows = int(hdr[H_ROWS])
        cols = int(hdr[H_COLS])
        m = int(hdr[H_SIZE])
        d = carray(p, (HDR + nsp + nw * wtc + rows * cols,))
        d[H_CALLS] += 1.0
        sp = d[HDR:HDR + nsp]
        wt = d[HDR + nsp:HDR + nsp + nw * wtc].reshape((nw, wtc))
        prog = d[HDR + nsp + nw * wtc:].reshape((rows, cols))
        rhs_generic(t, carray(u, (m,)), carray(du, (m,)), sp, wt, prog)

    return rhs_cfunc


def make_numbalsoda():
    """``(lsoda, dop853, cfunc address)``; raises ImportError (or numba's compile error)."""
    from numbalsoda import dop853, lsoda

    return lsoda, dop853, make_rhs_cfunc().address


def run_numbalsoda(solver, addr, data, y0, tau, rtol, atol):
    """One numbalsoda integration: ``(states at tau, RHS evaluations)``; no rows on failure."""
    data[H_CALLS] = 0.0
    ys, ok = solver(addr, np.array(y0, dtype=float), tau, data=data, rtol=rtol, atol=atol,
                    mxstep=MXSTEP)
    return (ys if ok else ys[:0]), int(data[H_CALLS])


def stand_phases(scene, rtol, atol):
    """:func:`simulate_coupled`'s steps timed one by one (the same calls, in its order).

    Returns
    -------
    (dict, ndarray, int)
        Wall time [s] per phase (``build``: :func:`build_model`; ``initial``:
        :func:`initial_state` and the sample grid; ``integrate``: the compiled DOP853
        driver; ``si``: :func:`samples_si`), the rotor coordinates q (k, n) [SI] and the
        RHS evaluations.
    """
    from stand.integrate.driver import run_dop853
    from stand.integrate.result import SolverStats
    from stand.integrate.coupled import build_model, initial_state, samples_si

    rotor, prog = scene.linear_rotor(), scene.drive.programme
    dur, rate = scene.run.duration, scene.run.sample_rate
    t = {}
    t0 = time.perf_counter()
    model = build_model(rotor, scene.weights, prog)
    t1 = time.perf_counter()
    y = initial_state(model, scene.weights)
    w = model.omega_ref
    ts = np.arange(0.0, dur + 0.5 / rate, 1.0 / rate) * w
    ts = ts[ts <= dur * w * (1 + 1e-12)]
    out = np.full((ts.size, y.size), np.nan)
    out[0] = y
    st = SolverStats(method="DOP853", rtol=rtol, atol=atol)
    t2 = time.perf_counter()
    k = run_dop853(model, y, dur * w, rtol, atol, ts, out, st, 10_000_000, False)
    t3 = time.perf_counter()
    res = samples_si(model, out[:k], ts[:k])
    t4 = time.perf_counter()
    t.update(build=t1 - t0, initial=t2 - t1, integrate=t3 - t2, si=t4 - t3)
    if not st.success:
        raise RuntimeError(st.message)
    return t, res[1], st.nfev


def interleaved(fns: dict, rounds: int):
    """Best wall time [s] of each callable over ``rounds`` round-robin rounds, and its last
    result (the contenders run in turn, so the machine's drift hits all alike)."""
    best = {k: math.inf for k in fns}
    last = {}
    for _ in range(max(1, int(rounds))):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            last[k] = fn()
            best[k] = min(best[k], time.perf_counter() - t0)
    return best, last


def floor(name, scene, ref, ours, error, tol, rtol, atol, rounds=3):
    """Print part (b) for one problem and return its rows.

    Parameters
    ----------
    name : str
    scene : the problem's scene
    ref : ndarray (k, n)
        Reference rotor coordinates [SI] (the stand at rtol 1e-12).
    ours : callable
        ``ours(scene, rtol, atol)`` -> a :class:`CoupledRun` (the whole stand call).
    error : callable
        ``error(q, ref)`` -> relative error (bench_family's ``error``).
    tol : float
        Largest error for a valid peer, same unit.
    rtol, atol : float
        The tolerances of every contender (on the stand's scaled state).
    rounds : int
        Round-robin timing rounds (at least; a short run gets more, see the code).

    Returns
    -------
    list of (label, Peer, time [s] or None, RHS evaluations, note)
    """
    from stand.integrate.coupled import build_model, initial_state

    model = build_model(scene.linear_rotor(), scene.weights, scene.drive.programme)
    y0 = initial_state(model, scene.weights)
    w, dur, rate = model.omega_ref, scene.run.duration, scene.run.sample_rate
    tau = np.arange(0.0, dur + 0.5 / rate, 1.0 / rate) * w
    tau = tau[tau <= dur * w * (1 + 1e-12)]
    n = model.n

    def q_of(ys):
        return ys[:, :n] * model.scale if ys.shape[0] == tau.size else np.zeros((0, n))

    fns, checks, nfev = {}, {}, {}
    t0 = time.perf_counter()
    r = ours(scene, rtol, atol)
    # a short run is timed in more rounds (about 0.5 s of the stand's calls, at most 25):
    # its best time then escapes the other processes' bursts as a long run's does
    rounds = max(int(rounds), min(25, int(0.5 / max(time.perf_counter() - t0, 1e-6))))
    checks["stand"] = check_peer("stand DOP853 (simulate_coupled)", error(r.q, ref), tol)
    nfev["stand"] = r.stats["nfev"]
    fns["stand"] = lambda: ours(scene, rtol, atol)
    ph, q_ph, _ = stand_phases(scene, rtol, atol)
    checks["phases"] = check_peer("stand, by phases", error(q_ph, ref), tol)
    phases = {}

    def timed_phases():
        p, _, _ = stand_phases(scene, rtol, atol)
        for k, v in p.items():
            phases[k] = min(phases.get(k, math.inf), v)

    fns["phases"] = timed_phases
    note = ""
    try:
        lsoda, nb_dop853, addr = make_numbalsoda()
    except Exception as exc:  # noqa: BLE001 - the reason is printed
        note = f"numbalsoda unavailable ({type(exc).__name__}: {exc}): not evaluated"
    else:
        for key, label, solver in (("lsoda", "numbalsoda LSODA (C++)", lsoda),
                                   ("nb_dop853", "extra: numbalsoda DOP853 (Fortran)", nb_dop853)):
            data = pack_model(model)
            ys, nf = run_numbalsoda(solver, addr, data, y0, tau, rtol, atol)
            checks[key] = check_peer(label, error(q_of(ys), ref), tol)
            nfev[key] = nf
            if checks[key].valid:
                fns[key] = (lambda solver=solver, data=data:
                            run_numbalsoda(solver, addr, data, y0, tau, rtol, atol))
    best, _ = interleaved(fns, rounds)
    t_stand = best["stand"]
    from stand.integrate.kernel_set import kernels

    print(f"\n(b) {name}: compiled floor, rtol {rtol:g}, atol {atol:g} (scaled state), error = "
          f"max|q - q_ref| / max|q_ref| (ref: stand at rtol 1e-12), tolerance {tol:g}, "
          f"best of {rounds} interleaved rounds; the stand's kernels: {kernels(model.kind).source} "
          f"(STAND_KERNELS=jit / precompiled chooses)")
    print(f"  {'contender':<40} {'wall [ms]':>10} {'RHS evals':>10} {'error':>9} "
          f"{'time / stand':>13}")
    rows = []
    integ = phases.get("integrate", math.nan)
    entries = [("stand", "stand DOP853, whole call", t_stand, nfev["stand"]),
               ("phases", "stand DOP853, integration only", integ, nfev["stand"])]
    for key in ("lsoda", "nb_dop853"):
        if key in checks:
            entries.append((key, checks[key].name, best.get(key), nfev[key]))
    for key, label, t, nf in entries:
        p = checks[key]
        cells = p.cells(f"{t * 1e3:10.2f}", f"{t / t_stand:13.2f}")
        if p.valid:
            print(f"  {label:<40} {cells[0]} {nf:>10d} {p.error:>9.1e} {cells[1]}")
        else:
            print(f"  {label:<40} {cells[0]}")
        rows.append((label, p, t if p.valid else None, nf, ""))
    if note:
        print(f"  numbalsoda LSODA: {note}")
        rows.append(("numbalsoda LSODA (C++)", None, None, 0, note))
    if phases:
        tot = sum(phases.values())
        print("  stand phases (best of each): " + ", ".join(
            f"{k} {v * 1e3:.2f} ms ({100 * v / tot:.0f} %)" for k, v in phases.items()))
        print(f"  stand integration: {integ / max(nfev['stand'], 1) * 1e6:.2f} µs per RHS "
              f"evaluation (stepper included)")
    valid_floor = [best[k] for k in ("lsoda", "nb_dop853") if k in best]
    if valid_floor:
        f = min(valid_floor)
        verdict = "within" if t_stand <= 1.5 * f else "NOT within"
        print(f"  stand / fastest floor = {t_stand / f:.2f} (whole call), {integ / f:.2f} "
              f"(integration only): {verdict} 1.5x")
    return rows
