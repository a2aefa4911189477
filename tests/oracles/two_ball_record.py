"""An independent lab recording of the ball autobalancer stand (reference for ``stand fit``).

Written from the physics digest (/work/shared/physics/ch5_multiball.md, the corrected
(5.4), (5.7) of sections 0.2 and 2.1), not from the stand's simulator: no import of
``stand``, its own equations, its own prescribed rotor angle, scipy's ``solve_ivp``.

Model (SI, fixed right-handed axes X, Y; the rotor turns from +X towards +Y)
---------------------------------------------------------------------------
Shaft point K at (x, y); the rotor (mass M, every rotating part but the balls) has its
centre of mass at K + e (cos Phi, sin Phi), Phi = phi + beta, phi the angle of the
rotor's reference mark (prescribed), beta the unbalance angle from that mark; ball j
(mass m_j, a point) at K + l_j (cos psi_j, sin psi_j), psi_j its absolute angle,
alpha_j = psi_j - phi its angle relative to the rotor.  Linear supports
F = -(c_x x + H_x x', c_y y + H_y y').  With q = (x, y, psi_1 .. psi_n), the Lagrange
equations of T = M |r_C'|^2 / 2 + sum m_j |r_j'|^2 / 2 + sum k_j m_j l_j^2 alpha_j'^2 / 2
(k_j = 0 for sliding point balls; k = 2/5 for a ball rolling on a track of radius
l_j + r, small r: its spin relative to the rotor is -(l/r) alpha', so its spin energy is
(2/5) m r^2 (l/r)^2 alpha'^2 / 2 up to terms of order r/l and a rotor-driven term
in phi' only) give the symmetric mass-matrix system ``A(q) q'' = f(q, q', t)``::

    M_S x'' - sum m_j l_j sin psi_j psi_j''
        = c_x-force + sum m_j l_j psi_j'^2 cos psi_j + M e (phi'' sin Phi + phi'^2 cos Phi)
    M_S y'' + sum m_j l_j cos psi_j psi_j''
        = c_y-force + sum m_j l_j psi_j'^2 sin psi_j + M e (phi'^2 sin Phi - phi'' cos Phi)
    -m_j l_j sin psi_j x'' + m_j l_j cos psi_j y'' + (1 + k_j) m_j l_j^2 psi_j''
        = k_j m_j l_j^2 phi'' - c_b l_j^2 (psi_j' - phi')
          - mu m_j l_j psi_j'^2 l_j sat((psi_j' - phi') / v_s)

(M_S = M + sum m_j; c-force = -c x - H x'; sat(u) = u / sqrt(1 + u^2), the kinetic
rolling friction of stand/model/balancers/friction.py's docstring with the normal force
m_j l_j psi_j'^2 of a vertical rotor).  The first two rows are the corrected (5.7), the
ball rows (5.4) with J_j = m_j l_j^2 and the drag moment c_b l_j^2 (digest section 1).
The system is solved as it stands at every call (Gaussian elimination with partial
pivoting on plain floats, :mod:`oracles._dense`).

Note on ``rolling``: the stand's ``rolling = true`` (stand/scene/tables.py) multiplies the
ball's inertia, J = (7/5) m l^2 on psi_j'' (the digest's j = 5/7), which has no
k m l^2 phi'' term; here the spin inertia acts on the *relative* acceleration (the ball
rolls on the rotor's track).  The two agree at constant speed and differ on a ramp.

Speed drive: a piecewise-linear programme [[t s, rev/s], ...] (held before the first
node and after the last), phi(0) = 0, phi, phi', phi'' in closed form; the integration
runs segment by segment between the nodes so that no step straddles a kink of phi'.

Keyphasor: a TTL pulse (0/5 V) while the mark is within ``kp_width_deg`` past the sensor:
high when (phi - mark_angle) mod 2 pi < width.  ``mark_angle`` is the rotor angle at which
the mark faces the sensor (the stand's ``[instruments.keyphasor] mark_angle``): the
leading edge fires at phi = mark_angle + 2 pi k, so a recording reader that counts the
rotor angle from the pulses measures phi - mark_angle, and the unbalance angle it sees
from its mark is beta + mark_angle (the ball angles likewise alpha_j + mark_angle).  The
truth JSON gives the angles in that frame (the mark's), which equals the scene frame for
the default mark_angle = 0.
"""
from __future__ import annotations

import bisect
import json
import math
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from oracles._dense import solve

__all__ = ["StandParams", "SpeedProgramme", "Record", "UNIVERSAL", "simulate", "record",
           "write_record", "template_scene", "whirl_radius", "scene_text", "family_scene_text",
           "universal_record"]

TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0


# ---------------------------------------------------------------- parameters
@dataclass(frozen=True)
class StandParams:
    """The stand's true parameters, SI (angles in degrees, as in a scene file).

    ``stiffness_y`` / ``damping_y`` None: isotropic.  Per-ball values may be one number
    or a tuple of ``count``.  ``friction``: kinetic rolling-friction coefficient mu
    (0: none), ``slip_speed`` v_s [rad/s].  ``rolling``: spin inertia factor k of the
    ball relative to the rotor (False/0: point balls; True: 2/5).
    """

    mass: float = 4.45                     # kg, M (all rotating parts except the balls)
    eccentricity: float = 8.0899e-4        # m
    unbalance_angle: float = 0.0           # deg from the reference mark
    stiffness_x: float = 1613.09           # N/m
    stiffness_y: float | None = None
    damping_x: float = 8.5577              # N s/m
    damping_y: float | None = None
    count: int = 2
    ball_mass: float | tuple = 0.045       # kg
    radius: float | tuple = 0.08           # m, track radius (ball centre)
    drag: float | tuple = 0.16965          # N s/m on the ball's speed along the track
    initial_angles: tuple = (150.0, 210.0)  # deg relative to the reference mark
    initial_speeds: tuple | None = None    # rad/s relative to the rotor (default 0)
    friction: float = 0.0                  # mu, kinetic (= static)
    slip_speed: float = 0.02               # rad/s
    rolling: float | bool = False

    def per_ball(self, v) -> np.ndarray:
        a = np.atleast_1d(np.asarray(v, float))
        if a.size == 1:
            a = np.full(self.count, float(a[0]))
        if a.size != self.count:
            raise ValueError(f"{a.size} values for {self.count} balls")
        return a

    @property
    def cx(self):
        return float(self.stiffness_x)

    @property
    def cy(self):
        return float(self.stiffness_x if self.stiffness_y is None else self.stiffness_y)

    @property
    def hx(self):
        return float(self.damping_x)

    @property
    def hy(self):
        return float(self.damping_x if self.damping_y is None else self.damping_y)

    @property
    def m(self):
        return self.per_ball(self.ball_mass)

    @property
    def l(self):
        return self.per_ball(self.radius)

    @property
    def cb(self):
        return self.per_ball(self.drag)

    @property
    def k_spin(self) -> float:
        return 0.4 if self.rolling is True else float(self.rolling or 0.0)

    @property
    def total_mass(self) -> float:
        return self.mass + float(self.m.sum()) if self.count else self.mass

    @property
    def capacity(self) -> float:
        """S = sum m_j l_j [kg m]."""
        return float((self.m * self.l).sum()) if self.count else 0.0

    @property
    def f0_hz(self) -> float:
        return math.sqrt(self.cx / self.total_mass) / TWO_PI


UNIVERSAL = StandParams()  #: data_samples/scenes/ball_runup.toml (universal stand, 0.5 S)


class SpeedProgramme:
    """Piecewise-linear rotor speed [[t s, rev/s], ...], held before the first node and
    after the last; phi(0) = 0.  ``kin(t)`` -> (phi, phi', phi'') [rad, rad/s, rad/s^2],
    in closed form, for scalar or array t."""

    def __init__(self, nodes):
        nodes = np.asarray(nodes, float).reshape(-1, 2)
        if nodes.shape[0] < 1 or np.any(np.diff(nodes[:, 0]) <= 0) or nodes[0, 0] < 0:
            raise ValueError("programme: times >= 0, strictly increasing")
        self.nodes = nodes
        self.t = nodes[:, 0].copy()
        self.w = TWO_PI * nodes[:, 1]
        k = len(self.t)
        self.a = np.zeros(k)                        # acceleration on [t_i, t_{i+1})
        self.a[:-1] = np.diff(self.w) / np.diff(self.t)
        # phi at each node: held speed w_0 before the first node
        self.phi = np.empty(k)
        self.phi[0] = self.w[0] * self.t[0]
        for i in range(k - 1):
            d = self.t[i + 1] - self.t[i]
            self.phi[i + 1] = self.phi[i] + self.w[i] * d + 0.5 * self.a[i] * d * d
        self._lists = (self.t.tolist(), self.w.tolist(), self.a.tolist(), self.phi.tolist())

    def kin(self, t):
        t = np.asarray(t, float)
        i = np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, len(self.t) - 1)
        before = t < self.t[0]
        d = np.where(before, t - self.t[0], t - self.t[i])
        a = np.where(before, 0.0, self.a[i])
        w = self.w[i] + a * d
        phi = self.phi[i] + self.w[i] * d + 0.5 * a * d * d
        return phi, w, a

    def kin1(self, t: float):
        """:meth:`kin` at one time, in Python floats (the same operations, the same values;
        the right-hand side's per-call cost)."""
        tl = self._lists
        i = min(max(bisect.bisect_right(tl[0], t) - 1, 0), len(tl[0]) - 1)
        if t < tl[0][0]:
            d, a = t - tl[0][0], 0.0
        else:
            d, a = t - tl[0][i], tl[2][i]
        return tl[3][i] + tl[1][i] * d + 0.5 * a * d * d, tl[1][i] + a * d, a

    def kinks(self, t0, t1):
        """The nodes strictly inside (t0, t1)."""
        return [float(s) for s in self.t if t0 < s < t1]

    @property
    def top_speed_hz(self) -> float:
        return float(np.max(self.nodes[:, 1]))


# ---------------------------------------------------------------- equations of motion
def _sat(u):
    return u / math.sqrt(1.0 + u * u)


def make_rhs(p: StandParams, prog: SpeedProgramme):
    """``f(t, s)`` of the state s = (x, y, psi_1..psi_n, x', y', psi_1'..psi_n')."""
    n = p.count
    nq = n + 2
    M, e, beta = p.mass, p.eccentricity, p.unbalance_angle * DEG
    Ms = p.total_mass
    cx, cy, hx, hy = p.cx, p.cy, p.hx, p.hy
    if n:
        m, l, cb = p.m, p.l, p.cb
        ml, ml2 = m * l, m * l * l
        k = p.k_spin
    mu, vs = float(p.friction), float(p.slip_speed)
    if n:                              # per-ball values as Python floats
        ml, ml2, cbl2 = (ml.tolist(), ml2.tolist(), (cb * l * l).tolist())
        diag = [(1.0 + k) * v for v in ml2]

    def rhs(t, s):      # plain floats (~5x cheaper than numpy at this size)
        s = s.tolist()
        x, y, vx, vy = s[0], s[1], s[nq], s[nq + 1]
        ph, w, acc = prog.kin1(float(t))
        P = ph + beta
        sP, cP = math.sin(P), math.cos(P)
        A = [[0.0] * nq for _ in range(nq)]    # the mass matrix
        A[0][0] = A[1][1] = Ms
        f = [0.0] * nq
        f0 = -cx * x - hx * vx + M * e * (acc * sP + w * w * cP)
        f1 = -cy * y - hy * vy + M * e * (w * w * sP - acc * cP)
        for j in range(n):
            psi, dpsi = s[2 + j], s[nq + 2 + j]
            s_, c_ = math.sin(psi), math.cos(psi)
            A[0][2 + j] = A[2 + j][0] = -ml[j] * s_
            A[1][2 + j] = A[2 + j][1] = ml[j] * c_
            A[2 + j][2 + j] = diag[j]
            f0 += ml[j] * dpsi * dpsi * c_
            f1 += ml[j] * dpsi * dpsi * s_
            rel = dpsi - w
            fb = k * ml2[j] * acc - cbl2[j] * rel
            if mu:
                fb = fb - mu * ml2[j] * dpsi * dpsi * _sat(rel / vs)
            f[2 + j] = fb
        f[0], f[1] = f0, f1
        return np.array(s[nq:] + solve(A, f))

    return rhs


def simulate(p: StandParams = UNIVERSAL, programme=((0.0, 0.0), (10.0, 15.0)), *,
             t_eval, method="DOP853", rtol=1e-10, atol_m=1e-14, atol_rad=1e-12,
             max_step=None, x0=(0.0, 0.0), v0=(0.0, 0.0)) -> dict:
    """Integrate from t = 0 (shaft at ``x0`` with velocity ``v0``, balls at their initial
    angles relative to the rotor with their initial relative speeds) and sample at the
    increasing times ``t_eval`` (>= 0).  Segment by segment between the programme's nodes.

    Returns dict(t, x, y [m], vx, vy [m/s], phi [rad], omega [rad/s], psi (n, N) absolute
    ball angles [rad], alpha (n, N) relative to the rotor [rad], dpsi (n, N) [rad/s],
    nfev, wall [s])."""
    prog = programme if isinstance(programme, SpeedProgramme) else SpeedProgramme(programme)
    n = p.count
    nq = n + 2
    t_eval = np.asarray(t_eval, float)
    T = float(t_eval[-1])
    ph0, w0, _ = prog.kin(0.0)
    alpha0 = p.per_ball(p.initial_angles) * DEG if n else np.zeros(0)
    dal0 = (p.per_ball(p.initial_speeds) if (n and p.initial_speeds is not None)
            else np.zeros(n))
    s = np.concatenate(([x0[0], x0[1]], float(ph0) + alpha0, [v0[0], v0[1]], float(w0) + dal0))
    atol = np.concatenate(([atol_m] * 2, [atol_rad] * n, [atol_m * 100.0] * 2,
                           [atol_rad * 100.0] * n))
    if max_step is None:  # a quarter of a revolution at the top speed, or of the natural period
        top = max(prog.top_speed_hz, p.f0_hz * math.sqrt(max(p.cy, p.cx) / p.cx))
        max_step = 0.25 / top
    rhs = make_rhs(p, prog)
    edges = [0.0] + prog.kinks(0.0, T) + [T]
    Y = np.empty((2 * nq, t_eval.size))
    nfev, t_start = 0, time.perf_counter()
    for a, b in zip(edges[:-1], edges[1:]):
        last = b == T
        sel = (t_eval >= a) & ((t_eval <= b) if last else (t_eval < b))
        if b > a:
            sol = solve_ivp(rhs, (a, b), s, method=method, rtol=rtol, atol=atol,
                            max_step=max_step, dense_output=True)
            if not sol.success:
                raise RuntimeError(f"solve_ivp on [{a}, {b}] s: {sol.message}")
            nfev += sol.nfev
            if sel.any():
                Y[:, sel] = sol.sol(t_eval[sel])
            s = sol.y[:, -1]
        elif sel.any():
            Y[:, sel] = s[:, None]
    phi, w, _ = prog.kin(t_eval)
    psi, dpsi = Y[2:nq], Y[nq + 2:]
    return dict(t=t_eval, x=Y[0], y=Y[1], vx=Y[nq], vy=Y[nq + 1], phi=phi, omega=w,
                psi=psi, alpha=psi - phi, dpsi=dpsi, nfev=nfev,
                wall=time.perf_counter() - t_start)


def whirl_radius(sim: dict, t_from: float) -> float:
    """Mean radius |x + i y| of the whirl from ``t_from`` on [m] (the truth, no noise)."""
    sel = sim["t"] >= t_from
    return float(np.mean(np.hypot(sim["x"][sel], sim["y"][sel])))


# ---------------------------------------------------------------- the recording
@dataclass
class Record:
    """A sampled recording with its truth.

    t [s]; x_true, y_true [m] (the motion); x, y [m] (with probe noise); kp [V];
    phi [rad], omega [rad/s] (the prescribed rotor); alpha (n, N) [rad] ball angles
    relative to the rotor (reference mark); params, programme, settings (dict)."""

    t: np.ndarray
    x_true: np.ndarray
    y_true: np.ndarray
    x: np.ndarray
    y: np.ndarray
    kp: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    params: StandParams
    programme: np.ndarray
    settings: dict = field(default_factory=dict)

    def truth(self) -> dict:
        """The true parameters in scene units, angles from the keyphasor's mark."""
        p, st = self.params, self.settings
        mark = st["mark_angle_deg"]
        iso = p.stiffness_y is None and p.damping_y is None
        d = {
            "model": "planar rotor, fixed frame, prescribed speed, n point balls "
                     "(tests/oracles/two_ball_record.py; digest ch5 (5.4), (5.7) corrected)",
            "mass": p.mass, "total_mass": p.total_mass,
            "eccentricity": p.eccentricity,
            "unbalance_angle": (p.unbalance_angle + mark) % 360.0,
            "unbalance_angle_scene": p.unbalance_angle,
            "stiffness_x": p.cx, "stiffness_y": p.cy,
            "damping_x": p.hx, "damping_y": p.hy,
            "balancer": {"type": "balls", "count": p.count,
                         "mass": p.m.tolist(), "radius": p.l.tolist(), "drag": p.cb.tolist(),
                         "initial_angles": [((a + mark) % 360.0) for a in
                                            p.per_ball(p.initial_angles).tolist()],
                         "initial_angles_scene": p.per_ball(p.initial_angles).tolist(),
                         "friction": p.friction, "slip_speed": p.slip_speed,
                         "rolling_spin_factor": p.k_spin},
            "natural_frequency_hz": p.f0_hz,
            "damping_ratio": p.hx / (2.0 * math.sqrt(p.cx * p.total_mass)),
            "unbalance_gmm": p.mass * p.eccentricity * 1e6,
            "capacity_gmm": p.capacity * 1e6,
            "e0": p.mass * p.eccentricity / p.capacity if p.capacity else None,
            "programme": self.programme.tolist(),
            "units": {"stiffness": "N/m", "damping": "N s/m", "eccentricity": "m",
                      "unbalance_angle": "deg from the keyphasor mark, in the direction of "
                                         "rotation", "mass": "kg", "radius": "m",
                      "drag": "N s/m", "programme": "[s, rev/s]"},
            **{k: v for k, v in st.items()},
        }
        if iso:
            d["stiffness"], d["damping"] = p.cx, p.hx
        return d


def record(p: StandParams = UNIVERSAL, programme=((0.0, 0.0), (10.0, 15.0)), *,
           duration=25.0, fs=1000.0, noise_m=2e-6, seed=0, mark_angle_deg=0.0,
           kp_width_deg=30.0, kp_high_v=5.0, kp_noise_v=0.02, **sim_kw) -> Record:
    """Sample the stand at ``fs`` [Hz] over [0, duration] and add the probes' Gaussian noise
    (``noise_m`` std on x and y, numpy Generator seeded ``seed``) and a TTL keyphasor.
    ``sim_kw`` go to :func:`simulate` (method, rtol, ...)."""
    t = np.arange(int(round(duration * fs)) + 1) / fs
    sim = simulate(p, programme, t_eval=t, **sim_kw)
    rng = np.random.default_rng(seed)
    nx = noise_m * rng.standard_normal(t.size)
    ny = noise_m * rng.standard_normal(t.size)
    u = np.mod(sim["phi"] - mark_angle_deg * DEG, TWO_PI)
    kp = np.where(u < kp_width_deg * DEG, kp_high_v, 0.0) + kp_noise_v * rng.standard_normal(t.size)
    settings = dict(duration_s=float(t[-1]), sample_rate_hz=fs, noise_std_m=noise_m, seed=seed,
                    mark_angle_deg=mark_angle_deg, keyphasor_width_deg=kp_width_deg,
                    keyphasor_high_v=kp_high_v, keyphasor_noise_v=kp_noise_v,
                    integrator=sim_kw.get("method", "DOP853"),
                    rtol=sim_kw.get("rtol", 1e-10), nfev=sim["nfev"],
                    wall_time_s=round(sim["wall"], 3))
    return Record(t, sim["x"], sim["y"], sim["x"] + nx, sim["y"] + ny, kp, sim["phi"],
                  sim["omega"], sim["alpha"], p, np.asarray(
                      programme.nodes if isinstance(programme, SpeedProgramme) else programme,
                      float).reshape(-1, 2), settings)


def write_record(rec: Record, path) -> tuple:
    """``path`` (.csv: time_s, x_um, y_um, kp_V), its map ``.map.toml`` and the truth
    ``.truth.json`` beside it; returns the three paths."""
    path = Path(path)
    data = np.column_stack((rec.t, rec.x * 1e6, rec.y * 1e6, rec.kp))
    np.savetxt(path, data, delimiter=",", fmt="%.10g", header="time_s,x_um,y_um,kp_V",
               comments="")
    stem = path.with_suffix("")
    m = stem.with_name(stem.name + ".map.toml")
    top_rpm = float(np.max(rec.programme[:, 1])) * 60.0
    m.write_text("# Recording map of an oracle record (tests/oracles/two_ball_record.py)\n"
                 '[columns]\ntime = "time_s [s]"\nx = "x_um [um]"\ny = "y_um [um]"\n'
                 'keyphasor = "kp_V [V]"\n\n[rotor]\n'
                 f'mass = "{rec.params.total_mass:.10g} kg"   # all vibrating mass, balls included\n'
                 f'service_speed = "{top_rpm:.10g} rpm"\n')
    tj = stem.with_name(stem.name + ".truth.json")
    tj.write_text(json.dumps(rec.truth(), indent=2) + "\n")
    return path, m, tj


# ---------------------------------------------------------------- scenes
def _fmt_list(v):
    return "[" + ", ".join(f"{float(x):.10g}" for x in v) + "]"


def scene_text(truth: dict, *, stiffness=1.0, damping=1.0, eccentricity=1.0,
               unbalance_angle=0.0, drag=1.0, friction=1.0, name="oracle_two_ball",
               sample_rate=None, duration=None, rtol=None, atol=None) -> str:
    """A planar scene TOML (docs/scene.md) of ``truth`` (:meth:`Record.truth` or the JSON)
    with stiffness, damping, eccentricity, drag and friction multiplied by the given
    factors and ``unbalance_angle`` [deg] added.  Angles are the mark's (truth's
    ``unbalance_angle``/``initial_angles``), so the scene's rotor angle is the one a reader
    of the record's keyphasor counts."""
    b = truth["balancer"]
    iso = "stiffness" in truth
    lines = [f'[scene]\nname = "{name}"\n',
             "[rotor]", f"mass = {truth['mass']:.10g}",
             f"eccentricity = {truth['eccentricity'] * eccentricity:.10g}",
             f"unbalance_angle = {(truth['unbalance_angle'] + unbalance_angle) % 360.0:.10g}",
             "", "[supports]"]
    if iso:
        lines += [f"stiffness = {truth['stiffness'] * stiffness:.10g}",
                  f"damping = {truth['damping'] * damping:.10g}"]
    else:
        lines += [f"stiffness_x = {truth['stiffness_x'] * stiffness:.10g}",
                  f"stiffness_y = {truth['stiffness_y'] * stiffness:.10g}",
                  f"damping_x = {truth['damping_x'] * damping:.10g}",
                  f"damping_y = {truth['damping_y'] * damping:.10g}"]
    if b["count"]:
        lines += ["", "[balancer]", 'type = "balls"', f"count = {b['count']}",
                  f"mass = {_fmt_list(b['mass'])}", f"radius = {_fmt_list(b['radius'])}",
                  f"drag = {_fmt_list(np.asarray(b['drag']) * drag)}",
                  f"initial_angles = {_fmt_list(b['initial_angles'])}"]
        if b.get("friction", 0.0) > 0:
            lines.append(f"friction = {b['friction'] * friction:.10g}")
            if b.get("slip_speed", 0.02) != 0.02:
                lines.append(f"slip_speed = {b['slip_speed']:.10g}")
    return _drive_and_run(lines, truth, duration, sample_rate, rtol, atol, lambda v: f"{v:.10g}",
                          lambda v: f"{v:g}")


def family_scene_text(truth: dict, *, sample_rate=None, duration=None, rtol=None, atol=None,
                      name="oracle_two_ball_family") -> str:
    """The same stand as a rotor-family scene (``[structure] type = "planar"`` +
    ``[[weights]]``, stand/scene/structure_tables.py), which takes the balls' friction
    (``friction``, ``slip_speed``) and ``rolling`` today.  Angles: the truth's mark frame
    (every angle in degrees, scene language 2; the ``unbalance`` M e in kg m)."""
    b = truth["balancer"]
    lines = [f'[scene]\nname = "{name}"\n', "[structure]", 'type = "planar"',
             f"mass = {truth['mass']!r}",
             f"stiffness_x = {truth['stiffness_x']!r}", f"stiffness_y = {truth['stiffness_y']!r}",
             f"damping_x = {truth['damping_x']!r}", f"damping_y = {truth['damping_y']!r}",
             f"unbalance = {truth['mass'] * truth['eccentricity']!r}",
             f"unbalance_angle = {float(truth['unbalance_angle'])!r}"]
    if b["count"]:
        lines += ["", "[[weights]]", 'plane = "balancer"', 'type = "balls"',
                  f"count = {b['count']}", f"mass = {_fmt_list(b['mass'])}",
                  f"radius = {_fmt_list(b['radius'])}", f"drag = {_fmt_list(b['drag'])}",
                  f"initial_angles = {_fmt_list(b['initial_angles'])}"]
        if b.get("friction", 0.0) > 0:
            lines += [f"friction = {b['friction']!r}", f"slip_speed = {b['slip_speed']!r}"]
        if b.get("rolling_spin_factor", 0.0):
            if b["rolling_spin_factor"] != 0.4:
                raise ValueError("the stand's rolling balls have the spin factor 2/5 only")
            lines.append("rolling = true")
    return _drive_and_run(lines, truth, duration, sample_rate, rtol, atol, repr, repr)


def template_scene(truth, path, *, stiffness=1.12, damping=1.8, eccentricity=0.7,
                   unbalance_angle=35.0, drag=2.5, friction=1.0, **kw) -> Path:
    """Write the fit's starting scene: ``truth`` (a dict, or the path of a truth JSON) with
    stiffness x1.12, damping x1.8, eccentricity x0.7, unbalance angle +35 deg, drag x2.5
    (friction x1: pass ``friction=`` to perturb it).  Returns the path."""
    if not isinstance(truth, dict):
        truth = json.loads(Path(truth).read_text())
    path = Path(path)
    path.write_text(scene_text(truth, stiffness=stiffness, damping=damping,
                               eccentricity=eccentricity, unbalance_angle=unbalance_angle,
                               drag=drag, friction=friction, name=path.stem, **kw))
    return path


# ---------------------------------------------------------------- default case
def universal_record(friction=0.0, **kw) -> Record:
    """The default case: the universal stand (ball_runup.toml), 0 -> 15 rev/s in 10 s then
    held, 25 s at 1 kHz, 2 um noise, optionally with rolling friction ``friction``."""
    return record(replace(UNIVERSAL, friction=friction), ((0.0, 0.0), (10.0, 15.0)), **kw)


if __name__ == "__main__":   # python tests/oracles/two_ball_record.py OUTDIR [mu]
    import sys

    out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    mu = float(sys.argv[2]) if len(sys.argv) > 2 else 0.0
    t0 = time.perf_counter()
    rec = universal_record(friction=mu)
    print(f"generated in {time.perf_counter() - t0:.1f} s ({rec.settings['nfev']} calls)")
    sim = dict(t=rec.t, x=rec.x_true, y=rec.y_true)
    print(f"whirl radius (t >= 20 s): {whirl_radius(sim, 20.0) * 1e6:.3f} um")
    paths = write_record(rec, out / f"two_ball_mu{mu:g}.csv")
    template_scene(rec.truth(), out / f"two_ball_mu{mu:g}.template.toml")
    print(*paths, sep="\n")


def _drive_and_run(lines, truth, duration, sample_rate, rtol, atol, num, tol) -> str:
    """The scene's ``[drive]`` (the truth's speed programme) and ``[run]`` tables appended to
    ``lines``, numbers written by ``num`` (tolerances by ``tol``): the whole scene text."""
    prog = np.asarray(truth["programme"], float)
    lines += ["", "[drive]", 'type = "speed"',
              "programme = [" + ", ".join(f"[{num(float(a))}, {num(float(w))}]" for a, w in prog) + "]",
              "", "[run]",
              f"duration = {num(duration if duration is not None else truth['duration_s'])}",
              f"sample_rate = {num(sample_rate if sample_rate is not None else truth['sample_rate_hz'])}"]
    if rtol is not None:
        lines.append(f"rtol = {tol(rtol)}")
    if atol is not None:
        lines.append(f"atol = {tol(atol)}")
    return "\n".join(lines) + "\n"
