"""Influence-coefficient balancing from 1X phasors (the field balancer's method).

A reference run gives the 1X phasors ``V0`` of S measurement points; one
trial run per correction plane j (a known trial unbalance ``T_j`` added in
plane j alone) gives ``V_j``.  For a linear rotor at one speed

    A[:, j] = (V_j - V0) / T_j          [m per kg m]

is column j of the influence-coefficient matrix (S x P), and the correction
unbalances that cancel the reference vibration are

    U = -A^+ V0                         [kg m]

(``A^+`` the inverse for S = P, the least-squares pseudo-inverse for S > P).
A correction plane's mass at radius r is ``|U_j| / r`` at angle ``arg U_j``
from the reference mark.

Conventions: phasors are the 1X vectors of :func:`dsp.unbalance.synchronous_component`
(x + i y of the displacement, read in the rotor frame from the reference mark),
unbalances are ``s e^{i angle}`` with the angle from the same mark, counter-
clockwise (in the direction of rotation).  Uncertainties are propagated to
first order from the phasors' standard uncertainties (each of Re and Im, the
``vector_std_m`` of a :class:`~dsp.unbalance.SynchronousComponent`), treated as
independent; the trial unbalances are taken as exact.

Plain numpy; imports nothing from ``stand``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional, Sequence

import numpy as np

from .units import DEG_PER_RAD

__all__ = ["influence_matrix", "InfluenceBalance", "influence_balance"]

#: condition number of A above which the trial runs cannot separate the planes
MAX_CONDITION = 1e8


def _complex(a, name, shape):
    try:
        v = np.asarray(a, dtype=complex)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: must be complex numbers, got {a!r}") from None
    if v.shape != shape:
        raise ValueError(f"{name}: shape {v.shape}, expected {shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name}: contains NaN or inf")
    return v


def _std(a, name, shape):
    if a is None:
        return np.zeros(shape)
    v = np.broadcast_to(np.asarray(a, dtype=float), shape).astype(float)
    if not np.all(np.isfinite(v)) or np.any(v < 0):
        raise ValueError(f"{name}: standard uncertainties must be finite and >= 0")
    return v


def _labels(names, n, default, what):
    if names is None:
        return tuple(f"{default}{k + 1}" for k in range(n))
    names = tuple(str(s) for s in names)
    if len(names) != n:
        raise ValueError(f"{what}: {len(names)} name(s) {list(names)} for {n} {what}")
    return names


def influence_matrix(reference, trials, trial_unbalances):
    """Influence coefficients ``A[i, j] = (V_j[i] - V0[i]) / T_j`` [m / (kg m)].

    Parameters
    ----------
    reference : (S,) complex
        1X phasors V0 of the S measurement points in the reference run [m].
    trials : (P, S) complex
        ``trials[j]``: the phasors with the trial unbalance in plane j [m].
    trial_unbalances : (P,) complex
        Trial unbalances ``m r e^{i angle}`` [kg m].

    Returns
    -------
    (S, P) complex
    """
    V0 = np.asarray(reference, dtype=complex).ravel()
    S = V0.size
    T = np.asarray(trial_unbalances, dtype=complex).ravel()
    P = T.size
    V = _complex(trials, "trials", (P, S))
    if np.any(T == 0):
        j = int(np.argmax(T == 0))
        raise ValueError(f"trial_unbalances[{j}]: the trial unbalance is zero")
    return ((V - V0[None, :]) / T[:, None]).T


def _solve(V0, V, T):
    A = ((V - V0[None, :]) / T[:, None]).T
    U = -np.linalg.lstsq(A, V0, rcond=None)[0]
    return A, U


@dataclass(frozen=True)
class InfluenceBalance:
    """Influence-coefficient balancing result.

    Attributes
    ----------
    planes : tuple of str
        Correction planes (P).
    sensors : tuple of str
        Measurement points (S >= P).
    influence_m_per_kg_m : (S, P) complex ndarray
        A: 1X phasor change at each sensor per unit trial unbalance [m / (kg m)].
    influence_std_m_per_kg_m : (S, P) float ndarray
        Standard uncertainty of each of Re and Im of A.
    reference_m : (S,) complex ndarray
        V0, the reference run's 1X phasors [m].
    correction_kg_m : (P,) complex ndarray
        U = -A^+ V0: the correction unbalance of each plane [kg m].
    correction_cov_kg_m2 : (P, 2, 2) float ndarray
        Covariance of (Re U_j, Im U_j) [(kg m)^2].
    radius_m : (P,) float ndarray
        Correction radii [m] (NaN where not given).
    mass_kg, mass_std_kg : (P,) float ndarray
        Correction masses ``|U_j| / r_j`` and their standard uncertainties [kg].
    angle_rad, angle_std_rad : (P,) float ndarray
        Angle of each correction mass from the reference mark, in [0, 2 pi),
        and its standard uncertainty [rad].
    residual_m : (S,) complex ndarray
        Predicted 1X phasors after the correction, V0 + A U [m] (zero for
        S = P; the least-squares residual for S > P).
    condition : float
        2-norm condition number of A (large: the trial runs hardly separate
        the planes; the correction is then sensitive to noise).
    speed_rad_s : float
        Mean speed of the runs [rad/s] (NaN when not given).
    """

    planes: tuple
    sensors: tuple
    influence_m_per_kg_m: np.ndarray = field(repr=False)
    influence_std_m_per_kg_m: np.ndarray = field(repr=False)
    reference_m: np.ndarray = field(repr=False)
    correction_kg_m: np.ndarray = field(repr=False)
    correction_cov_kg_m2: np.ndarray = field(repr=False)
    radius_m: np.ndarray
    mass_kg: np.ndarray
    mass_std_kg: np.ndarray
    angle_rad: np.ndarray
    angle_std_rad: np.ndarray
    residual_m: np.ndarray = field(repr=False)
    condition: float = float("nan")
    speed_rad_s: float = float("nan")

    @property
    def mass_g(self) -> np.ndarray:
        """Correction masses [g]."""
        return self.mass_kg * 1e3

    @property
    def mass_std_g(self) -> np.ndarray:
        """Standard uncertainties of the correction masses [g]."""
        return self.mass_std_kg * 1e3

    @property
    def angle_deg(self) -> np.ndarray:
        """Correction angles from the reference mark [deg], in [0, 360)."""
        return self.angle_rad * DEG_PER_RAD

    @property
    def angle_std_deg(self) -> np.ndarray:
        """Standard uncertainties of the correction angles [deg]."""
        return self.angle_std_rad * DEG_PER_RAD

    @property
    def correction_gmm(self) -> np.ndarray:
        """|U_j| [g mm]."""
        return np.abs(self.correction_kg_m) * 1e6

    @property
    def correction_std_gmm(self) -> np.ndarray:
        """Standard uncertainty of |U_j| [g mm]."""
        return self._abs_std() * 1e6

    def _abs_std(self):
        U = self.correction_kg_m
        out = np.empty(U.size)
        for j, u in enumerate(U):
            a = abs(u)
            g = np.array([u.real, u.imag]) / a if a > 0 else np.array([1.0, 0.0])
            out[j] = math.sqrt(max(float(g @ self.correction_cov_kg_m2[j] @ g), 0.0))
        return out

    def to_dict(self) -> dict:
        """Plain-Python form (JSON-ready): per plane and per sensor, lab units."""
        A = self.influence_m_per_kg_m
        return {
            "speed_rev_s": self.speed_rad_s / (2.0 * math.pi),
            "condition": self.condition,
            "planes": [
                {"plane": p, "correction_gmm": float(self.correction_gmm[j]),
                 "correction_std_gmm": float(self.correction_std_gmm[j]),
                 "radius_mm": float(self.radius_m[j] * 1e3),
                 "mass_g": float(self.mass_g[j]), "mass_std_g": float(self.mass_std_g[j]),
                 "angle_deg": float(self.angle_deg[j]),
                 "angle_std_deg": float(self.angle_std_deg[j])}
                for j, p in enumerate(self.planes)],
            "sensors": [
                {"sensor": s, "reference_um": float(abs(self.reference_m[i]) * 1e6),
                 "reference_deg": float(np.degrees(np.angle(self.reference_m[i])) % 360.0),
                 "residual_um": float(abs(self.residual_m[i]) * 1e6),
                 "influence_um_per_gmm": [float(abs(A[i, j])) for j in range(len(self.planes))],
                 "influence_deg": [float(np.degrees(np.angle(A[i, j])) % 360.0)
                                   for j in range(len(self.planes))]}
                for i, s in enumerate(self.sensors)],
        }

    def to_frame(self):
        """One row per correction plane: correction [g mm], radius [mm], mass [g],
        angle [deg] and their standard uncertainties (a pandas DataFrame)."""
        import pandas as pd

        return pd.DataFrame({
            "plane": list(self.planes),
            "correction_gmm": self.correction_gmm,
            "correction_std_gmm": self.correction_std_gmm,
            "radius_mm": self.radius_m * 1e3,
            "mass_g": self.mass_g,
            "mass_std_g": self.mass_std_g,
            "angle_deg": self.angle_deg,
            "angle_std_deg": self.angle_std_deg,
        }).set_index("plane")


def influence_balance(reference, trials, trial_unbalances, radii=None, *,
                      reference_std=None, trials_std=None, speeds=None,
                      speed_rtol: float = 0.01, planes: Optional[Sequence[str]] = None,
                      sensors: Optional[Sequence[str]] = None,
                      runs: Optional[Sequence[str]] = None) -> InfluenceBalance:
    """Correction masses from a reference run and one trial run per plane.

    Parameters
    ----------
    reference : (S,) complex
        1X phasors V0 of the S measurement points in the reference run [m].
    trials : (P, S) complex
        ``trials[j]``: the 1X phasors of the run with the trial unbalance in plane j [m].
    trial_unbalances : (P,) complex
        Trial unbalances ``m r e^{i angle}`` [kg m], angle from the reference mark.
    radii : (P,) float, optional
        Correction radii [m]; the masses are NaN where not given.
    reference_std, trials_std : float or arrays of shape (S,), (P, S), optional
        Standard uncertainty of each of Re and Im of the phasors [m] (default 0).
    speeds : (P + 1,) float, optional
        Mean speed of the reference run and of each trial run [rad/s].  The
        influence coefficients hold at one speed: runs whose speeds differ from
        the reference's by more than ``speed_rtol`` (relative) are refused.
    planes, sensors : sequence of str, optional
        Names of the correction planes and measurement points.
    runs : sequence of str, optional
        Names of the P + 1 runs (e.g. file names) for the error messages.

    Returns
    -------
    InfluenceBalance

    Raises
    ------
    ValueError
        Fewer sensors than planes, shapes that do not match, a zero trial
        unbalance, a trial run whose phasors equal the reference's, a
        (near-)singular influence matrix, runs at different speeds; the
        message names the run, plane or sensor.
    """
    V0 = np.asarray(reference, dtype=complex).ravel()
    S = V0.size
    V0 = _complex(V0, "reference", (S,))
    T = np.asarray(trial_unbalances, dtype=complex).ravel()
    P = T.size
    if P == 0:
        raise ValueError("trial_unbalances: no correction plane (give one trial run per plane)")
    planes = _labels(planes, P, "plane", "planes")
    sensors = _labels(sensors, S, "sensor", "sensors")
    runs = _labels(runs, P + 1, "run", "runs") if runs is not None else \
        ("reference run",) + tuple(f"trial run {j + 1} (plane {p})" for j, p in enumerate(planes))
    if S < P:
        raise ValueError(f"sensors: {S} measurement point(s) {list(sensors)} for {P} correction "
                         f"planes {list(planes)}; need at least as many sensors as planes")
    T = _complex(T, "trial_unbalances", (P,))
    V = _complex(trials, "trials", (P, S))
    for j in range(P):
        if T[j] == 0:
            raise ValueError(f"trial_unbalances[{j}] (plane {planes[j]}): the trial unbalance "
                             f"is zero")
    s0 = _std(reference_std, "reference_std", (S,))
    sV = _std(trials_std, "trials_std", (P, S))
    if radii is None:
        r = np.full(P, np.nan)
    else:
        r = np.asarray(radii, dtype=float).ravel()
        if r.shape != (P,):
            raise ValueError(f"radii: {r.size} value(s) for {P} planes {list(planes)}")
        if np.any(~np.isnan(r) & ~(r > 0)) or np.any(np.isinf(r)):
            raise ValueError(f"radii: must be positive and finite [m], got {r.tolist()}")
    speed = float("nan")
    if speeds is not None:
        w = np.asarray(speeds, dtype=float).ravel()
        if w.shape != (P + 1,):
            raise ValueError(f"speeds: {w.size} value(s), expected {P + 1} (reference + one "
                             f"trial run per plane)")
        if not np.all(np.isfinite(w)) or np.any(w <= 0):
            raise ValueError(f"speeds: must be positive and finite [rad/s], got {w.tolist()}")
        for k in range(1, P + 1):
            rel = abs(w[k] - w[0]) / w[0]
            if rel > speed_rtol:
                raise ValueError(
                    f"{runs[k]}: speed {w[k] / (2 * math.pi):.6g} rev/s differs from the "
                    f"{runs[0]}'s {w[0] / (2 * math.pi):.6g} rev/s by {100 * rel:.3g} % "
                    f"(tolerance {100 * speed_rtol:.3g} %); influence coefficients hold at one "
                    f"speed: run all at the same steady speed")
        speed = float(np.mean(w))
    scale = max(float(np.max(np.abs(V0))), float(np.max(np.abs(V))), 1e-300)
    for j in range(P):
        d = np.abs(V[j] - V0)
        if np.max(d) <= 1e-9 * scale or np.max(d) == 0.0:
            raise ValueError(f"{runs[j + 1]}: the trial unbalance did not change the 1X "
                             f"vibration (|V - V0| = {np.max(d):.3g} m); A would be singular: "
                             f"check the trial weight and that the right recording was given")
    A, U = _solve(V0, V, T)
    sv = np.linalg.svd(A, compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else float("inf")
    if not cond < MAX_CONDITION:
        raise ValueError(f"influence matrix A is singular (condition number {cond:.3g}): the "
                         f"trial runs ({', '.join(runs[1:])}) do not separate the planes "
                         f"{list(planes)} at sensors {list(sensors)}; move a trial weight "
                         f"to another plane, or measure at other points")
    # first-order propagation: Jacobian of (Re U, Im U) by central differences in
    # every real input (Re, Im of V0 and of each V_j)
    x0 = np.concatenate([V0, V.ravel()])
    sig = np.concatenate([s0, sV.ravel()])
    J = np.zeros((2 * P, 2 * x0.size))
    cov = np.zeros((2 * P, 2 * P))
    if np.any(sig > 0):
        for k in range(x0.size):
            if sig[k] == 0:
                continue
            for part, unit in ((0, 1.0), (1, 1j)):
                h = 1e-6 * max(abs(x0[k]), sig[k], 1e-30)
                xp = x0.copy()
                xm = x0.copy()
                xp[k] += unit * h
                xm[k] -= unit * h
                Up = _solve(xp[:S], xp[S:].reshape(P, S), T)[1]
                Um = _solve(xm[:S], xm[S:].reshape(P, S), T)[1]
                dU = (Up - Um) / (2 * h)
                J[:, 2 * k + part] = np.concatenate([dU.real, dU.imag])
        sig2 = np.repeat(sig, 2) ** 2
        cov = (J * sig2) @ J.T
    cU = np.zeros((P, 2, 2))
    for j in range(P):
        idx = [j, P + j]
        cU[j] = cov[np.ix_(idx, idx)]
    absU = np.abs(U)
    ang = np.mod(np.angle(U), 2 * math.pi)
    abs_std = np.zeros(P)
    ang_std = np.zeros(P)
    for j in range(P):
        a = absU[j]
        if a == 0:
            abs_std[j] = math.sqrt(max(np.trace(cU[j]) / 2, 0.0))
            ang_std[j] = math.pi
            continue
        g = np.array([U[j].real, U[j].imag]) / a
        n = np.array([-U[j].imag, U[j].real]) / (a * a)
        abs_std[j] = math.sqrt(max(float(g @ cU[j] @ g), 0.0))
        ang_std[j] = math.sqrt(max(float(n @ cU[j] @ n), 0.0))
    # A's uncertainty: each of Re, Im of (V_j - V0) / T_j
    A_std = np.sqrt(sV.T ** 2 + s0[:, None] ** 2) / np.abs(T)[None, :]
    return InfluenceBalance(
        planes=planes, sensors=sensors, influence_m_per_kg_m=A,
        influence_std_m_per_kg_m=A_std, reference_m=V0, correction_kg_m=U,
        correction_cov_kg_m2=cU, radius_m=r, mass_kg=absU / r, mass_std_kg=abs_std / r,
        angle_rad=ang, angle_std_rad=ang_std, residual_m=V0 + A @ U, condition=cond,
        speed_rad_s=speed)
