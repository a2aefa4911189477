"""Part (c) of ``bench_family.py``: a Jeffcott run-up in ROSS and in the stand.

The problem (:data:`PROBLEM`): a disk at mid-span of a very stiff two-element shaft on
two equal isotropic bearings (ROSS), and the same rotor as the stand's planar structure
without weights (mass = ROSS's whole rotor mass, stiffness and damping = the two
bearings' sums), run up at constant angular acceleration from rest through the critical
speed, with the unbalance force of a point mass ``U = m e`` on the disk::

    F = U (phi'^2 cos phi + phi'' sin phi,  phi'^2 sin phi - phi'' cos phi).

Each solver is measured against an exact answer of its *own* model, and the two models
against each other:

* ROSS (``rotor.run_time_response(speed_array, F, t)``: Newmark, average acceleration,
  one step per entry of ``t``) against scipy's DOP853 at rtol 1e-11 on ROSS's own matrices
  ``M q'' + (C + Omega G) q' + (K + Omega' Ksdt) q = F`` (what its Newmark integrates);
* the stand (:func:`stand.integrate.coupled.simulate_coupled`) against the closed
  complex Jeffcott equation of ``tests/oracles/runup_exact.py`` (scipy DOP853, rtol 1e-11);
* the two references against each other (the model gap: the shaft's own flexibility and
  mass distribution in ROSS).

ROSS pins ``plotly<6`` and pulls many packages, so it lives in its own interpreter: this
file is also the script run there (``python _family_ross.py --child PARAMS_JSON``; it
imports only ross, numpy and the standard library and prints its JSON after
:data:`MARK`, because ross prints REFPROP notices on stdout).  :func:`ross_python`
chooses the interpreter.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

MARK = "@@ROSS-JSON@@"
#: the problem: SI units; steps: ROSS's Newmark time steps [s] (the first: the sample grid)
PROBLEM = dict(
    shaft_length=0.4, shaft_diameter=0.05, rho=7810.0, E=2.11e12, G_s=8.12e11,  # 10 x steel
    disk_mass=10.0, disk_Id=0.05, disk_Ip=0.1,
    # small disks at the bearings' nodes: their tilt inertia keeps the highest lateral mode at
    # 3.5e4 rad/s, so that the explicit DOP853 reference is stable at a useful step
    end_mass=0.1, end_Id=0.05, end_Ip=0.1,
    kb=1.1e5, cb=50.0,                 # each bearing [N/m], [N s/m]
    unbalance=1.0e-3,                  # U = m e [kg m]
    rate=20.0, duration=2.0,           # constant acceleration [rev/s^2] from rest, [s]
    sample_rate=1000.0,                # [Hz]: samples compared; Newmark's default step
    steps=[1e-3, 2.5e-4, 1e-4, 2.5e-5, 1e-5],
)


def ross_python():
    """The interpreter that imports ross: ``$ROSS_PYTHON``, else ``/opt/rossenv/bin/python``
    when it exists, else this one when it imports ross; ``None`` when none does."""
    env = os.environ.get("ROSS_PYTHON", "").strip()
    if env:
        return env
    if Path("/opt/rossenv/bin/python").exists():
        return "/opt/rossenv/bin/python"
    import importlib.util

    return sys.executable if importlib.util.find_spec("ross") else None


def kinematics(t, rate):
    """Rotor angle [rad], speed [rad/s], acceleration [rad/s^2] of the run-up from rest at
    ``rate`` rev/s^2."""
    a = 2.0 * math.pi * rate
    t = np.asarray(t, float)
    return 0.5 * a * t * t, a * t, np.full_like(t, a)


def unbalance_force(t, U, rate):
    """(k, 2) unbalance force [N] (module docstring) at times ``t``."""
    phi, w, a = kinematics(t, rate)
    c, s = np.cos(phi), np.sin(phi)
    return U * np.stack([w * w * c + a * s, w * w * s - a * c], axis=1)


def sample_times(p):
    return np.arange(0.0, p["duration"] + 0.5 / p["sample_rate"], 1.0 / p["sample_rate"])


# ------------------------------------------------------------------ in ROSS's interpreter
def child(p: dict) -> dict:
    """Assemble the rotor in ROSS, run its time response at each Newmark step of
    ``p["steps"]``; the disk's (x, y) at the sample times, wall times and the matrices."""
    import contextlib
    import io

    t0 = time.perf_counter()
    import ross as rs
    t_import = time.perf_counter() - t0

    t0 = time.perf_counter()
    mat = rs.Material(name="stiff_steel", rho=p["rho"], E=p["E"], G_s=p["G_s"])
    half = 0.5 * p["shaft_length"]
    shaft = [rs.ShaftElement(L=half, idl=0.0, odl=p["shaft_diameter"], material=mat,
                             shear_effects=True, rotary_inertia=True, gyroscopic=True)
             for _ in range(2)]
    disks = [rs.DiskElement(n=1, m=p["disk_mass"], Id=p["disk_Id"], Ip=p["disk_Ip"])]
    disks += [rs.DiskElement(n=k, m=p["end_mass"], Id=p["end_Id"], Ip=p["end_Ip"]) for k in (0, 2)]
    brg = [rs.BearingElement(n=k, kxx=p["kb"], kyy=p["kb"], cxx=p["cb"], cyy=p["cb"])
           for k in (0, 2)]
    rotor = rs.Rotor(shaft, disks, brg)
    t_assembly = time.perf_counter() - t0
    nd = rotor.number_dof
    ix, iy = nd * 1, nd * 1 + 1
    ts = sample_times(p)
    runs = []
    with contextlib.redirect_stdout(io.StringIO()):   # compile Newmark's numba part: untimed
        rotor.run_time_response(np.zeros(3), np.zeros((3, rotor.ndof)), np.arange(3) * 1e-3)
    for dt in p["steps"]:
        every = int(round(1.0 / (p["sample_rate"] * dt)))
        t = np.arange(ts.size * every - every + 1) * (1.0 / (p["sample_rate"] * every))
        F = np.zeros((t.size, rotor.ndof))
        F[:, [ix, iy]] = unbalance_force(t, p["unbalance"], p["rate"])
        speed = kinematics(t, p["rate"])[1]
        wall = math.inf
        for _ in range(2 if t.size < 50_000 else 1):       # best of two when short
            t0 = time.perf_counter()
            with contextlib.redirect_stdout(io.StringIO()):   # "Running direct method"
                res = rotor.run_time_response(speed, F, t)
            wall = min(wall, time.perf_counter() - t0)
        y = np.asarray(res.yout)[::every]
        runs.append(dict(dt=dt, steps=int(t.size - 1), wall=wall, x=y[:, ix].tolist(),
                         y=y[:, iy].tolist()))
    return dict(version=rs.__version__, import_s=t_import, assembly_s=t_assembly,
                mass=float(rotor.m), ndof=int(rotor.ndof), number_dof=int(nd), ix=ix, iy=iy,
                M=rotor.M().tolist(), K=rotor.K(0.0).tolist(), C=rotor.C(0.0).tolist(),
                G=rotor.G().tolist(), Ksdt=rotor.Ksdt().tolist(), runs=runs)


# ------------------------------------------------------------------ in the stand's interpreter
def run_child(python: str, p: dict, timeout: float = 600.0) -> dict:
    """Run :func:`child` in ``python``; its JSON answer (RuntimeError with its stderr tail)."""
    proc = subprocess.run([python, str(Path(__file__).resolve()), "--child", json.dumps(p)],
                          capture_output=True, text=True, timeout=timeout)
    out = proc.stdout
    if proc.returncode != 0 or MARK not in out:
        tail = "\n".join(proc.stderr.strip().splitlines()[-5:])
        raise RuntimeError(f"{python} exited {proc.returncode}: {tail}")
    return json.loads(out.split(MARK, 1)[1])


def ross_reference(data: dict, p: dict, rtol=1e-11):
    """ROSS's own equations (its M, C, G, K, Ksdt) under the same forcing, scipy DOP853 (the
    force's jump at t = 0 rings the stiff modes: an implicit method must resolve that ringing
    too, and scipy's Radau took minutes):
    the disk's (k, 2) displacement [m] at the sample times."""
    from scipy.integrate import solve_ivp

    M, K, C, G, Ks = (np.array(data[k]) for k in ("M", "K", "C", "G", "Ksdt"))
    nd = data["number_dof"]
    # the lateral dofs (x, y and the tilts); the axial and torsional ones are uncoupled
    # from them in every matrix (checked) and unforced: they stay zero
    lat = np.array([i for i in range(M.shape[0]) if nd != 6 or i % 6 in (0, 1, 3, 4)])
    rest = np.setdiff1d(np.arange(M.shape[0]), lat)
    for A in (M, K, C, G, Ks):
        if rest.size and (np.any(A[np.ix_(lat, rest)] != 0) or np.any(A[np.ix_(rest, lat)] != 0)):
            raise RuntimeError("ROSS reference: the axial/torsional dofs couple to the lateral ones")
    M, K, C, G, Ks = (A[np.ix_(lat, lat)] for A in (M, K, C, G, Ks))
    n = lat.size
    Mi = np.linalg.inv(M)
    ix, iy = (int(np.searchsorted(lat, data[k])) for k in ("ix", "iy"))
    a = 2.0 * math.pi * p["rate"]
    MC, MG, MK = Mi @ C, Mi @ G, Mi @ (K + a * Ks)
    ts = sample_times(p)
    fx, fy = Mi[:, ix], Mi[:, iy]

    def rhs(t, z):
        q, qd = z[:n], z[n:]
        f = unbalance_force(np.array([t]), p["unbalance"], p["rate"])[0]
        return np.concatenate([qd, f[0] * fx + f[1] * fy - MK @ q - (MC + a * t * MG) @ qd])

    U, m = p["unbalance"], data["mass"]
    xs = U / m            # the response's scale [m] (rad for the tilts: a 1 m lever)
    sol = solve_ivp(rhs, (0.0, ts[-1]), np.zeros(2 * n), method="DOP853", t_eval=ts,
                    rtol=rtol, atol=rtol * xs)
    if not sol.success:
        raise RuntimeError(f"ROSS reference: {sol.message}")
    return np.stack([sol.y[ix], sol.y[iy]], axis=1)


def equivalent(data: dict, p: dict) -> dict:
    """The stand's Jeffcott rotor equal to ROSS's at the disk: mass [kg], stiffness [N/m],
    damping [N s/m], natural frequency [Hz], damping ratio."""
    m, k, c = data["mass"], 2.0 * p["kb"], 2.0 * p["cb"]
    w0 = math.sqrt(k / m)
    return dict(mass=m, stiffness=k, damping=c, f0=w0 / (2 * math.pi), zeta=c / (2 * m * w0))


def stand_scene_text(eq: dict, p: dict) -> str:
    """The stand's scene of the same rotor (planar structure, no weights)."""
    top = p["rate"] * p["duration"]
    return f"""
[scene]
name = "jeffcott_runup_vs_ross"
[structure]
type = "planar"
mass = {eq['mass']!r}
stiffness_x = {eq['stiffness']!r}
stiffness_y = {eq['stiffness']!r}
damping_x = {eq['damping']!r}
damping_y = {eq['damping']!r}
unbalance = {p['unbalance']!r}
[drive]
type = "speed"
programme = [[0.0, 0.0], [{p['duration']!r}, {top!r}]]
[run]
duration = {p['duration']!r}
sample_rate = {p['sample_rate']!r}
"""


def stand_reference(eq: dict, p: dict) -> np.ndarray:
    """The closed Jeffcott equation (tests/oracles/runup_exact.py): (k, 2) [m]."""
    root = Path(__file__).resolve().parents[1]
    if str(root) not in sys.path:
        sys.path.insert(0, str(root))
    from tests.oracles.runup_exact import exact_runup

    ts = sample_times(p)
    span = ts[-1] + 0.5 / p["sample_rate"]   # the oracle samples [0, span): ts; its rate:
    ex = exact_runup(f0_hz=eq["f0"], zeta=eq["zeta"], e_m=p["unbalance"] / eq["mass"],  # f_end/span
                     beta_deg=0.0, mass_kg=eq["mass"], f_start_hz=0.0,
                     f_end_hz=p["rate"] * span, duration_s=span, fs_hz=p["sample_rate"])
    if ex.t.size != ts.size or not np.allclose(ex.t, ts, rtol=0, atol=1e-9):
        raise RuntimeError("the oracle's sample times differ from the benchmark's")
    return np.stack([ex.x, ex.y], axis=1)


def rel_error(z, ref) -> float:
    """max |z - ref| / max |ref| over the samples (both (k, 2)); inf when shapes differ."""
    z = np.asarray(z, float)
    if z.shape != ref.shape or not np.all(np.isfinite(z)):
        return math.inf
    return float(np.max(np.hypot(*(z - ref).T)) / np.max(np.hypot(*ref.T)))


def compare_ross(load, ours, p: dict = PROBLEM, repeats: int = 3) -> list:
    """Print part (c); return its rows ``(label, wall [s] or None, error, note)`` and a dict
    (model gap, ROSS's assembly time [s] and version; empty when ROSS was not run).

    ``load(text)`` -> scene and ``ours(scene, rtol, atol)`` -> CoupledRun are
    bench_family's own helpers."""
    python = ross_python()
    print("\n(c) ROSS: Jeffcott run-up through the critical speed")
    if python is None:
        print("  ROSS not installed: not evaluated")
        return [("ROSS", None, math.nan, "ROSS not installed: not evaluated")], {}
    try:
        data = run_child(python, p)
    except Exception as exc:  # noqa: BLE001 - said, not raised: ROSS is an optional peer
        print(f"  ROSS failed in {python}: {exc}: not evaluated")
        return [("ROSS", None, math.nan, f"failed: {exc}")], {}
    eq = equivalent(data, p)
    ref_ross = ross_reference(data, p)
    ref_stand = stand_reference(eq, p)
    scene = load(stand_scene_text(eq, p))
    from _peers import best_of

    ours(scene)                                        # warm-up
    t_st, r = best_of(lambda: ours(scene), repeats)
    q_tight = ours(scene, 1e-12, 1e-15).q
    print(f"  ROSS {data['version']} ({python}): disk of {p['disk_mass']} kg at mid-span of a "
          f"{p['shaft_length']} m shaft (E = {p['E']:.3g} Pa: 10 x steel), bearings "
          f"{p['kb']:.3g} N/m, {p['cb']:.3g} N s/m each; rotor mass {eq['mass']:.4f} kg")
    print(f"  the stand's equal rotor: planar, no weights: f0 = {eq['f0']:.3f} Hz, zeta = "
          f"{eq['zeta']:.4f}; U = {p['unbalance']:g} kg m; run-up from rest at {p['rate']:g} "
          f"rev/s^2 to {p['rate'] * p['duration']:g} rev/s in {p['duration']:g} s; "
          f"{p['sample_rate']:g} samples/s compared")
    print(f"  error = max|z - z_ref| / max|z_ref| of the disk's (x, y); import ross "
          f"{data['import_s']:.1f} s (not counted), model assembly {data['assembly_s'] * 1e3:.1f} ms")
    gap = rel_error(ref_ross, ref_stand)
    print(f"  model gap: ROSS's reference vs the Jeffcott reference: {gap:.2e}")
    print(f"  {'contender':<52} {'wall [ms]':>10} {'steps':>8} {'error vs own ref':>17} "
          f"{'vs other ref':>13}")
    rows = []
    for k, run in enumerate(data["runs"]):
        z = np.stack([run["x"], run["y"]], axis=1)
        label = (f"ROSS Newmark dt = {run['dt']:g} s" +
                 (" (default: the sample grid)" if k == 0 else ""))
        e, e2 = rel_error(z, ref_ross), rel_error(z, ref_stand)
        print(f"  {label:<52} {run['wall'] * 1e3:10.1f} {run['steps']:>8d} {e:>17.2e} {e2:>13.2e}")
        rows.append((label, run["wall"], e, ""))
    z = r.q
    e, e2 = rel_error(z, ref_stand), rel_error(z, ref_ross)
    label = "stand DOP853 (simulate_coupled, rtol 1e-9)"
    print(f"  {label:<52} {t_st * 1e3:10.1f} {r.stats['n_steps']:>8d} {e:>17.2e} {e2:>13.2e}")
    rows.append((label, t_st, e, ""))
    print(f"  check of the Jeffcott reference: stand at rtol 1e-12 vs it: "
          f"{rel_error(q_tight, ref_stand):.2e}")
    return rows, dict(gap=gap, assembly=data["assembly_s"], version=data["version"])


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--child":
        answer = child(json.loads(sys.argv[2]))
        sys.stdout.write("\n" + MARK + json.dumps(answer) + "\n")
    else:
        sys.exit("usage: _family_ross.py --child PARAMS_JSON (run by bench_family.py)")
