"""Run a :class:`LinearRotor` with correction weights in any planes (compiled, O(n) per call).

The equations, the compiled right-hand side and the packing are in
:mod:`stand.model.rotors.coupled_kernel`; this module integrates them through the one
integrator path (:mod:`stand.integrate.driver`) and returns the samples in SI
(:class:`CoupledRun`).  :func:`stand.run` turns a scene into the same integration
and a :class:`stand.integrate.result.Run`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from stand.model.programme import programme_kinematics_many
from stand.scene.model import PlaneWeights, RotorTorqueDrive  # noqa: F401 (re-exported: the inputs)
from stand.model.rotors.bodies import body_channels, body_initial
from stand.model.rotors.coupled_kernel import (H_W0, W_L, W_M, W_PLANE, CoupledModel, build_model,
                                               rhs_generic, with_locked_weights)
from stand.model.rotors.structure import LinearRotor
from stand.model.rotors.weight_table import W_EPS, W_ER, ball_offsets
from stand.integrate.driver import run_dop853
from stand.integrate.result import SolverStats

__all__ = ["PlaneWeights", "CoupledModel", "CoupledRun", "build_model", "simulate_coupled",
           "rhs_generic", "with_locked_weights", "initial_state", "samples_si",
           "RotorTorqueDrive"]


@dataclass
class CoupledRun:
    """Result of :func:`simulate_coupled` (SI).

    Attributes
    ----------
    t : (k,) s;  q : (k, n) rotor coordinates;  qd : (k, n) their rates
    rotor_angle : (k,) rad;  speed : (k,) rad/s
    weight_angle : (k, N) rad, relative to the reference mark
    planes : dict name -> (k, 2) fixed-frame translation of each plane [m]
    residual : dict name -> (k, 2) total unbalance in that plane, rotor frame [kg m]
    stats : dict (n_steps, n_rejected, nfev, message, success)
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    rotor_angle: np.ndarray
    speed: np.ndarray
    weight_angle: np.ndarray
    planes: dict
    residual: dict
    stats: dict = field(default_factory=dict)
    bodies: list = field(default_factory=list)   #: per body weight: coordinate -> array (SI)

    @property
    def success(self) -> bool:
        return bool(self.stats.get("success"))

    @property
    def static_residual(self) -> np.ndarray:
        """(k, 2) sum of the residual unbalances of all planes, rotor frame [kg m]
        (the static unbalance; equal to the balancer plane's residual when the
        unbalance and the weights share one plane location)."""
        return sum(self.residual.values())


def simulate_coupled(rotor: LinearRotor, weights: Sequence[PlaneWeights], programme,
                     duration: float, sample_rate: float, *, rtol: float = 1e-8,
                     atol: float = 1e-10, q0=None, qd0=None, omega_ref=None,
                     max_steps: int = 10_000_000, bodies=()) -> CoupledRun:
    """Integrate a rotor with its weights under a speed programme (compiled DOP853).

    Parameters
    ----------
    rotor, weights, programme : see :func:`build_model`
    duration : float   s
    sample_rate : float   Hz (samples kept on a uniform grid, dense output)
    rtol, atol : float
        Tolerances on the scaled state (coordinates in units of their
        high-speed capacity response; weight angles in rad; time in 1/omega_ref).
    q0, qd0 : array (n,), optional
        Initial rotor coordinates [SI] and rates; weights start at their
        balancers' ``initial_angles`` / ``initial_speeds`` (relative).
    """

    duration = _positive("duration", duration, "s")
    sample_rate = _positive("sample_rate", sample_rate, "Hz")
    model = build_model(rotor, weights, programme, omega_ref, bodies)
    y = initial_state(model, weights, q0, qd0)
    w = model.omega_ref
    ts = np.arange(0.0, duration + 0.5 / sample_rate, 1.0 / sample_rate) * w
    ts = ts[ts <= duration * w * (1 + 1e-12)]
    out = np.full((ts.size, y.size), np.nan)
    out[0] = y
    st = SolverStats(method="DOP853", rtol=rtol, atol=atol)
    k = run_dop853(model, y, duration * w, rtol, atol, ts, out, st, max_steps, False)
    stats = dict(n_steps=st.n_steps, n_rejected=st.n_rejected, nfev=st.nfev, success=st.success,
                 message=st.message)
    res = CoupledRun(*samples_si(model, out[:k], ts[:k]), stats)
    if model.bodies:
        res.bodies, _ = body_channels(model.bt, model.bodies, out[:k], w, res.rotor_angle,
                                      res.planes)
    return res


def _positive(name, v, unit):
    v = float(v)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} = {v!r}: must be > 0 ({unit})")
    return v


def initial_state(model: CoupledModel, weights, q0=None, qd0=None) -> np.ndarray:
    """Scaled initial state: rotor coordinates ``q0`` [SI] and rates ``qd0``; the weights at
    their balancers' ``initial_angles`` / ``initial_speeds`` (relative to the rotor)."""
    n, nw, w = model.n, model.nw, model.omega_ref
    y = np.zeros(model.size)
    if q0 is not None:
        y[:n] = np.asarray(q0, float) / model.scale
    if qd0 is not None:
        y[n + nw:2 * n + nw] = np.asarray(qd0, float) / (model.scale * w)
    if weights:
        y[n:n + nw] = np.concatenate([np.asarray(pw.balancer.initial_angles, float) for pw in weights])
        y[2 * n + nw:2 * (n + nw)] = np.concatenate(
            [np.asarray(pw.balancer.initial_speeds, float) for pw in weights]) / w
    if model.free:      # torque drive: phi = 0, Omega = the drive's initial speed
        y[model.i_phi + 1] = model.sp[H_W0] / w
    if model.bodies:
        q = y[:n] * model.scale
        planes = {p: model.rotor.planes[p] @ q for p in model.plane_names}
        omega0 = (y[model.i_phi + 1] * w if model.free
                  else programme_kinematics_many(0.0, model.prog)[0, 1] * w)
        body_initial(model.bt, model.bodies, y, w, omega0, planes)
    return y


def samples_si(model: CoupledModel, out: np.ndarray, tau: np.ndarray) -> tuple:
    """SI samples from the scaled ones: ``(t, q, qd, rotor_angle, speed, weight_angle
    (relative), planes, residual)`` (the fields of :class:`CoupledRun` but ``stats``), plus
    nothing else; weight speeds relative to the rotor are ``out[:, 2n+nw:2(n+nw)] * omega_ref``."""
    rotor = model.rotor
    n, nw, w = model.n, model.nw, model.omega_ref
    q = out[:, :n] * model.scale
    qd = out[:, n + nw:2 * n + nw] * model.scale * w
    alpha = out[:, n:n + nw]
    if model.free:
        phis, speeds = out[:, model.i_phi].copy(), out[:, model.i_phi + 1] * w
    else:
        kin = programme_kinematics_many(np.ascontiguousarray(tau, dtype=float), model.prog)
        phis, speeds = kin[:, 0], kin[:, 1] * w
    planes = {p: q @ rotor.planes[p].T for p in model.plane_names}
    residual = {}
    for k, p in enumerate(model.plane_names):
        U = np.zeros((tau.size, 2))
        for u in rotor.unbalances:
            if u.plane == p:
                U += u.s * np.array([math.cos(u.angle), math.sin(u.angle)])
        for j in np.nonzero(model.wt[:, W_PLANE] == k)[0]:
            if model.wt[j, W_ER] != 0.0 or model.wt[j, W_EPS] != 0.0:   # the race's shape
                z = model.wt[j, W_M] * ball_offsets(model.wt, j, alpha[:, j])
                U[:, 0] += z.real
                U[:, 1] += z.imag
                continue
            ml = model.wt[j, W_M] * model.wt[j, W_L]
            U[:, 0] += ml * np.cos(alpha[:, j])
            U[:, 1] += ml * np.sin(alpha[:, j])
        residual[p] = U
    if model.bodies:
        _, unb = body_channels(model.bt, model.bodies, out, w, phis, planes)
        for pb, U in zip(model.bodies, unb):
            residual[pb.plane] = residual[pb.plane] + U
    return tau / w, q, qd, phis, speeds, alpha, planes, residual
