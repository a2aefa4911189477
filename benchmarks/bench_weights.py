"""Body weights on the compiled kernel against the books' Python right-hand sides.

Two measurements, every number from this one run on this machine:

(a) **Liquid float sample** (data_samples/scenes/weight_liquid_float.toml, paper
    001 model M1, run-up over 45 s through the critical speed): the old path
    (the model's own right-hand side in Python stepped by ``solve_ivp``'s
    DOP853, the test oracle ``tests/oracles/book_run.run_book_oracle``) against the
    generic composition on the compiled kernel (``run_book``, what ``stand run``
    does), both at the scene's tolerances.  The error of each is
    measured against the exact closed-form run-up of paper 001
    (:func:`stand.model.balancers.runup_closed_form.runup_closed_form`), so the ratio
    is at equal (or better) accuracy; the script says which.  Each path's
    answer is checked first (``benchmarks/_peers.py``): a relative error above
    ``TOL_RTOL`` x the scene's rtol makes it "invalid (error X > tolerance Y)",
    printed in place of its time, and no ratio is printed.

(b) **Per-call cost against the number of weights**: the compiled right-hand
    side of a planar rotor carrying k two-axis pendulums (k = 1, 2, 4, 8, 16,
    32), timed in a compiled loop; the cost per weight should be flat (linear
    total cost: the bodies couple only through the shaft).

Usage: ``python benchmarks/bench_weights.py [--repeats N]`` (about a minute).
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
SAMPLE = ROOT / "data_samples" / "scenes" / "weight_liquid_float.toml"
#: a path is valid when its max relative error against the closed form is at most
#: TOL_RTOL x the scene's rtol (both paths: about 40 x rtol over the 45 s run-up)
TOL_RTOL = 1000.0


def liquid_float(repeats: int) -> dict:
    import stand
    from stand.integrate.book_run import run_book
    from stand.model.balancers.runup_closed_form import runup_closed_form

    sys.path.insert(0, str(ROOT / "tests"))           # the books' forms are test oracles
    from oracles.book_run import run_book_oracle

    scene = stand.load(SAMPLE)
    run_book(scene)                                   # compile outside the timing
    t_c, fast = best_of(lambda: run_book(scene), repeats)
    t_p, slow = best_of(lambda: run_book_oracle(scene), max(1, repeats // 3))
    p = scene.structure.params
    errs = {}
    for name, r in (("python", slow), ("compiled", fast)):
        Z = runup_closed_form(p, r.t)
        errs[name] = float(np.max(np.abs(r.x + 1j * r.y - Z)) / np.max(np.abs(Z)))
    return {"python_s": t_p, "compiled_s": t_c, "ratio": t_p / t_c,
            "tolerance": TOL_RTOL * scene.run.rtol,
            "python_nfev": int(slow.stats.nfev), "compiled_nfev": int(fast.stats.nfev),
            "python_error": errs["python"], "compiled_error": errs["compiled"]}


def per_weight_cost(counts=(1, 2, 4, 8, 16, 32), calls: int = 200_000) -> list:
    from stand._jit import njit
    from stand.model.rotors.bodies import PlaneBody, TiltingWeight
    from stand.integrate.coupled import build_model, initial_state
    from stand.model.rotors.coupled_kernel import rhs_generic
    from stand.model.rotors.planar_supports import planar_rotor

    @njit(_nrt=False)   # as the DOP853 loop calls it: no reference counts on the views
    def loop(n, y, dy, sp, wt, prog):
        s = 0.0
        for i in range(n):
            rhs_generic(1e-3 * i, y, dy, sp, wt, prog)
            s += dy[-1]
        return s

    rows = []
    rotor = planar_rotor(3.0, 3e4, 3e4, 20.0, 20.0, unbalance=6e-4)
    for k in counts:
        bodies = tuple(PlaneBody("balancer", TiltingWeight(
            "two_axis_pendulum", 0.05, 0.03, 1e-4, 6e-5, 1e-4, 1e-4, 9.81,
            initial_tilt=0.1, initial_angle=2 * np.pi * j / k)) for j in range(k))
        m = build_model(rotor, (), [[0.0, 100.0]], None, bodies)
        y = initial_state(m, ())
        dy = np.zeros_like(y)
        loop(10, y, dy, m.sp, m.wt, m.prog)
        t, _ = best_of(lambda: loop(calls, y, dy, m.sp, m.wt, m.prog), 3)
        rows.append({"weights": k, "us_per_call": t / calls * 1e6,
                     "us_per_call_per_weight": t / calls * 1e6 / k})
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args(argv)
    lf = liquid_float(a.repeats)
    print(f"(a) liquid float sample ({SAMPLE.name}), error against paper 001's closed form")
    print("| path | wall [s] | RHS evaluations | max rel. error |")
    print("|---|---|---|---|")
    peers = {}
    for key, label in (("python", "book RHS in Python + solve_ivp DOP853"),
                       ("compiled", "generic composition, compiled DOP853")):
        peers[key] = check_peer(label, lf[f"{key}_error"], lf["tolerance"])
        (wall,) = peers[key].cells(f"{lf[f'{key}_s']:.3f}")
        print(f"| {label} | {wall} | {lf[f'{key}_nfev']} | {lf[f'{key}_error']:.2e} |")
    if all(p.valid for p in peers.values()):
        eq = "equal or better" if lf["compiled_error"] <= 1.5 * lf["python_error"] else "WORSE"
        print(f"ratio: compiled is {lf['ratio']:.0f}x faster at {eq} accuracy (target >= 50x)\n")
    else:
        print(f"ratio: not computed (a path's error exceeds {lf['tolerance']:.2g})\n")
    rows = per_weight_cost()
    print("(b) compiled right-hand side, planar rotor + k two-axis pendulums")
    print("| k | us / call | us / call / weight |")
    print("|---|---|---|")
    for r in rows:
        print(f"| {r['weights']} | {r['us_per_call']:.3f} | {r['us_per_call_per_weight']:.4f} |")
    lin = rows[-1]["us_per_call"] / rows[-2]["us_per_call"]
    print(f"cost({rows[-1]['weights']}) / cost({rows[-2]['weights']}) = {lin:.2f} "
          "(2.0 for linear cost)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
