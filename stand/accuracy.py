"""Error against run time: a scene at a ladder of tolerances and methods.

Each run is compared with an exact solution where one exists (a rotor with no
weights at constant speed on isotropic supports: the linear oscillator driven
by the unbalance, solved in closed form from the scene's initial state) or with
a much tighter reference run, whose own error is estimated by comparing it with
a second reference ten times looser.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from .planar import build_planar_model, initial_state
from .scene import Scene
from .simulate import Trajectory, choose_method, simulate

DEFAULT_RTOLS = (1e-4, 1e-6, 1e-8, 1e-10)


def closed_form_no_balancer(scene: Scene, t: np.ndarray) -> np.ndarray | None:
    """Exact shaft motion x + i y [m] of a rotor without weights, or None.

    Applies when there are no weights, the speed is prescribed and constant
    (one programme node, no coast-down) and the supports are isotropic.  In
    units of tau = omega_1 t:  z'' + H z' + z = eps0 R^2 e^{i(R tau + beta)},
    whose steady part has the amplitude e R^2 / sqrt((1 - R^2)^2 + (H R)^2)
    (digest ch5 section 8.2), plus the free response fixed by z(0), z'(0).
    """
    d = scene.drive
    s = scene.supports
    if (scene.balancer.count or d.kind != "speed" or len(d.programme) != 1
            or d.coast_down_start is not None or s.stiffness_x != s.stiffness_y
            or s.damping_x != s.damping_y):
        return None
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


@dataclass
class AccuracyReport:
    scene: str
    reference: str
    reference_error_m: float
    scale_m: float
    rows: list

    def to_dict(self) -> dict:
        d = asdict(self)
        d["rows"] = [asdict(r) if not isinstance(r, dict) else r for r in self.rows]
        return d

    def table(self) -> str:
        lines = [f"scene: {self.scene}",
                 f"reference: {self.reference} (its own error ~ {self.reference_error_m:.3g} m); "
                 f"max |r| = {self.scale_m:.4g} m",
                 f"{'method':<8} {'rtol':>8} {'atol':>8} {'max error [m]':>14} {'rel. error':>11} "
                 f"{'wall [s]':>9} {'RHS evals':>10} {'steps':>8}"]
        for r in self.rows:
            lines.append(f"{r.method:<8} {r.rtol:>8.0e} {r.atol:>8.0e} {r.max_error_m:>14.3e} "
                         f"{r.relative_error:>11.3e} {r.wall_time_s:>9.3f} {r.nfev:>10d} {r.n_steps:>8d}"
                         + ("" if r.success else "  FAILED"))
        return "\n".join(lines)


def _position(tr: Trajectory) -> np.ndarray:
    return tr.x + 1j * tr.y


def accuracy(scene: Scene, rtols=DEFAULT_RTOLS, methods=None) -> AccuracyReport:
    """Run ``scene`` at each tolerance and method; errors vs exact or reference.

    Parameters
    ----------
    scene : Scene
    rtols : sequence of float
        Relative tolerances; atol = rtol / 100 on the dimensionless state.
    methods : sequence of str, optional
        Default: the automatically chosen method, plus "Radau" for stiff scenes.
    """
    auto, _, _ = choose_method(build_planar_model(scene), "auto")
    if methods is None:
        methods = [auto] if auto == "DOP853" else ["Radau", "BDF"]
    ref_method = "DOP853" if auto == "DOP853" else "Radau"
    exact = None
    runs = {}
    for m in methods:
        for rt in rtols:
            runs[(m, rt)] = simulate(scene, method=m, rtol=rt, atol=rt * 1e-2)
    t = next(iter(runs.values())).t
    exact = closed_form_no_balancer(scene, t)
    if exact is not None:
        ref = exact
        ref_name = "closed form (no weights, constant speed, isotropic supports)"
        ref_err = 0.0
    else:
        tight = 1e-13 if ref_method == "DOP853" else 1e-11
        r1 = simulate(scene, method=ref_method, rtol=tight, atol=tight * 1e-2)
        r2 = simulate(scene, method=ref_method, rtol=tight * 10, atol=tight * 1e-1)
        ref = _position(r1)
        ref_name = f"{ref_method} at rtol {tight:.0e}"
        k = min(len(r1.t), len(r2.t))
        ref_err = float(np.max(np.abs(ref[:k] - _position(r2)[:k])))
    scale = float(np.max(np.abs(ref))) or 1.0
    rows = []
    for (m, rt), tr in runs.items():
        k = min(len(tr.t), len(ref))
        err = float(np.max(np.abs(_position(tr)[:k] - ref[:k]))) if k else float("nan")
        rows.append(AccuracyRow(m, rt, rt * 1e-2, err, err / scale, tr.stats.wall_time,
                                tr.stats.nfev, tr.stats.n_steps, tr.stats.success))
    return AccuracyReport(scene.name, ref_name, ref_err, scale, rows)
