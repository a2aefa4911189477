"""An independent reference of the two-ball autobalancer stand (issue 39): its own equations of
motion, its own integrator call, its own keyphasor -- not the stand's simulator.

The planar rotor of chapter 5 (digest ch5 sections 0.2, 2.3: the corrected (5.4), (5.7),
(5.10)) written in SI in the fixed frame by Lagrange's equations and solved as the full
mass-matrix system ``A(q) q'' = f(q, q', t)`` by Gaussian elimination at every call (the
stand eliminates the balls by a Schur complement in dimensionless form).  Shaft point K at
(x, y) on supports (c_x, c_y; H_x, H_y), rotor mass M with its centre of mass at
K + e (cos(phi + beta), sin(phi + beta)), balls of mass m_j at K + l_j (cos psi_j, sin psi_j)::

    (M + sum m) x'' - sum m l (psi'' sin psi + psi'^2 cos psi)
        = -c_x x - H_x x' + M e (phi'' sin(phi + beta) + phi'^2 cos(phi + beta))
    (M + sum m) y'' + sum m l (psi'' cos psi - psi'^2 sin psi)
        = -c_y y - H_y y' + M e (phi'^2 sin(phi + beta) - phi'' cos(phi + beta))
    J_j psi_j'' - m l x'' sin psi_j + m l y'' cos psi_j
        = -c_b l^2 (psi_j' - phi') - mu N_j l sat((psi_j' - phi') / v_s)

with the ball's drag c_b on its speed along the track, N_j = m_j l_j psi_j'^2 the track's
normal force on a vertical rotor, sat(u) = u / sqrt(1 + u^2) (rolling resistance, the
regularised Coulomb law of stand.model.balancers.friction's docstring: the same physics, not
its code) and J_j = m_j l_j^2 (point balls).  The rotor angle phi(t) is prescribed by a
piecewise-linear speed programme ``[[t s, speed rev/s], ...]`` (held after the last node,
phi(0) = 0), in closed form.  Integrated by scipy's solve_ivp between the programme's nodes.
"""
from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from oracles._dense import solve

TWO_PI = 2.0 * math.pi


@dataclass
class Stand:
    """The stand's values in the scene file's units (angles in degrees)."""

    mass: float = 4.45                 # kg, rotor without the balls
    eccentricity: float = 8.0899e-4    # m
    unbalance_angle: float = 0.0       # deg from the keyphasor mark
    stiffness: float = 1613.09         # N/m (both axes)
    damping: float = 8.5577            # N s/m (both axes)
    ball_mass: float = 0.045           # kg
    radius: float = 0.08               # m
    count: int = 2
    drag: float = 0.16965              # N s/m
    friction: float = 0.0              # rolling resistance mu (dimensionless)
    slip_speed: float = 0.02           # rad/s
    initial_angles: list = field(default_factory=lambda: [150.0, 210.0])   # deg
    programme: list = field(default_factory=lambda: [[0.0, 0.0], [10.0, 15.0]])  # [s, rev/s]


def kinematics(prog, t):
    """phi, phi', phi'' [rad, rad/s, rad/s^2] of the piecewise-linear speed programme."""
    T = [float(p[0]) for p in prog]
    W = [TWO_PI * float(p[1]) for p in prog]
    t = float(t)
    if t < T[0]:
        return W[0] * t, W[0], 0.0
    phi = W[0] * T[0]
    for k in range(len(T) - 1):
        a = (W[k + 1] - W[k]) / (T[k + 1] - T[k])
        if t < T[k + 1]:
            d = t - T[k]
            return phi + W[k] * d + 0.5 * a * d * d, W[k] + a * d, a
        phi += 0.5 * (W[k] + W[k + 1]) * (T[k + 1] - T[k])
    return phi + W[-1] * (t - T[-1]), W[-1], 0.0


def rhs(s: Stand):
    """The right-hand side of the state (x, y, psi_1..n, x', y', psi_1'..n')."""
    n = s.count
    M, m, l = s.mass, s.ball_mass, s.radius
    Ms = M + n * m
    beta = math.radians(s.unbalance_angle)
    cb = s.drag * l * l

    def f(t, q):        # plain floats (~5x cheaper than numpy at this size)
        q = q.tolist()
        x, y = q[0], q[1]
        psi = q[2:2 + n]
        vx, vy = q[2 + n], q[3 + n]
        dpsi = q[4 + n:4 + 2 * n]
        phi, w, a = kinematics(s.programme, t)
        sp = [math.sin(v) for v in psi]
        cp = [math.cos(v) for v in psi]
        A = [[0.0] * (2 + n) for _ in range(2 + n)]
        b = [0.0] * (2 + n)
        A[0][0] = A[1][1] = Ms
        Me, sb, cbeta = M * s.eccentricity, math.sin(phi + beta), math.cos(phi + beta)
        b[0] = (-s.stiffness * x - s.damping * vx + m * l * sum(d * d * c for d, c in zip(dpsi, cp))
                + Me * (a * sb + w * w * cbeta))
        b[1] = (-s.stiffness * y - s.damping * vy + m * l * sum(d * d * v for d, v in zip(dpsi, sp))
                + Me * (w * w * sb - a * cbeta))
        for j in range(n):
            A[0][2 + j] = A[2 + j][0] = -m * l * sp[j]
            A[1][2 + j] = A[2 + j][1] = m * l * cp[j]
            A[2 + j][2 + j] = m * l * l
            rel = dpsi[j] - w
            b[2 + j] = -cb * rel
            if s.friction:
                u = rel / s.slip_speed
                b[2 + j] -= s.friction * m * l * dpsi[j] ** 2 * l * u / math.sqrt(1.0 + u * u)
        return np.array(q[2 + n:] + solve(A, b))

    return f


def simulate(s: Stand, t_eval, rtol: float = 1e-10):
    """(x, y, psi (N, n), phi) at ``t_eval`` [s], from rest, balls at their initial angles."""
    t_eval = np.asarray(t_eval, float)
    n = s.count
    q = np.zeros(4 + 2 * n)
    q[2:2 + n] = np.radians(s.initial_angles)
    f = rhs(s)
    nodes = sorted({0.0, float(t_eval[-1])} | {float(p[0]) for p in s.programme
                                              if 0.0 < p[0] < t_eval[-1]})
    out = np.empty((t_eval.size, q.size))
    method = "DOP853"          # the friction law is mildly stiff (~1e3 1/s): explicit is fine
    atol = np.concatenate([[1e-13, 1e-13], [1e-12] * n, [1e-11, 1e-11], [1e-10] * n])
    for a, b in zip(nodes[:-1], nodes[1:]):
        last = b == nodes[-1]
        sel = (t_eval >= a) & ((t_eval <= b) if last else (t_eval < b))
        te = np.concatenate([t_eval[sel], [b]])           # the segment's end state too
        sol = solve_ivp(f, (a, b), q, method=method, t_eval=np.unique(te), rtol=rtol, atol=atol)
        if not sol.success:
            raise RuntimeError(sol.message)
        out[sel] = sol.y[:, np.searchsorted(sol.t, t_eval[sel])].T
        q = sol.y[:, -1]
    phi = np.array([kinematics(s.programme, t)[0] for t in t_eval])
    return out[:, 0], out[:, 1], out[:, 2:2 + n], phi


def record(s: Stand, duration: float = 25.0, fs: float = 1000.0, noise_m: float = 2e-6,
           seed: int = 0, mark_width_deg: float = 30.0, kp_noise_v: float = 0.02):
    """A lab record: time, probe x, y [m] with Gaussian noise, a TTL keyphasor [V] high while
    the mark is within ``mark_width_deg`` past it (its leading edge at phi = 0 mod 2 pi)."""
    t = np.arange(int(round(duration * fs)) + 1) / fs
    x, y, psi, phi = simulate(s, t)
    rng = np.random.default_rng(seed)
    kp = (np.where(np.mod(phi, TWO_PI) < math.radians(mark_width_deg), 5.0, 0.0)
          + rng.normal(0.0, kp_noise_v, t.size))
    return dict(t=t, x=x + rng.normal(0.0, noise_m, t.size),
                y=y + rng.normal(0.0, noise_m, t.size), kp=kp, x_true=x, y_true=y, psi=psi,
                phi=phi)


def write_record(rec: dict, s: Stand, path) -> tuple:
    """The record as a DAQ-like CSV (time_s, x_um, y_um, kp_V), its map and the truth JSON;
    returns (csv, map) paths."""
    path = Path(path)
    np.savetxt(path, np.column_stack((rec["t"], rec["x"] * 1e6, rec["y"] * 1e6, rec["kp"])),
               delimiter=",", fmt="%.12g", header="time_s,x_um,y_um,kp_V", comments="")
    m = path.with_suffix(".map.toml")
    m.write_text('[columns]\ntime = "time_s [s]"\nx = "x_um [um]"\ny = "y_um [um]"\n'
                 'keyphasor = "kp_V [V]"\n\n[rotor]\n'
                 f'mass = "{s.mass + s.count * s.ball_mass} kg"\n')
    path.with_suffix(".truth.json").write_text(json.dumps(asdict(s), indent=1))
    return path, m


#: the values a template gets wrong, and how (issue 39's acceptance)
PERTURBED = {"stiffness": 1.12, "damping": 1.8, "eccentricity": 0.7, "unbalance_angle": 35.0,
             "drag": 2.5}


def template_scene(s: Stand, path, duration: float = 25.0, perturb=PERTURBED) -> Path:
    """The scene a lab would start from: ``s`` with the values of ``perturb`` scaled (an
    angle: shifted by degrees), in the planar scene form."""
    v = asdict(s)
    for k, f in (perturb or {}).items():
        v[k] = v[k] + f if k == "unbalance_angle" else v[k] * f
    fr = (f"friction = {v['friction']!r}\nslip_speed = {v['slip_speed']!r}\n"
          if v["friction"] else "")
    text = (f"[scene]\nname = \"two_ball_template\"\n\n[rotor]\nmass = {v['mass']!r}\n"
            f"eccentricity = {v['eccentricity']!r}\nunbalance_angle = {v['unbalance_angle']!r}\n\n"
            f"[supports]\nstiffness = {v['stiffness']!r}\ndamping = {v['damping']!r}\n\n"
            f"[balancer]\ntype = \"balls\"\ncount = {v['count']}\nmass = {v['ball_mass']!r}\n"
            f"radius = {v['radius']!r}\ndrag = {v['drag']!r}\n"
            f"initial_angles = {[float(a) for a in v['initial_angles']]}\n{fr}\n"
            f"[drive]\ntype = \"speed\"\nprogramme = {[[float(a), float(b)] for a, b in v['programme']]}\n\n"
            f"[run]\nduration = {duration!r}\nsample_rate = 200.0\n")
    path = Path(path)
    path.write_text(text)
    return path
