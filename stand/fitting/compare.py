"""Theory against experiment: the quantities the seeds compare, measured in the record and
predicted by the fitted model, each with its ±, and the difference in sigma.

Every quantity is one function of a signal (``x + i y`` at the record's samples, the measured
rotor angle and speed), applied alike to the record (its offset and runout removed: the
probes', not the rotor's) and to the fitted model's simulation -- so the two are measured the
same way, and a difference is the model's, not the method's:

* **critical speed** -- the speed of the largest 1X amplitude (one value per revolution,
  parabola through the peak) on the first passage;
* **onset of autobalancing** -- the first speed past that peak where the 1X amplitude falls
  below half of what the rotor without its weights would have there (the fitted rotor's
  steady response; planar rotor);
* **residual 1X amplitude** and **residual whirl radius** over the record's last fifth
  (the radius with the noise's share removed), and the **reduction factor**: the rotor
  without its weights at the final speed over the residual whirl;
* **settling time** -- from the end of the speed change until the 1X amplitude stays within
  10 % (or three noise units) of its final value;
* **precession frequency** of a quasi-periodic ("stuck weights") motion over the last fifth,
  when the record or the model shows one (:func:`dsp.quasiperiodic.decompose`).

The measured value's std: the spread of the quantity over noise draws of the record's own
noise level added to the fitted model's signal; the predicted value's: the quantity along
the principal directions of the fitted values' covariance (2 P simulations).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["comparison", "quantities"]

TWO_PI = 2.0 * math.pi
UNITS = {"critical_speed": "rev/s", "onset_speed": "rev/s", "residual_1x": "m",
         "residual_whirl": "m", "reduction_factor": "1", "settling_time": "s",
         "precession_frequency": "Hz"}
LABELS = {"critical_speed": "critical speed (1X peak)",
          "onset_speed": "onset of autobalancing (1X below half the rotor's without weights)",
          "residual_1x": "residual 1X amplitude (last fifth)",
          "residual_whirl": "residual whirl radius (last fifth)",
          "reduction_factor": "reduction factor (rotor without weights / residual whirl)",
          "settling_time": "settling time after the speed change",
          "precession_frequency": "precession frequency of the stuck weights"}


def _per_revolution(t, z, phi, w):
    """(speed [rev/s], 1X amplitude, end time [s]) per whole revolution of the angle."""
    rev = np.floor((phi - phi[0]) / TWO_PI).astype(int)
    zz = z * np.exp(-1j * phi)
    cnt = np.bincount(rev)
    ok = cnt >= 4
    s = (np.bincount(rev, weights=zz.real) + 1j * np.bincount(rev, weights=zz.imag))[ok] / cnt[ok]
    sp = np.bincount(rev, weights=w)[ok] / cnt[ok] / TWO_PI
    te = t[np.searchsorted(rev, np.flatnonzero(ok), side="right") - 1]
    return sp, np.abs(s), te


def _no_weights_amplitude(scene, speed_rev_s):
    """The steady whirl of the fitted rotor without its weights [m] (planar rotor; None else)."""
    if scene is None or getattr(scene, "kind", None) != "planar":
        return None
    r, s = scene.rotor, scene.supports
    w = TWO_PI * np.asarray(speed_rev_s, float)
    k, c = 0.5 * (s.stiffness_x + s.stiffness_y), 0.5 * (s.damping_x + s.damping_y)
    return r.mass * r.eccentricity * w * w / np.abs(k - r.mass * w * w + 1j * c * w)


def quantities(t, z, phi, w, scene=None, sigma: float = 0.0, qp: bool = False) -> dict:
    """The compared quantities of one signal (module docstring); a value that does not apply
    is missing from the dict."""
    out = {}
    last = t >= t[0] + 0.8 * (t[-1] - t[0])
    zl = z[last]
    r2 = float(np.mean(np.abs(zl - zl.mean()) ** 2)) - 2.0 * sigma * sigma
    out["residual_whirl"] = math.sqrt(max(r2, 0.0))
    if phi is None or w is None:
        return out
    out["residual_1x"] = float(abs(np.mean(zl * np.exp(-1j * phi[last]))))
    sp, amp, te = _per_revolution(t, z, phi, w)
    if sp.size < 8:
        return out
    rising = np.max(sp) > 1.5 * max(np.min(sp), 1e-9)
    if rising:
        i = int(np.argmax(amp))
        if 0 < i < amp.size - 1 and amp[i] > 3 * amp[-1]:
            a, b, c = amp[i - 1:i + 2]
            den = a - 2 * b + c
            f = 0.5 * (a - c) / den if den != 0 else 0.0
            out["critical_speed"] = float(sp[i] + f * 0.5 * (sp[i + 1] - sp[i - 1]))
            nb = _no_weights_amplitude(scene, sp)
            if nb is not None:
                below = np.flatnonzero((np.arange(sp.size) > i) & (amp < 0.5 * nb))
                if below.size:
                    j = below[0]
                    x0, x1 = amp[j - 1] - 0.5 * nb[j - 1], amp[j] - 0.5 * nb[j]
                    g = x0 / (x0 - x1) if x0 != x1 else 1.0
                    out["onset_speed"] = float(sp[j - 1] + g * (sp[j] - sp[j - 1]))
    nb_end = _no_weights_amplitude(scene, [float(np.mean(w[last])) / TWO_PI])
    if nb_end is not None and out["residual_whirl"] > 0:
        out["reduction_factor"] = float(nb_end[0] / out["residual_whirl"])
    # settling: from the end of the speed change
    top = float(np.median(w[last]))
    moving = np.flatnonzero(np.abs(w - top) > 1e-3 * max(abs(top), 1e-9))
    if moving.size and moving[-1] < t.size - 1:
        t_end = float(t[moving[-1]])
        after = te > t_end
        if after.sum() > 4:
            final = float(amp[after][-max(2, int(after.sum()) // 5):].mean())
            band = max(0.1 * final, 3.0 * sigma / math.sqrt(max(1, t.size // max(sp.size, 1))))
            outside = np.flatnonzero(after & (np.abs(amp - final) > band))
            out["settling_time"] = float((te[outside[-1]] if outside.size else t_end) - t_end)
    if qp:
        from dsp import quasiperiodic as qpd
        from dsp.errors import SignalError

        try:
            dec = qpd.decompose(t[last], zl, rotor_speed_hz=top / TWO_PI, polish="rect")
            if dec.precession is not None:
                out["precession_frequency"] = float(dec.precession_hz)
        except (SignalError, ValueError, np.linalg.LinAlgError):
            pass
    return out


def comparison(obj, theta, unc, rec, fitted, series, progress=None, draws: int = 8) -> list:
    """The theory-against-experiment rows of a fit (module docstring)."""
    t = rec.t
    phi, w = rec.phi(), rec.speed()
    sigma = obj.linear(t.size).sigma
    coef_model = series["model"] - series["simulated"]      # the fitted nuisance (offset, ...)
    measured_sig = series["measured"] - coef_model           # the record without it
    sim = series["simulated"]
    # a quasi-periodic motion: decompose only when the last fifth whirls at other than 1X
    last = t >= t[0] + 0.8 * (t[-1] - t[0])
    qp = False
    if phi is not None:
        for z in (measured_sig, sim):
            zl = z[last] - z[last].mean()
            one = np.mean(zl * np.exp(-1j * phi[last]))
            rest = np.sqrt(max(np.mean(np.abs(zl) ** 2) - abs(one) ** 2 - 2 * sigma ** 2, 0.0))
            qp |= rest > max(0.2 * abs(one), 20 * sigma)
    m = quantities(t, measured_sig, phi, w, fitted, sigma, qp)
    p = quantities(t, sim, phi, w, fitted, 0.0, qp)
    rng = np.random.default_rng(0)
    reps = [quantities(t, sim + sigma * (rng.standard_normal(t.size)
                                         + 1j * rng.standard_normal(t.size)),
                       phi, w, fitted, sigma, qp) for _ in range(draws)]
    # the prediction's spread along the principal directions of the covariance
    C = np.asarray(unc["covariance"], float)
    k = len(unc["parameters"])
    spreads = {key: 0.0 for key in p}
    try:
        lam, V = np.linalg.eigh(0.5 * (C + C.T))
    except np.linalg.LinAlgError:
        lam, V = np.zeros(0), np.zeros((C.shape[0], 0))
    from stand.fitting.paths import FitError, scene_with

    setup = obj.setup
    for j in range(lam.size):
        if lam[j] <= 0:
            continue
        d = V[:, j] * math.sqrt(lam[j])
        vals = []
        for sgn in (1.0, -1.0):
            th = np.asarray(theta, float) + sgn * d
            try:
                sc = scene_with(setup.doc, dict(zip(setup.paths, th[:k])), setup.stem)
            except FitError:
                vals = []
                break
            zz = obj.signal(th, t.size)
            if not np.all(np.isfinite(zz)):
                vals = []
                break
            vals.append(quantities(t, zz, phi, w, sc, 0.0, qp))
        if len(vals) == 2:
            for key in spreads:
                if key in vals[0] and key in vals[1]:
                    spreads[key] += (0.5 * (vals[0][key] - vals[1][key])) ** 2
    rows = []
    for key in UNITS:
        if key not in m and key not in p:
            continue
        sm = [r[key] for r in reps if key in r]
        m_std = float(np.std(sm)) if len(sm) > 2 else None
        p_std = math.sqrt(spreads[key]) if key in spreads else None
        mv, pv = m.get(key), p.get(key)
        diff = None
        if mv is not None and pv is not None:
            s2 = (m_std or 0.0) ** 2 + (p_std or 0.0) ** 2
            diff = (mv - pv) / math.sqrt(s2) if s2 > 0 else None
        unit = UNITS[key] if UNITS[key] != "m" else rec.unit
        rows.append({"quantity": LABELS[key], "key": key, "unit": unit, "measured": mv,
                     "measured_std": m_std, "predicted": pv, "predicted_std": p_std,
                     "difference_sigma": diff})
    return rows
