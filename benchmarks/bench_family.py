"""The rotor family's generic kernel against its peers (issue 33).

(a) the stand's generic kernel (compiled DOP853, :func:`stand.integrate.coupled.simulate_coupled`)
    against scipy's ``solve_ivp`` (DOP853) on a right-hand side written here in numpy from the
    equations of :mod:`stand.model.rotors.coupled_kernel`'s docstring (SI state, the Schur
    system assembled with matrix products and solved by ``np.linalg.solve``: the same linear
    structure and weights, none of the stand's code), at the same rtol/atol, on
    1. a rigid rotor on two elastic supports (model 2.7.2) with two two-ball balancers, and
    2. the hinged-hinged flexible shaft with 10 modes per direction (stress_flexible_10modes).
    Reference: the stand at rtol 1e-12.  Both answers are checked (``_peers.check_peer``)
    before their times are printed; the numpy peer agreeing with the stand's tight run is
    also the check of the stand's kernel against an independent formulation.
(b) the compiled floor (``_family_floor.py``): numbalsoda's LSODA (and its Fortran DOP853,
    an extra row) on a numba ``cfunc`` of the same kernel's RHS, same problems, same
    tolerances; the stand timed as a whole call and by phases; else said why not.
(c) ROSS (``_family_ross.py``): a Jeffcott run-up through the critical speed in ROSS (Newmark,
    run in ROSS's own interpreter: ``$ROSS_PYTHON``, /opt/rossenv/bin/python, or this one)
    and in the stand, each against an exact answer of its own model; else said so.
(d) cost growth: µs per right-hand-side evaluation (a run's wall time / its evaluations)
    of the flexible shaft with n_modes x number of balls.

Usage: ``python benchmarks/bench_family.py [--repeats 3] [--numpy-repeats 1] [--parts abcd]``
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _peers import best_of, check_peer  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
RTOL, ATOL = 1e-9, 1e-12
#: a peer's largest |q - q_ref| / max |q_ref| (q: rotor coordinates at the samples)
TOL_FACTOR = 1000.0    # x rtol

SPATIAL_TWO = """
[scene]
name = "bench_spatial_two_balancers"
[structure]
type = "spatial"
mass = 10.0
A = 0.3
C = 0.1
l1 = 0.2
l2 = 0.3
c1 = 2.0e4
balancer_positions = [-0.15, 0.1]
unbalance = 2.0e-3
unbalance_position = 0.1
stiffness_damping = 1.0e-3
[[weights]]
plane = "balancer1"
type = "balls"
count = 2
mass = 0.02
radius = 0.1
drag = 0.5
initial_angles = [60.0, 250.0]
[[weights]]
plane = "balancer2"
type = "balls"
count = 2
mass = 0.02
radius = 0.1
drag = 0.5
initial_angles = [10.0, 200.0]
[drive]
type = "speed"
programme = [[0.0, 0.0], [3.0, 15.0]]
[run]
duration = 6.0
sample_rate = 200.0
"""


def load(source):
    from stand.scene.parse import load_scene

    if isinstance(source, Path):
        return load_scene(source)
    import tempfile

    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as fh:
        fh.write(source)
    return load_scene(fh.name)


def flexible(n_modes: int, balls: int, duration: float = 1.5) -> str:
    text = (ROOT / "data_samples" / "scenes" / "stress_flexible_10modes.toml").read_text()
    angles = ", ".join(f"{(60.0 + 360.0 * k / balls) % 360:.1f}" for k in range(balls))
    text = text.replace("n_modes = 10", f"n_modes = {n_modes}")
    text = text.replace("count = 2", f"count = {balls}").replace(
        "initial_angles = [60.0, 250.0]", f"initial_angles = [{angles}]")
    return text.replace("duration = 1.5", f"duration = {duration}")


def ours(scene, rtol=RTOL, atol=ATOL):
    from stand.integrate.coupled import simulate_coupled

    r = simulate_coupled(scene.linear_rotor(), scene.weights, scene.drive.programme,
                         scene.run.duration, scene.run.sample_rate, rtol=rtol, atol=atol)
    if not r.success:
        raise RuntimeError(r.stats["message"])
    return r


# ----------------------------------------------------------- the numpy peer (SI, independent)
def numpy_problem(scene):
    """(rhs(t, z), z0, t_eval, n) of the scene in SI: z = (q, alpha, q', alpha')."""
    rotor = scene.linear_rotor()
    n = rotor.n
    M, G, D, K = rotor.M, rotor.G, rotor.D, rotor.K
    grav, gp = np.asarray(rotor.gravity, float), np.asarray(rotor.gravity_plane, float)
    prog = np.asarray(scene.drive.programme, float)
    tk, wk = prog[:, 0], prog[:, 1]
    phik = np.concatenate([[0.0], np.cumsum(0.5 * (wk[1:] + wk[:-1]) * np.diff(tk))])
    ub = [(rotor.force_map(u.plane), u.s, u.angle) for u in rotor.unbalances]
    W = []
    for pw in scene.weights:
        b = pw.balancer
        T, F = rotor.planes[pw.plane], rotor.force_map(pw.plane)
        for k in range(b.count):
            W.append((T, F, b.mass[k], b.radius[k], b.inertia[k], b.moment_drag[k]))
    nw = len(W)
    Tn = np.array([w[0] for w in W])                  # (nw, 2, n)
    Fn = np.array([w[1] for w in W])
    m, l, J, H = (np.array([w[i] for w in W]) for i in range(2, 6))
    k2 = m * m * l * l / J
    A0 = M + np.einsum("j,jai,jak->ik", m, Fn, Tn)

    def speed(t):
        if t >= tk[-1]:
            return phik[-1] + wk[-1] * (t - tk[-1]), wk[-1], 0.0
        i = max(0, int(np.searchsorted(tk, t, side="right")) - 1)
        a = (wk[i + 1] - wk[i]) / (tk[i + 1] - tk[i])
        dt = t - tk[i]
        return phik[i] + wk[i] * dt + 0.5 * a * dt * dt, wk[i] + a * dt, a

    def rhs(t, z):
        q, al, qd, ald = z[:n], z[n:n + nw], z[n + nw:2 * n + nw], z[2 * n + nw:]
        phi, Om, dOm = speed(t)
        f = grav - K @ q - (D + Om * G) @ qd
        for F, s, th in ub:
            c, si = np.cos(phi + th), np.sin(phi + th)
            f = f + F.T @ (s * np.array([Om * Om * c + dOm * si, Om * Om * si - dOm * c]))
        psi, psid = phi + al, Om + ald
        e = np.stack([np.cos(psi), np.sin(psi)], 1)   # (nw, 2)
        nv = np.stack([np.sin(psi), -np.cos(psi)], 1)
        Mr = H * ald
        ng = nv @ gp
        force = (m[:, None] * gp + (m * l * psid ** 2)[:, None] * e
                 - (k2 * ng)[:, None] * nv - (m * l * Mr / J)[:, None] * nv)
        f = f + np.einsum("jai,ja->i", Fn, force)
        Fnv = np.einsum("jai,ja->ji", Fn, nv)
        Tnv = np.einsum("jai,ja->ji", Tn, nv)
        A = A0 - np.einsum("j,ji,jk->ik", k2, Fnv, Tnv)
        qdd = np.linalg.solve(A, f)
        psidd = (m * l * (Tnv @ qdd - ng) - Mr) / J
        return np.concatenate([qd, ald, qdd, psidd - dOm])

    z0 = np.zeros(2 * (n + nw))
    z0[n:n + nw] = np.concatenate([np.asarray(pw.balancer.initial_angles, float)
                                   for pw in scene.weights])
    ts = np.arange(0.0, scene.run.duration + 0.5 / scene.run.sample_rate,
                   1.0 / scene.run.sample_rate)
    return rhs, z0, ts[ts <= scene.run.duration * (1 + 1e-12)], n


def run_numpy(scene, rtol=RTOL, atol=ATOL):
    from scipy.integrate import solve_ivp

    from stand.integrate.coupled import build_model

    rhs, z0, ts, n = numpy_problem(scene)
    # the stand's atol is on its scaled state (coordinates in units of their capacity response
    # ``scale``, time in 1/omega_ref): the same absolute error control in SI, per component
    m = build_model(scene.linear_rotor(), scene.weights, scene.drive.programme)
    nw = z0.size // 2 - n
    w = m.omega_ref
    atol_si = atol * np.concatenate([m.scale, np.ones(nw), m.scale * w, np.full(nw, w)])
    r = solve_ivp(rhs, (0.0, ts[-1]), z0, method="DOP853", t_eval=ts, rtol=rtol, atol=atol_si)
    if not r.success:
        raise RuntimeError(r.message)
    return r.y[:n].T, r.nfev


def error(q, ref) -> float:
    if q.shape != ref.shape:
        return float("inf")
    return float(np.max(np.abs(q - ref)) / np.max(np.abs(ref)))


# --------------------------------------------------------------------------------- (a)
def compare(name, scene, repeats, np_repeats):
    ref = ours(scene, 1e-12, 1e-15).q
    t_ours, r = best_of(lambda: ours(scene), repeats)
    e_ours = error(r.q, ref)
    tol = TOL_FACTOR * RTOL
    p_ours = check_peer("stand generic kernel", e_ours, tol)
    t0 = time.perf_counter()
    try:
        q_np, nfev_np = run_numpy(scene)
        e_np = error(q_np, ref)
    except Exception as exc:  # noqa: BLE001 - no answer
        print(f"  numpy peer failed: {exc}")
        e_np, nfev_np = float("nan"), 0
    t_np = time.perf_counter() - t0
    for _ in range(np_repeats - 1):
        t0 = time.perf_counter()
        run_numpy(scene)
        t_np = min(t_np, time.perf_counter() - t0)
    p_np = check_peer("scipy solve_ivp DOP853, numpy RHS", e_np, tol)
    rows = [(p_ours, t_ours, r.stats["nfev"]), (p_np, t_np, nfev_np)]
    print(f"\n(a) {name}: rtol {RTOL:g}, error = max|q - q_ref| / max|q_ref| (ref: stand at "
          f"rtol 1e-12), tolerance {tol:g}")
    for p, t, nfev in rows:
        print("  " + p.line(f"{t * 1e3:9.1f} ms  error {p.error:.2e}  {nfev} RHS evals  "
                            f"{t / max(nfev, 1) * 1e6:.2f} µs/eval"))
    ratio = t_np / t_ours if p_ours.valid and p_np.valid else None
    print(f"  naive SciPy / stand: {f'{ratio:.0f}x' if ratio else 'not evaluated'}")
    return name, rows, ratio


# --------------------------------------------------------------------------------- (b)
def floor_part(problems, rounds):
    """Part (b) on each problem (benchmarks/_family_floor.py); a markdown table at the end."""
    from _family_floor import floor

    tables = []
    for name, sc in problems:
        ref = ours(sc, 1e-12, 1e-15).q
        tables.append((name, floor(name, sc, ref, ours, error, TOL_FACTOR * RTOL, RTOL, ATOL,
                                   max(3, rounds))))
    print("\n| problem | contender | wall [ms] | RHS evals | error | time / stand |")
    print("|---|---|---|---|---|---|")
    for name, rows in tables:
        t_stand = rows[0][2]
        for label, p, t, nfev, note in rows:
            if p is None:
                print(f"| {name} | {label} | {note} | | | |")
            elif p.valid:
                print(f"| {name} | {label} | {t * 1e3:.2f} | {nfev} | {p.error:.1e} | "
                      f"{t / t_stand:.2f} |")
            else:
                print(f"| {name} | {label} | {p.verdict} | {nfev} | | - |")
    return tables


# --------------------------------------------------------------------------------- (d)
def growth(modes=(2, 4, 6, 8, 10), balls=(2, 4, 8)):
    print("\n(d) µs per RHS evaluation inside the compiled loop (run wall time / evaluations), "
          "flexible shaft, 0.3 s of the run-up")
    print("  n_modes " + "".join(f"{b:>4} balls" for b in balls))
    table = {}
    for nm in modes:
        cells = []
        for b in balls:
            sc = load(flexible(nm, b, 0.3))
            t, r = best_of(lambda: ours(sc), 3)
            us = t / max(r.stats["nfev"], 1) * 1e6
            table[(nm, b)] = us
            cells.append(f"{us:>10.2f}")
        print(f"  {nm:>7} " + "".join(cells))
    return table


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--numpy-repeats", type=int, default=1)
    ap.add_argument("--parts", default="abcd", help="which parts to run (default abcd)")
    a = ap.parse_args(argv)
    ours(load(flexible(2, 2, 0.05)))     # load / compile the kernel before timing
    problems = [("spatial rotor, two supports, two two-ball balancers", load(SPATIAL_TWO)),
                ("flexible shaft, 10 modes per direction, two balls",
                 load(ROOT / "data_samples" / "scenes" / "stress_flexible_10modes.toml"))]
    results = ([compare(name, sc, a.repeats, a.numpy_repeats) for name, sc in problems]
               if "a" in a.parts else [])
    if "b" in a.parts:
        floor_part(problems, a.repeats)
    if "c" in a.parts:
        from _family_ross import compare_ross

        compare_ross(load, ours, repeats=a.repeats)
    if "d" not in a.parts:
        return 0
    table = growth()
    print("\n| problem | stand [ms] | error | naive SciPy [ms] | error | ratio |")
    print("|---|---|---|---|---|---|")
    for name, rows, ratio in results:
        (po, to, _), (pn, tn, _) = rows
        cell = lambda p, t: (f"{t * 1e3:.1f} | {p.error:.1e}" if p.valid  # noqa: E731
                             else f"- | {p.verdict}")
        print(f"| {name} | {cell(po, to)} | {cell(pn, tn)} | "
              f"{f'{ratio:.0f}x' if ratio else 'not evaluated'} |")
    print("\n| n_modes | " + " | ".join(f"{b} balls [µs/RHS]" for b in (2, 4, 8)) + " |")
    print("|---|---|---|---|")
    for nm in (2, 4, 6, 8, 10):
        print(f"| {nm} | " + " | ".join(f"{table[(nm, b)]:.2f}" for b in (2, 4, 8)) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
