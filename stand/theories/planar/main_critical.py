"""Critical speeds of the main motion: the speeds at which it gains or loses stability.

Digest ch5 sections 4.2 and 4.4, on the characteristic polynomial (5.90) and
its conservative form (5.98) of :mod:`stand.theories.planar.main_charpoly` (parameters
and units there: R, Rt, h, H, d, all dimensionless).

* Damped case (h, H > 0).  a0 = Rt^2 R^8 (1 - d^2) > 0, so roots cross the
  imaginary axis only as imaginary pairs l = +-i mu, x = mu^2 a common root of
  the two halves of (5.123) (the tests check this at every crossing found).  The
  spectral abscissa is sampled on a logarithmic grid, which is then zoomed: every
  cell holding a sign change, or whose end values are within a few local
  variations of zero, is re-sampled (four rounds, 16-fold each), and every local
  extremum of the wrong sign close to zero (a peak just below 0, a dip just
  above) is refined with a bounded scalar optimiser.  So nearly coincident
  crossings -- thin unstable bands or stable windows inside one grid cell -- are
  found (checked against brute-force grids of 10^5-10^6 points); each sign change
  is then solved with ``brentq``.
* Conservative case (h = H = 0).  The same scan is run on the signed margin
  of :mod:`stand.theories.planar.main_charpoly` (> 0 iff some root x = l^2 of (5.98) is
  non-real or >= 0); ``brentq`` on it locates the boundaries to
  ~1e-12 near R ~ 1-3 (a collision is a double root x, so double precision
  limits this to about 1e-10 R^2 at higher speeds).  The touching double root
  of (5.107) at k = 1 is not reported (the margin only touches zero there), but
  the thin band it opens into for k < 1 is (Rt = 0.05, d = 0.02: (1.67091,
  1.68351)).
* Exactly one of h, H zero: never asymptotically stable (see
  :mod:`stand.theories.planar.main_charpoly`); :func:`critical_speeds` returns [] with a
  :class:`~stand.theories.planar.main_charpoly.StabilityWarning`.

Crossings are found with hysteresis, so that an abscissa lying flat within its
round-off floor (``_abscissa_tol``, very small damping at high speed) cannot
produce a chatter of crossings.

At d = 1 exactly the structural zero root is deflated; the remaining
polynomial has a real root passing through 0 at R = 1 (a1 = 0), the critical
speed R1 = 1 of (5.102) and (5.127).

Vanishing damping.  The damped critical speeds do not tend to the conservative
ones as h, H -> 0 (the destabilisation paradox): at Rt = 0.05, d = 0.02 the thin
conservative band disappears and h = H = 1e-4 gives a single critical speed
1.7206 against the conservative 1.6835; the limit depends on h/H.
"""
from __future__ import annotations

import functools
import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from stand.theories.planar.main_charpoly import (StabilityWarning, _abscissa_batch, _abscissa_tol, _check_params,
                            _companion_roots, _conservative_margin_batch, _conservative_tol,
                            _degenerate_message, charpoly_coefficients,
                            conservative_coefficients, is_stable)

__all__ = ["CriticalSpeed", "critical_speeds", "unbalance_independent_threshold",
           "high_speed_h_crit_exact", "R_MIN_DEFAULT", "R_MAX_DEFAULT"]

_EPS = np.finfo(float).eps
_RTOL = 4 * _EPS                 # the smallest rtol brentq accepts
R_MIN_DEFAULT = 0.5
R_MAX_DEFAULT = 1000.0
_GRID_PER_DECADE = 300           # base scan density (cell width ~0.8 % of R)


@dataclass(frozen=True)
class CriticalSpeed:
    """A speed at which the main motion changes stability.

    Attributes
    ----------
    R : float
        Speed ratio omega / omega_1.
    kind : str
        ``"gains"`` if the main motion is stable just above ``R`` and unstable just
        below it (stability is gained on increasing R), ``"loses"`` otherwise.
    mu : float
        Frequency (units of omega_1, rotating frame) of the roots that cross:
        l = +-i mu with x = mu^2 a common root of the two halves of (5.123)
        (damped case), or the frequency at which two roots x = -mu^2 of (5.98)
        collide (conservative case).  0 for a real root passing through l = 0
        (d = 1, R = 1).
    """

    R: float
    kind: str
    mu: float = math.nan


def _check_range(R_min, R_max):
    R_min, R_max = float(R_min), float(R_max)
    if not (0.0 < R_min < R_max and math.isfinite(R_max)):
        raise ValueError(f"need 0 < R_min < R_max < inf, got ({R_min!r}, {R_max!r})")
    return R_min, R_max


def _merge(R, F, Rn, Fn):
    R2 = np.concatenate([R, Rn])
    F2 = np.concatenate([F, Fn])
    o = np.argsort(R2, kind="stable")
    return R2[o], F2[o]


def _scan_sign_changes(f, R_min, R_max, n_grid, floor, *, depth=4, split=16):
    """Sample a continuous function ``f`` (vectorised over an array of speeds) on
    [R_min, R_max] densely enough to bracket every sign change, including nearly
    coincident pairs.

    1. Log grid of ``n_grid`` points.
    2. ``depth`` rounds of zooming: every cell that holds a sign change, or whose
       smaller end value is within 3 local cell-variations of zero (a thin band or
       window may hide inside, or more crossings share the cell), is re-sampled
       with ``split - 1`` interior points.
    3. Every interior local extremum of the wrong sign that is close to zero on
       the same scale (a peak below zero, a dip above zero) is refined by a
       bounded scalar optimiser; a point of the other sign is added if found.

    ``floor(R)`` is the magnitude below which f is round-off; cells whose values
    all lie below it are not zoomed.  Returns the sorted speeds and values, and
    the base grid with its values.
    """
    R = np.geomspace(R_min, R_max, n_grid)
    F = f(R)
    R0, F0 = R, F
    for _ in range(depth):
        if R.size < 3:
            break
        dF = np.abs(np.diff(F))
        var = dF.copy()
        var[1:] = np.maximum(var[1:], dF[:-1])
        var[:-1] = np.maximum(var[:-1], dF[1:])
        a, b = F[:-1], F[1:]
        change = (a > 0) != (b > 0)
        near = np.minimum(np.abs(a), np.abs(b)) <= 3.0 * var
        noisy = np.maximum(np.abs(a), np.abs(b)) <= floor(R[1:])
        wide = (R[1:] - R[:-1]) > 1e-9 * R[1:]
        cells = np.nonzero((change | (near & ~noisy)) & wide)[0]
        if cells.size == 0:
            break
        t = np.linspace(0.0, 1.0, split + 1)[1:-1]
        Rn = (R[cells, None] + (R[cells + 1] - R[cells])[:, None] * t).ravel()
        R, F = _merge(R, F, Rn, f(Rn))
    extra = []
    i = np.arange(1, R.size - 1)
    lo, mid, hi = F[i - 1], F[i], F[i + 1]
    var = np.maximum(np.abs(mid - lo), np.abs(hi - mid))
    noisy = np.maximum(np.maximum(np.abs(lo), np.abs(hi)), np.abs(mid)) <= floor(R[i])
    peak = (mid < 0) & (mid >= lo) & (mid >= hi)
    dip = (mid > 0) & (mid <= lo) & (mid <= hi)
    near = np.abs(mid) <= 4.0 * var
    for j in i[(peak | dip) & near & ~noisy]:
        sgn = 1.0 if F[j] < 0 else -1.0          # maximise f at a peak, minimise at a dip
        res = minimize_scalar(lambda r: -sgn * f(np.array([r]))[0],
                              bounds=(R[j - 1], R[j + 1]), method="bounded",
                              options={"xatol": 1e-12 * R[j]})
        if res.fun < 0:                          # f changes sign inside the cell
            extra.append(res.x)
    if extra:
        Rn = np.asarray(extra)
        R, F = _merge(R, F, Rn, f(Rn))
    return R, F, R0, F0


def _crossing_frequency(R, Rt, h, H, d):
    """mu of :class:`CriticalSpeed` at a crossing speed R."""
    if h == 0.0 and H == 0.0:
        C = conservative_coefficients(np.array([R]), Rt, d)
        if d == 1.0:
            C = C[:, 1:]
        x = _companion_roots(C)[0]
        w = np.sort(np.sqrt(np.abs(x)))
        if w.size < 2:
            return float(w[0])
        g = np.diff(w)
        j = int(np.argmin(g))
        return float(w[0]) if w[0] < 0.5 * g[j] else float(0.5 * (w[j] + w[j + 1]))
    A = charpoly_coefficients(np.array([R]), Rt, h, H, d)
    if d == 1.0:
        A = A[:, 1:]
    lam = _companion_roots(A)[0]
    mu = float(abs(lam[np.argmax(lam.real)].imag))
    if d == 1.0 or mu == 0.0:
        return mu
    # polish x = mu^2 on the odd half of (5.123), a1 - a3 x + a5 x^2 - a7 x^3 = 0
    a = A[0]
    x = mu * mu
    for _ in range(3):
        q = a[1] - a[3] * x + a[5] * x * x - a[7] * x ** 3
        dq = -a[3] + 2.0 * a[5] * x - 3.0 * a[7] * x * x
        if dq == 0.0 or not math.isfinite(q / dq) or x - q / dq <= 0.0:
            break
        x -= q / dq
    return math.sqrt(x)


def _crossings(f, R, F, noise, params):
    """brentq every change of sign of f on the sampled grid; kind from the signs.

    Hysteresis against round-off: a sample counts as positive if f > noise(R),
    negative if f < -noise(R), and keeps the previous verdict otherwise, so a
    function that creeps along zero cannot produce a chatter of crossings.
    """
    eta = noise(R)
    state = np.where(F > eta, 1, np.where(F < -eta, -1, 0))
    idx = np.nonzero(state)[0]
    out = []
    for p, q in zip(idx[:-1], idx[1:]):
        if state[p] == state[q]:
            continue
        r = brentq(lambda x: f(np.array([x]))[0], R[p], R[q], xtol=1e-13, rtol=_RTOL,
                   maxiter=200)
        out.append(CriticalSpeed(R=float(r), kind="gains" if state[p] > 0 else "loses",
                                 mu=_crossing_frequency(r, *params)))
    return out


def _polish_conservative(c, Rt, d):
    """Move a conservative boundary from margin = tol to margin = 0.

    Near a collision of roots x the margin grows like sqrt|R - R*|, so the root of
    margin - tol found by the scan sits (tol / slope)^2 inside the unstable side
    (up to ~1e-9 at R ~ 30).  The margin itself is bracketed by stepping towards the
    stable side and solved again; the noise of the margin (~1e-8 (1 + R)) then
    displaces the boundary by < 1e-12.
    """
    def m(x):
        return _conservative_margin_batch(np.array([x]), Rt, d)[0]

    toward = 1.0 if c.kind == "gains" else -1.0        # the stable side
    if not m(c.R) > 0.0:
        return c
    step = 1e-13 * c.R
    while step < 1e-6 * c.R:
        other = c.R + toward * step
        if m(other) < 0.0:
            lo, hi = sorted((c.R, other))
            r = brentq(m, lo, hi, xtol=1e-15, rtol=_RTOL, maxiter=200)
            return CriticalSpeed(R=float(r), kind=c.kind, mu=c.mu)
        step *= 4.0
    return c


def _n_grid(R_min, R_max, n_grid):
    if n_grid is not None:
        return max(int(n_grid), 8)
    return max(64, int(math.ceil(_GRID_PER_DECADE * math.log10(R_max / R_min))))


def critical_speeds(Rt, h, H, d, R_min=R_MIN_DEFAULT, R_max=R_MAX_DEFAULT, *, n_grid=None):
    """Critical speeds of the main motion in (R_min, R_max) (digest ch5 4.2, 4.4).

    Parameters
    ----------
    Rt : float
        R~_m (5.88), 0 < Rt < 0.5.
    h, H : float
        Weight drag and support damping, >= 0.  h = H = 0 selects the conservative
        analysis (5.98)-(5.107); otherwise the spectral abscissa of (5.90) is used.
    d : float
        Configuration parameter (5.88).
    R_min, R_max : float
        Speed range scanned (log grid).  Below resonance the main motion is
        unstable (a1 < 0, digest 4.1), so the default R_min = 0.5 starts in an
        unstable zone.
    n_grid : int or None
        Base grid size; default 300 points per decade (then zoomed, see
        :func:`_scan_sign_changes`).

    Returns
    -------
    list of CriticalSpeed
        In increasing R.  ``"gains"``: stable just above; ``"loses"``: unstable
        just above.  Whether the motion is stable at R_min is given by
        :func:`is_stable`.  Crossings are located to ~1e-12 in R (damped; less
        where the abscissa itself is tiny, e.g. ~1e-6 for H = 1000 near R = 1)
        and to ~1e-12 at R ~ 1-3 in the conservative case, where a boundary is a
        double root x and double precision limits it to about 1e-10 R^2 (e.g.
        +-3e-10 at R = 22, Rt = 0.24).

    Notes
    -----
    Damped case: scan of f(R) = abscissa(R) - tol(R) with tol the round-off floor
    (~4e-15 (1 + R)^2; moves a crossing by tol / slope, far below any printed
    digit).  Conservative case: the signed margin (notes of
    :mod:`stand.theories.planar.main_charpoly`, :func:`_conservative_margin_batch`) minus its
    noise floor 1e-7 (1 + R) (so a touching double root, (5.107) at k = 1, is not
    taken for a band); each boundary is then re-solved on the margin itself
    (:func:`_polish_conservative`).  Unstable bands narrower than the location
    accuracy cannot be resolved (the scan itself was checked down to a band
    6e-5 wide, Rt = 0.05, d = 1e-4).
    A :class:`StabilityWarning` is issued when exactly one of h, H is zero
    (see the module notes) or when the verdict somewhere rests on an abscissa within
    the round-off floor.
    """
    Rt, h, H, d = _check_params(Rt, h, H, d)
    R_min, R_max = _check_range(R_min, R_max)
    cs, caught = _critical_speeds_kept(Rt, h, H, d, R_min, R_max, _n_grid(R_min, R_max, n_grid))
    for w in caught:
        warnings.warn(w, stacklevel=2)
    return list(cs)


@functools.lru_cache(maxsize=256)
def _critical_speeds_kept(Rt, h, H, d, R_min, R_max, n):
    """:func:`critical_speeds` of checked arguments, kept per arguments with the warnings it
    issued (re-issued on every call): a deterministic list of frozen records, the same for the
    speed maps of one stand under other drives and for the conservative comparisons (which
    depend on Rt and d only)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        cs = tuple(_critical_speeds(Rt, h, H, d, R_min, R_max, n))
    return cs, tuple(w.message for w in caught)


def _critical_speeds(Rt, h, H, d, R_min, R_max, n):
    if h == 0.0 and H == 0.0:
        def f(R):
            return _conservative_margin_batch(R, Rt, d) - _conservative_tol(R)
        Rg, Fg, _, _ = _scan_sign_changes(f, R_min, R_max, n, _conservative_tol)
        cs = _crossings(f, Rg, Fg, lambda R: 0.5 * _conservative_tol(R), (Rt, h, H, d))
        return [_polish_conservative(c, Rt, d) for c in cs]

    if h == 0.0 or H == 0.0:
        warnings.warn(StabilityWarning(_degenerate_message(h, H, "critical_speeds")
                                       + "; no critical speed returned"), stacklevel=2)
        return []

    def f(R):
        return _abscissa_batch(R, Rt, h, H, d) - _abscissa_tol(R)

    Rg, Fg, R0, F0 = _scan_sign_changes(f, R_min, R_max, n, _abscissa_tol)
    flat = np.abs(F0 + _abscissa_tol(R0)) <= _abscissa_tol(R0)
    if np.any(flat):
        r = R0[flat]
        warnings.warn(StabilityWarning(
            f"critical_speeds: the spectral abscissa is within round-off of zero for R in "
            f"[{r.min():.6g}, {r.max():.6g}] (damping too small to resolve there); those "
            f"speeds count as stable"), stacklevel=2)
    return _crossings(f, Rg, Fg, lambda R: 0.5 * _abscissa_tol(R), (Rt, h, H, d))


def _last_gain(cs, stable_at_end):
    """The last stabilising crossing, or inf if the motion is unstable at the end."""
    if not stable_at_end:
        return math.inf
    for c in reversed(cs):
        if c.kind == "gains":
            return c.R
    return -math.inf      # stable over the whole range (cannot happen from R_min < 1)


def unbalance_independent_threshold(Rt, h, H, *, R_min=R_MIN_DEFAULT, R_max=R_MAX_DEFAULT,
                                    n_d=41, n_grid=None):
    """Speed above which the main motion is stable for every unbalance (digest 4.2, 4.4).

    sup over d in [0, 1] of the last stabilising critical speed.  Since d ranges
    over all configurations of any number of weights (5.88), this is the speed
    above which autobalancing holds whatever the unbalance.  The book's
    R_omega1max (5.127) assumes the worst case is d = 0; for low damping it is not
    (digest 4.4 "Warning for low damping": d = 1 gives the sup).

    Parameters
    ----------
    Rt, h, H : float
    R_min, R_max : float
        Speed range of each scan.
    n_d : int
        Size of the d grid (uniform in d, plus points clustered at d = 1); the best
        grid point is refined by a bounded scalar search over its neighbours.
    n_grid : int or None
        Passed to :func:`critical_speeds`.

    Returns
    -------
    float
        ``inf`` if for some d the main motion is unstable at R_max (e.g.
        h < H sqrt(Rt), (5.96), or exactly one of h, H zero).
    """
    Rt, h, H, _ = _check_params(Rt, h, H, 0.0)
    R_min, R_max = _check_range(R_min, R_max)
    return _threshold(Rt, h, H, R_min, R_max, int(n_d), None if n_grid is None else int(n_grid))


@functools.lru_cache(maxsize=64)
def _threshold(Rt, h, H, R_min, R_max, n_d, n_grid):
    """:func:`unbalance_independent_threshold` of checked arguments, kept per arguments (a
    deterministic float; it does not depend on the unbalance nor the drive, so the speed maps
    of one stand under other unbalances or drives reuse it instead of its ~50 scans)."""
    def last(d):
        d = min(max(float(d), 0.0), 1.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", StabilityWarning)
            cs = critical_speeds(Rt, h, H, d, R_min, R_max, n_grid=n_grid)
            ok = is_stable(R_max, Rt, h, H, d)
        return _last_gain(cs, ok)

    ds = np.unique(np.concatenate([np.linspace(0.0, 1.0, max(int(n_d), 3)),
                                   1.0 - np.geomspace(1e-4, 0.05, 8)]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", StabilityWarning)
        if not all(is_stable(R_max, Rt, h, H, d) for d in ds):
            return math.inf
    # the grid's best d from every 4th d (and those near 1), then the d between the evaluated
    # neighbours of the best, until both are evaluated (unimodal on that spacing: as scanning all)
    vals = np.full(ds.size, np.nan)
    todo = np.nonzero((np.arange(ds.size) % 4 == 0) | (ds > 0.95) | (ds == ds[-1]))[0]
    while todo.size:
        vals[todo] = [last(ds[i]) for i in todo]
        j = int(np.nanargmax(vals))
        done = np.nonzero(~np.isnan(vals))[0]
        a, b = done[done < j], done[done > j]
        todo = np.arange(a[-1] + 1 if a.size else 0, b[0] if b.size else ds.size)
        todo = todo[np.isnan(vals[todo])]
    best = vals[j]
    lo, hi = ds[max(j - 1, 0)], ds[min(j + 1, ds.size - 1)]
    if hi > lo:
        res = minimize_scalar(lambda x: -last(x), bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-7})
        best = max(best, -res.fun)
    return float(best)


def high_speed_h_crit_exact(Rt, H, d, R=1000.0, *, h_max=None):
    """Exact ball-drag threshold for stability at a fixed high speed (cf. (5.96)).

    The largest h at which the spectral abscissa of (5.90) at speed ``R`` changes
    sign from positive (h below) to negative (h above).  For d = 0 and R >= 100
    it equals H sqrt(Rt) to 0.3 % (digest 4.2: 0.16771 at Rt = 0.05, H = 0.75);
    for d > 0 it is lower (0.0773 at d = 0.5, 0.0119 at d = 0.9).

    Parameters
    ----------
    Rt, H : float
        H > 0.
    d : float
    R : float
        Speed ratio (>> 1).
    h_max : float or None
        Upper end of the h search (default 10 (1 + H)).

    Returns
    -------
    float
        0.0 if the main motion is stable at ``R`` for every h scanned.
    """
    Rt, _, H, d = _check_params(Rt, 0.0, H, d)
    if H <= 0.0:
        raise ValueError("high_speed_h_crit_exact: needs H > 0")
    R = float(R)
    hi = 10.0 * (1.0 + H) if h_max is None else float(h_max)
    hs = np.geomspace(1e-6 * max(H * math.sqrt(Rt), 1e-6), hi, 400)
    tol = _abscissa_tol(R)

    def g(hh):
        return _abscissa_batch(np.array([R]), Rt, hh, H, d)[0] - tol

    vals = np.array([g(x) for x in hs])
    idx = np.nonzero((vals[:-1] > 0) & (vals[1:] <= 0))[0]
    if idx.size == 0:
        return 0.0 if vals[-1] <= 0 else math.inf
    c = idx[-1]
    return float(brentq(g, hs[c], hs[c + 1], xtol=1e-14, rtol=_RTOL))
