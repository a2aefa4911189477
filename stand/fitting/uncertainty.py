"""What the record leaves open of the fitted values: covariance, profile, identifiability.

At the optimum the augmented residual ``r`` (data rows in noise units, then the rotor angle's
prior rows) and its Jacobian ``J`` -- projected off the linear nuisance, so the offset, the
runout and the angle's error are marginalised -- give:

* the covariance, the larger of the white ``s^2 (J'J)^-1`` (``s^2`` = chi^2/dof) and the
  batch-means sandwich ``(J'J)^-1 S (J'J)^-1`` (S from 40 contiguous blocks of samples:
  residuals correlated in time -- coloured noise, model error following the speed -- are
  kept, not averaged away), as :func:`dsp.lsq.covariances` does for the rigid-rotor fit;
* the curvature along each value's profile: the cost at ``+-2 std`` along the direction in
  which the other values follow it (their conditional mean, the linearised profile); where
  the cost rises less than the quadratic model says (a non-linear, flat or one-sided
  objective) the std is widened by that ratio;
* an identifiability verdict per value: *not identifiable* when the record does not depend
  on it (a 100 % change moves the residual by less than one noise unit), when the others can
  make up for it (std above half its size), or when its profile is flat;
* chi^2/dof overall and per tenth of the record: where the model cannot explain the record.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["uncertainty"]

BLOCKS = 40
#: a value whose std exceeds this fraction of its scale is not identifiable
UNDETERMINED = 0.5


def _sandwich(Js, r, n, k_modes, Ai):
    """Batch-means sandwich (in scaled units): blocks of contiguous samples (both rows of a
    sample together), the prior rows one by one."""
    score_t = Js[:n] * r[:n, None] + Js[n:2 * n] * r[n:2 * n, None]     # per sample
    nb = int(min(BLOCKS, max(n // 16, 2)))
    edges = np.linspace(0, n, nb + 1).astype(int)
    sums = np.add.reduceat(score_t, edges[:-1], axis=0)
    S = sums.T @ sums
    if k_modes:
        sp = Js[2 * n:] * r[2 * n:, None]
        S = S + sp.T @ sp
    return Ai @ S @ Ai


def _segments(t, e, sigma, speed):
    """chi^2/dof of each tenth of the record."""
    out = []
    idx = np.array_split(np.arange(t.size), 10)
    for part in idx:
        if part.size < 4:
            continue
        c = float(np.mean(np.abs(e[part]) ** 2) / (2 * sigma * sigma))
        row = {"start_s": float(t[part[0]]), "end_s": float(t[part[-1]]), "chi2_dof": c}
        if speed is not None:
            row["speed_rev_s"] = [float(np.min(speed[part]) / (2 * math.pi)),
                                  float(np.max(speed[part]) / (2 * math.pi))]
        out.append(row)
    return out


def uncertainty(obj, theta, scales, lo, hi, free, rec, lp, progress=None) -> dict:
    """The fit's statistics at ``theta`` (module docstring): parameters (value, std, unit,
    identifiable), correlation, the fit's chi^2 and residual, notes."""
    n = rec.t.size
    r, Q, coef, m = obj.residual(theta, n)
    J = obj.jacobian(theta, n)
    k_modes = 0 if lp.modes is None else lp.modes.count
    e = rec.z - lp.fitted_signal(m, coef)
    sigma = lp.sigma
    n_lin = 4 if lp.runout else 2
    P = theta.size
    dof = max(2 * n - P - n_lin, 1)
    chi2 = float(np.sum(np.abs(e) ** 2) / sigma ** 2)
    chi2_dof = chi2 / dof
    Js = J * scales
    A = Js.T @ Js
    Ai = np.linalg.pinv(A, rcond=1e-12, hermitian=True)
    white = chi2_dof * Ai
    corr = _sandwich(Js, r, n, k_modes, Ai) * (2 * n / dof)
    var_s = np.maximum(np.diag(white), np.diag(corr))
    std = np.sqrt(np.maximum(var_s, 0.0)) * scales
    cost0 = float(r @ r)
    better = None
    notes = []
    # does the record show a motion at all?  The fitted model against the offset (and runout)
    # alone: a gain below chi^2's 99.9 % point for P values means the record is noise to it
    still = rec.z - (coef["offset"] + (coef["runout"] * np.exp(1j * lp.phi) if lp.runout else 0))
    gain = float(np.sum(np.abs(still) ** 2) - np.sum(np.abs(e) ** 2)) / sigma ** 2
    quiet = gain < 2.0 * P + 10.0 * math.sqrt(P) + 10.0
    # the Gauss-Newton step from here (a record that moves, every value felt): a trust region
    # that shrank on the way stops least squares where each step gains little, short of the
    # minimum it predicts chi^2 lower at
    g = Js.T @ r
    if not quiet and np.all(np.linalg.norm(Js, axis=0) >= 1.0) and float(g @ Ai @ g) > 0.1:
        th = np.clip(theta - (Ai @ g) * scales, lo, hi)
        rr = obj.residual(th, n)[0]
        if float(rr @ rr) < cost0 - 0.05:
            better = (th.copy(), float(rr @ rr))
    params = {}
    for i, f in enumerate(free):
        info = float(np.linalg.norm(Js[:, i]))
        note = None
        ident = True
        s = float(std[i])
        widen = 1.0
        if quiet:
            ident, note = False, (f"the record shows no motion above its noise: the fitted model "
                                  f"lowers chi^2 by {gain:.3g} against no motion at all, what "
                                  f"{P} values fitted to noise would")
            s = math.inf
        elif info < 1.0:
            ident, note = False, ("the record does not depend on it: a change by its whole size "
                                  f"({f.scale:.3g} {f.unit}) moves the residual by {info:.2g} "
                                  "noise units")
            s = math.inf
        else:
            # the profile: the others follow along their conditional mean
            d = Ai[:, i] / Ai[i, i] * (2.0 * math.sqrt(var_s[i])) * scales \
                if Ai[i, i] > 0 else np.zeros(P)
            rises = []
            for sign in (1.0, -1.0):
                th = np.clip(theta + sign * d, lo, hi)
                if np.allclose(th, theta):
                    continue
                rr = obj.residual(th, n)[0]
                rises.append(float(rr @ rr) - cost0)
                if rises[-1] < -max(1.0, 1e-9 * cost0) and (
                        better is None or float(rr @ rr) < better[1]):
                    better = (th.copy(), float(rr @ rr))     # not at the minimum yet
            expect = 4.0 * chi2_dof
            # the curvature is the mean of the two sides' rises (a first-order term from a
            # point a little beside the minimum cancels in it); one side where a bound stops
            rise = float(np.mean(rises)) if rises else None
            if rise is not None and rise < 0.25 * expect:
                ident = False
                note = (f"its profile is flat: {2 * s:.3g} {f.unit} either side the cost rises "
                        f"by {rise:.3g} where a determined value's would rise by {expect:.3g}")
            elif rise is not None and rise < expect:
                widen = math.sqrt(expect / max(rise, 1e-300))
                s *= widen
            if ident and s > UNDETERMINED * f.scale:
                ident = False
                note = (f"the record leaves it undetermined: ± {s:.3g} {f.unit}, more than half "
                        f"its size ({f.scale:.3g} {f.unit}); the other values can make up for it")
        at = (theta[i] <= f.lower + 1e-9 * f.scale) or (theta[i] >= f.upper - 1e-9 * f.scale)
        if at:
            side = "lower" if theta[i] <= f.lower + 1e-9 * f.scale else "upper"
            note = (note + "; " if note else "") + (f"at its {side} bound "
                                                      f"{getattr(f, side):g} {f.unit}")
            if ident and s > 0:
                note += ": the ± is one-sided"
        value = float(theta[i])
        if f.angle:
            value = value % 360.0
        params[f.path] = {"value": value, "std": s, "unit": f.unit, "identifiable": bool(ident),
                          "start": f.start, "lower": f.lower, "upper": f.upper,
                          "relative_std": (s / abs(value) if value and math.isfinite(s) else None),
                          "profile_widening": widen, "note": note}
        if not ident:
            notes.append(f"{f.path}: not identifiable from this record ({note})")
    # correlation of the free values, from the chosen variances
    k = len(free)
    Cw = white[:k, :k]
    dw = np.sqrt(np.maximum(np.diag(Cw), 1e-300))
    R = Cw / np.outer(dw, dw)
    R = np.clip(R, -1.0, 1.0)
    strong = [(free[a].path, free[b].path, float(R[a, b])) for a in range(k) for b in range(a)
              if abs(R[a, b]) > 0.95]
    for a, b, c in strong:
        notes.append(f"{a} and {b} are strongly correlated ({c:+.3f}): the record determines "
                     "a combination of them better than each")
    segs = _segments(rec.t, e, sigma, rec.speed())
    fit = {"chi2_dof": chi2_dof, "rms_residual": float(np.sqrt(np.mean(np.abs(e) ** 2))),
           "rms_residual_unit": rec.unit, "noise_std": sigma, "noise_std_unit": rec.unit,
           "samples": int(n), "dof": int(dof), "free_values": len(free),
           "nuisance_values": int(P - len(free) + n_lin + k_modes), "segments": segs,
           "explained": bool(chi2_dof < 2.0)}
    if chi2_dof >= 2.0:
        bad = [s_ for s_ in segs if s_["chi2_dof"] > 2.0 * max(1.0, np.median(
            [q["chi2_dof"] for q in segs]))]
        where = ", ".join(f"{s_['start_s']:.3g}-{s_['end_s']:.3g} s" +
                          (f" ({s_['speed_rev_s'][0]:.3g}-{s_['speed_rev_s'][1]:.3g} rev/s)"
                           if "speed_rev_s" in s_ else "") for s_ in bad) or "all along"
        fit["unexplained_where"] = where
        notes.append(f"the fitted model does not explain the record: chi2/dof = {chi2_dof:.3g} "
                     f"(residual RMS {fit['rms_residual']:.3g} {rec.unit} against noise "
                     f"{sigma:.3g} {rec.unit}); most of the misfit {('in ' + where) if bad else where}"
                     "; the ± are widened by the residuals' own scatter (sandwich), but a "
                     "model that misses the physics may still be biased")
    return {"parameters": params,
            "correlation": {"paths": [f.path for f in free], "matrix": R.tolist()},
            "fit": fit, "notes": notes, "covariance": white, "std": std, "better": better}

