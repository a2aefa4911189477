"""The blurred-spot fit of :mod:`vision.blur` as loops that numba compiles.

:func:`path` gives the path's points, weights and derivatives;
:func:`_normal_equations_loops` the residual sum of squares, ``J^T J`` (9 x 9), ``J^T r``
(9) and the sandwich's meat over the fitted pixels, clipped pixels censored (module
docstring of :mod:`vision.blur`), by loops over the pixels and, for each, over the path
points within a few sigma of it (with the matrices: ~20 us for a 330-pixel blob, ~70 us for
a 900-pixel 30-60 px arc); :func:`fit_loops` the whole Levenberg-Marquardt fit with its
score test and the centre's sandwich covariance; :func:`compiled_fit` compiles them.

The numpy twin of the normal equations (matrix products over the patch: the same numbers
to rounding, ``tests/test_video_track.py``, 5-10x slower) and the plain-Python fit that
uses it, for when numba is missing or ``STAND_DISABLE_JIT=1`` / ``NUMBA_DISABLE_JIT=1``,
are :mod:`vision._blur_numpy`.  This module imports nothing of ``vision`` but
:mod:`vision._numba` (which compiles nothing): numba's cache is invalidated per source
file, so the compiled code lives in this one file.
"""
from __future__ import annotations

import math

import numpy as np

from ._numba import cache_missing, numba_or_none, once

__all__ = ["fit_loops", "compiled_fit", "compiled_available", "compile_needed", "path",
           "n_points", "CUTOFF_SIGMAS"]

NP = 9                  #: parameters (m_u, m_v, h_u, h_v, kappa, a2, a3, ln A, ln s)
CUTOFF_SIGMAS = 5.0     #: a point contributes to pixels within this many sigma (exp(-12.5) ~ 4e-6)
_SQRT2 = math.sqrt(2.0)
_SQRT2PI = math.sqrt(2.0 * math.pi)



#: Gauss-Legendre nodes on [-1, 1] and weights (sum 1) of 4, 5 and 6 points, one after the
#: other (:func:`path` for a short path, :func:`n_points`)
_GL = [np.polynomial.legendre.leggauss(m) for m in (4, 5, 6)]
_GL_X = np.concatenate([x for x, _ in _GL])
_GL_W = np.concatenate([w / 2.0 for _, w in _GL])


def path(mu, mv, hu, hv, kap, a2, a3, n):
    """Path points, quadrature weights and their derivatives (plain loops, also compiled by
    numba; ``n`` >= 4: 4-6 the Gauss-Legendre nodes, 7 and more equal steps with Gregory's
    end corrections, :func:`n_points`).

    The point at time fraction x in [-1, 1] (the node, or ``n`` equal steps, ends included) is
    ``m + (T(x) + a2 P2(x)) h + (N(x) + a3 P3(x)) J h`` with beta = kappa l, l = |h|,
    J = +90 deg turn, T = sin(beta x)/beta, N = (sin(beta)/beta - cos(beta x))/beta
    (series near beta = 0), P2 = x^2 - 1/3, P3 = x^3 - 3x/5 (zero mean: m stays the
    mean position).

    Returns
    -------
    u, v : (n,) [px];  w : (n,) weights (sum 1: Gauss-Legendre's, or Gregory's end
    corrections);
    pu, pv : (5, n) d(u, v)/d(h_u, h_v, kappa, a2, a3).
    """
    u = np.empty(n)
    v = np.empty(n)
    w = np.empty(n)
    pu = np.empty((5, n))
    pv = np.empty((5, n))
    ell = math.sqrt(hu * hu + hv * hv)
    beta = kap * ell
    small = abs(beta) < 1e-3
    sb = math.sin(beta)
    cb = math.cos(beta)
    # d beta / d(hu, hv) = kappa h / l (the products below stay finite as l -> 0)
    bu = kap * hu / ell if ell > 0 else 0.0
    bv = kap * hv / ell if ell > 0 else 0.0
    total = 0.0
    gl = n < 7
    off = (n - 4) * (n + 3) // 2        # the first of the n nodes in _GL_X: 0, 4, 9
    for k in range(n):
        x = _GL_X[off + k] if gl else -1.0 + 2.0 * k / (n - 1)
        x2 = x * x
        if small:
            b2 = beta * beta
            T = x * (1.0 - b2 * x2 / 6.0)
            N = beta * (0.5 * x2 - 1.0 / 6.0) + beta * b2 * (1.0 / 120.0 - x2 * x2 / 24.0)
            Tb = -beta * x * x2 / 3.0
            Nb = (0.5 * x2 - 1.0 / 6.0) + 3.0 * b2 * (1.0 / 120.0 - x2 * x2 / 24.0)
        else:
            sx = math.sin(beta * x)
            cx = math.cos(beta * x)
            T = sx / beta
            N = (sb / beta - cx) / beta
            Tb = (x * cx * beta - sx) / (beta * beta)
            Nb = ((cb * beta - sb) / (beta * beta) + x * sx) / beta - N / beta
        P2 = x2 - 1.0 / 3.0
        P3 = x * (x2 - 0.6)
        T += a2 * P2
        N += a3 * P3
        u[k] = mu + T * hu - N * hv
        v[k] = mv + T * hv + N * hu
        gu = Tb * hu - Nb * hv          # d u / d beta
        gv = Tb * hv + Nb * hu          # d v / d beta
        pu[0, k] = T + gu * bu
        pu[1, k] = -N + gu * bv
        pu[2, k] = gu * ell
        pu[3, k] = P2 * hu
        pu[4, k] = -P3 * hv
        pv[0, k] = N + gv * bu
        pv[1, k] = T + gv * bv
        pv[2, k] = gv * ell
        pv[3, k] = P2 * hv
        pv[4, k] = P3 * hu
        # Gregory's end corrections of the trapezoidal rule: 3/8, 7/6, 23/24, 1, ...
        e = min(k, n - 1 - k)
        w[k] = 3.0 / 8.0 if e == 0 else (7.0 / 6.0 if e == 1 else (23.0 / 24.0 if e == 2 else 1.0))
        if gl:
            w[k] = _GL_W[off + k]
        total += w[k]
    for k in range(n):
        w[k] /= total
    return u, v, w, pu, pv


def _profile_row(c, s, lo, hi, wk, k, g, dg, sg):
    """Pixel-integrated profile of point ``k`` at ``c`` [px] over pixels lo..hi, times the
    weight ``wk``, into column ``k`` of ``g`` (pixels x points); its derivatives with respect
    to the point (``dg``) and to ``s`` (``sg``).  Pixel p covers [p - 1/2, p + 1/2]: each
    edge's erf and exp serve the two pixels it separates; the exps by the recurrences
    exp(-(b + d)^2 / 2) = exp(-b^2 / 2) exp(-b d) exp(-d^2 / 2), d = 1 / s, and
    exp(-(b + d) d) = exp(-b d) exp(-d^2)."""
    k_ = _SQRT2PI * s
    d = 1.0 / s
    e2 = 1.0 / (_SQRT2 * s)
    b = (lo - 0.5 - c) * d
    eb = math.exp(-0.5 * b * b)
    Eb = math.erf((lo - 0.5 - c) * e2)
    f = math.exp(-b * d)            # exp(-b d) at the current edge
    h = math.exp(-0.5 * d * d)
    hh = h * h
    for p in range(lo, hi + 1):
        a = b + d
        ea = eb * f * h
        f *= hh
        Ea = math.erf((p + 0.5 - c) * e2)
        gg = 0.5 * k_ * (Ea - Eb)
        g[p, k] = gg * wk
        dg[p, k] = (eb - ea) * wk
        sg[p, k] = (gg * d - (ea * a - eb * b)) * wk
        b, eb, Eb = a, ea, Ea


def _normal_equations_loops(patch, pi, pj, clipped, level, sat_eff, p, n, want_jac, want_meat,
                            JTJ, g, MJ):
    """Plain loops (compiled by numba).  Returns the residual sum of squares; fills
    ``JTJ`` (9, 9), ``g`` (9) and, when ``want_meat``, ``MJ`` (9, 9) when ``want_jac``.

    A pixel sums over the points from the last first-reaching one of its row and column to
    the first last-reaching one: the profiles are 0 beyond a point's reach, so the points
    in that range that do not reach the pixel add exact zeros (the numbers of a test of
    every point's reach, without its branches)."""
    H, W = patch.shape
    u, v, w, pu, pv = path(p[0], p[1], p[2], p[3], p[4], p[5], p[6], n)
    A = math.exp(p[7])
    s = math.exp(p[8])
    n = u.shape[0]
    P = pi.shape[0]
    cut = CUTOFF_SIGMAS * s + 1.0
    # 1-D profiles of every point over the patch's columns and rows (pixels x points: a
    # pixel's sum over the points reads contiguous memory)
    gu, du_, su = np.zeros((W, n)), np.zeros((W, n)), np.zeros((W, n))
    gv, dv_, sv = np.zeros((H, n)), np.zeros((H, n)), np.zeros((H, n))
    # each column's and row's first and last point that reaches it
    cfirst, clast = np.full(W, n, np.int64), np.full(W, -1, np.int64)
    rfirst, rlast = np.full(H, n, np.int64), np.full(H, -1, np.int64)
    for k in range(n):
        jlo = max(int(math.floor(u[k] - cut)), 0)
        jhi = min(int(math.ceil(u[k] + cut)), W - 1)
        ilo = max(int(math.floor(v[k] - cut)), 0)
        ihi = min(int(math.ceil(v[k] + cut)), H - 1)
        _profile_row(u[k], s, jlo, jhi, w[k], k, gu, du_, su)
        _profile_row(v[k], s, ilo, ihi, 1.0, k, gv, dv_, sv)
        for c in range(jlo, jhi + 1):       # (k increases: the first is set once)
            cfirst[c] = min(cfirst[c], k)
            clast[c] = k
        for c in range(ilo, ihi + 1):
            rfirst[c] = min(rfirst[c], k)
            rlast[c] = k
    cost = 0.0
    Jm = np.empty((NP, P if want_jac else 0))
    rr = np.empty(P if want_jac else 0)
    na = 0
    for q in range(P):
        i = pi[q]
        j = pj[q]
        k0 = max(rfirst[i], cfirst[j])
        k1 = min(rlast[i], clast[j]) + 1
        # a clipped pixel the model already reaches is inactive (residual 0, no gradient):
        # its model value first; every other pixel's value and gradient in one pass
        m = 0.0
        if clipped[q] or not want_jac:
            for k in range(k0, k1):
                m += gv[i, k] * gu[j, k]
            if clipped[q] and level + A * m >= sat_eff:
                continue
            if not want_jac:
                r = (sat_eff if clipped[q] else patch[i, j]) - level - A * m
                cost += r * r
                continue
        m = 0.0         # the row's sums in locals (registers), in the order of the points
        j0 = j1 = j2 = j3 = j4 = j5 = j6 = j8 = 0.0
        for k in range(k0, k1):
            gvk = gv[i, k]
            guk = gu[j, k]
            m += gvk * guk
            t1 = gvk * du_[j, k]
            t2 = dv_[i, k] * guk
            j0 += t1
            j1 += t2
            j2 += pu[0, k] * t1 + pv[0, k] * t2
            j3 += pu[1, k] * t1 + pv[1, k] * t2
            j4 += pu[2, k] * t1 + pv[2, k] * t2
            j5 += pu[3, k] * t1 + pv[3, k] * t2
            j6 += pu[4, k] * t1 + pv[4, k] * t2
            j8 += gvk * su[j, k] + sv[i, k] * guk
        full = level + A * m
        r = (sat_eff - full) if clipped[q] else (patch[i, j] - full)
        cost += r * r
        Jm[0, na], Jm[1, na], Jm[2, na] = A * j0, A * j1, A * j2
        Jm[3, na], Jm[4, na], Jm[5, na], Jm[6, na] = A * j3, A * j4, A * j5, A * j6
        Jm[7, na], Jm[8, na] = A * m, j8 * (A * s)      # d / d ln A, d / d ln s
        rr[na] = r
        na += 1
    if want_jac:
        _sums(Jm, rr, na, want_meat, JTJ, g, MJ)
    return cost


def _sums(Jm, rr, na, want_meat, JTJ, g, MJ):
    """J^T J, J^T r and (``want_meat``) sum r^2 J J^T of the first ``na`` columns of ``Jm``
    (9 x pixels) and of ``rr``, as dot products (:func:`_dot`)."""
    for a in range(NP):
        g[a] = _dot(Jm[a], rr, na)
        for b in range(a + 1):
            JTJ[a, b] = JTJ[b, a] = _dot(Jm[a], Jm[b], na)
    if want_meat:
        for q in range(na):          # the rows r J: sum r^2 J J^T = (r J)^T (r J)
            r = rr[q]
            for a in range(NP):
                Jm[a, q] *= r
        for a in range(NP):
            for b in range(a + 1):
                MJ[a, b] = MJ[b, a] = _dot(Jm[a], Jm[b], na)


def _dot(x, y, n):
    """sum x[:n] y[:n] (compiled reassociating: ~3x faster than one chain of additions)."""
    s = 0.0
    for q in range(n):
        s += x[q] * y[q]
    return s


#: the plain Python functions, kept before any of them is replaced by its compiled version
#: (:func:`vision._blur_numpy.python_fit` runs them)
_PY = {}
#: the normal equations :func:`_evaluate` calls: the compiled loops once :func:`compiled_fit`
#: has run (the plain Python copy of :mod:`vision._blur_numpy` binds its numpy twin instead)
_EVALUATE = None


def compiled_available() -> bool:
    """True when the numba kernel can be used (numba installed and not disabled)."""
    return _compiled_kernel() is not None


@once
def _compiled_kernel():
    numba = numba_or_none()
    if numba is None:
        return None
    jit = numba.njit(cache=True, error_model="numpy", nogil=True)
    # the dot products alone reassociating (SIMD partial sums; no assumption about NaN /
    # inf, no fused multiply-adds): the kernel's other sums keep their order
    fast = numba.njit(cache=True, error_model="numpy", nogil=True, fastmath={"reassoc"})
    globals()["path"] = jit(path)      # the kernel calls the compiled helpers
    globals()["_profile_row"] = jit(_profile_row)
    globals()["_dot"] = fast(_dot)
    globals()["_sums"] = jit(_sums)
    return jit(_normal_equations_loops)


# ---------------------------------------------------------------- Levenberg-Marquardt
def n_points(ell, s, min_sigma, max_points):
    """Points along a path of half-length ``ell`` [px] and spot sigma ``s`` [px] (at least
    ``min_sigma``): at most one sigma apart, at least 7 (Gregory's end weights); a short
    path (l <= 2.5 s) 4-6 Gauss-Legendre nodes instead (:func:`path`), each band's nodes
    more accurate than the 7 steps they replace (:mod:`vision.blur`, Model)."""
    L = ell / max(s, min_sigma)
    if L <= 1.0:
        return 4
    if L <= 1.5:
        return 5
    if L <= 2.5:
        return 6
    return int(min(max(math.ceil(2.0 * L) + 1, 7), max_points))


def _bound(q, size, c):
    """Parameters inside their domain, in place (``size``: the patch's diagonal [px];
    ``c`` = (min_sigma, max_sweep, max_shape)): min_sigma <= s <= size, l <= size,
    A <= e^30 DN, |kappa| <= min(max_sweep / l, 1 / s) (a bend tighter than the spot is
    not resolved: a curl smaller than the spot looks like a wider spot), |a2|, |a3| <=
    max_shape."""
    q[8] = min(max(q[8], math.log(c[0])), math.log(size))
    q[7] = min(q[7], 30.0)
    ell = math.sqrt(q[2] * q[2] + q[3] * q[3])
    if ell > size:
        q[2] *= size / ell
        q[3] *= size / ell
        ell = size
    kmax = min(c[1] / max(ell, 1e-12), math.exp(-q[8]))
    if abs(q[4]) > kmax:
        q[4] = kmax if q[4] > 0 else -kmax
    q[5] = min(max(q[5], -c[2]), c[2])
    q[6] = min(max(q[6], -c[2]), c[2])


def _evaluate(patch, pi, pj, clipped, level, sat_eff, p, c, JTJ, g, MJ):
    """Cost, and J^T J, J^T r, sum r^2 J J^T into the arrays, at ``p``."""
    n = n_points(math.sqrt(p[2] * p[2] + p[3] * p[3]), math.exp(p[8]), c[0], c[3])
    yes = n > 0            # (a computed bool: the same compiled kernel as a call from Python)
    return _EVALUATE(patch, pi, pj, clipped, level, sat_eff, p, n, yes, yes, JTJ, g, MJ)


def _lm(patch, pi, pj, clipped, level, sat_eff, p, cost, JTJ, g, MJ, free, size, c, tol,
        max_iter):
    """Levenberg-Marquardt over the ``free`` parameters from ``p`` (with its cost and
    matrices, updated in place).  Returns (cost, iterations, converged): converged when
    a step moves the centre < tol[0] px and lowers the cost by <= tol[1] of it, or no
    better point lies within tol[0] px.  That last step is taken unevaluated (its cost the
    linear model's): one evaluation of ~6 saved per fit; the matrices (the covariance, the
    score test) stay those of the point one step before (stds within a few %)."""
    lam = 1e-3
    q, rhs, ng = np.empty(NP), np.empty(NP), np.empty(NP)
    A, nJ, nM = np.empty((NP, NP)), np.empty((NP, NP)), np.empty((NP, NP))
    it = 0
    converged = False
    while it < max_iter:
        it += 1
        for a in range(NP):
            for b in range(NP):
                A[a, b] = JTJ[a, b] if (free[a] and free[b]) else 0.0
            if free[a]:
                d = JTJ[a, a]
                A[a, a] += lam * (d if d > 0 else 1.0)
                rhs[a] = g[a]
            else:
                A[a, a] = 1.0
                rhs[a] = 0.0
        step = rhs.reshape(NP, 1)
        _cholesky_solve(A, step)            # A is positive definite (damped)
        for a in range(NP):
            q[a] = p[a] + step[a, 0]
        _bound(q, size, c)
        moved = math.sqrt((q[0] - p[0]) ** 2 + (q[1] - p[1]) ** 2)
        if moved < tol[0]:
            # the last step taken without evaluating it: the cost's decrease the linear
            # model predicts, 2 d.g - d^T B d, against the stop's (the matrices stay p's)
            gain = 0.0
            for a in range(NP):
                if free[a]:
                    da = q[a] - p[a]
                    gain += 2.0 * da * g[a]
                    for b in range(NP):
                        if free[b]:
                            gain -= da * JTJ[a, b] * (q[b] - p[b])
            if 0.0 <= gain <= tol[1] * (cost - gain):
                _copy(p, q)
                cost -= gain
                converged = True
                break
        # the trial's Jacobian too: an accepted step (the usual case) needs it next
        new_cost = _evaluate(patch, pi, pj, clipped, level, sat_eff, q, c, nJ, ng, nM)
        if new_cost <= cost:
            gain = cost - new_cost
            _copy(p, q)
            _copy(JTJ, nJ)
            _copy(g, ng)
            _copy(MJ, nM)
            cost = new_cost
            lam = max(lam / 5.0, 1e-9)
            if moved < tol[0] and gain <= tol[1] * cost:
                converged = True
                break
        else:
            lam *= 4.0
            if lam > 1e8 or moved < tol[0]:
                converged = moved < tol[0]     # no better point nearby: at the minimum
                break
    return cost, it, converged


def _copy(dst, src):
    """``dst[...] = src`` for C-contiguous arrays of one size, by a loop (a slice assignment
    makes numba compile its shape-mismatch message: seconds of string code)."""
    d, s = dst.reshape(dst.size), src.reshape(src.size)
    for i in range(d.size):
        d[i] = s[i]


def _cholesky_solve(A, B):
    """Solve A X = B for a symmetric positive (semi-)definite A (n x n, small) by Cholesky,
    with a ridge of 1e-12 of the largest diagonal so that a singular A (a direction the data
    do not fix) gives the minimum-norm-like solution instead of failing; B (n, m) is
    overwritten with X.  Plain loops: no LAPACK (quick to compile)."""
    n = A.shape[0]
    L = np.zeros((n, n))
    top = 0.0
    for i in range(n):
        top = max(top, A[i, i])
    ridge = 1e-12 * top if top > 0 else 1e-300
    for i in range(n):
        for j in range(i + 1):
            s = A[i, j] + (ridge if i == j else 0.0)
            for k in range(j):
                s -= L[i, k] * L[j, k]
            if i == j:
                L[i, i] = math.sqrt(s) if s > 0 else math.sqrt(ridge)
            else:
                L[i, j] = s / L[j, j]
    for c in range(B.shape[1]):
        for i in range(n):
            s = B[i, c]
            for k in range(i):
                s -= L[i, k] * B[k, c]
            B[i, c] = s / L[i, i]
        for i in range(n - 1, -1, -1):
            s = B[i, c]
            for k in range(i + 1, n):
                s -= L[k, i] * B[k, c]
            B[i, c] = s / L[i, i]


def _where(free, value):
    """The indices a (increasing) with ``free[a] == value``."""
    n = 0
    for a in range(NP):
        n += free[a] == value
    out = np.empty(n, np.int64)
    k = 0
    for a in range(NP):
        if free[a] == value:
            out[k] = a
            k += 1
    return out


def _score(JTJ, g, MJ, free):
    """Robust score (Lagrange multiplier) statistic of freeing the held parameters at a
    fit with them held (:func:`vision.blur.fit_blurred_spot`): ``s^T (L M L^T)^-1 s`` with
    the efficient score ``s = g_c - B_cf B_ff^-1 g_f`` and ``L = [-B_cf B_ff^-1, 1]``
    (B = J^T J, g = J^T r, M = sum r^2 J J^T; c the held, f the fitted parameters; two
    held parameters)."""
    f = _where(free, True)
    h = _where(free, False)
    nf, nc = f.size, h.size
    Bff = np.empty((nf, nf))
    KT = np.empty((nf, nc))             # Bff^-1 Bfc = K^T
    for a in range(nf):
        for b in range(nf):
            Bff[a, b] = JTJ[f[a], f[b]]
        for b in range(nc):
            KT[a, b] = JTJ[f[a], h[b]]
    _cholesky_solve(Bff, KT)
    # s = g_c - K g_f;  rows of L: [-K, 1] in the order (f, h)
    s = np.empty(nc)
    Lr = np.zeros((nc, NP))
    for c in range(nc):
        v = g[h[c]]
        for a in range(nf):
            v -= KT[a, c] * g[f[a]]
            Lr[c, f[a]] = -KT[a, c]
        Lr[c, h[c]] = 1.0
        s[c] = v
    V = np.zeros((nc, nc))
    for c in range(nc):
        for d in range(nc):
            v = 0.0
            for a in range(NP):
                if Lr[c, a] == 0.0:
                    continue
                for b in range(NP):
                    v += Lr[c, a] * MJ[a, b] * Lr[d, b]
            V[c, d] = v
    S = s.reshape(nc, 1).copy()
    _cholesky_solve(V, S)
    out = 0.0
    for c in range(nc):
        out += s[c] * S[c, 0]
    return out


def _centre_cov(JTJ, MJ, free):
    """(var m_u, var m_v) of the sandwich ``B^-1 M B^-1`` over the ``free`` parameters
    (B = J^T J, M = sum r^2 J J^T; m_u, m_v always free), unscaled: B is scaled to a
    unit diagonal first, so the Cholesky solve's ridge stays at rounding level."""
    f = _where(free, True)
    nf = f.size
    d = np.empty(nf)
    for a in range(nf):
        x = JTJ[f[a], f[a]]
        d[a] = 1.0 / math.sqrt(x) if x > 0 else 1.0
    B = np.empty((nf, nf))
    X = np.zeros((nf, 2))
    for a in range(nf):
        for b in range(nf):
            B[a, b] = JTJ[f[a], f[b]] * d[a] * d[b]
    X[0, 0] = d[0]
    X[1, 1] = d[1]
    _cholesky_solve(B, X)               # rows m_u, m_v of B^-1 (scaled back below)
    out = np.zeros(2)
    for c in range(2):
        for a in range(nf):
            for b in range(nf):
                out[c] += X[a, c] * d[a] * MJ[f[a], f[b]] * X[b, c] * d[b]
    return out


def fit_loops(patch, pi, pj, clipped, level, sat_eff, starts, size, c, tol, max_iter,
              score_limit):
    """The whole fit after the starting values: the best start by cost; LM with the
    path's shape terms (a2, a3; indices 5, 6) held at 0; the score test; LM with them
    free when it exceeds ``score_limit``; the centre's covariance (:func:`_centre_cov`).

    Returns
    -------
    p (9,), cost, (var m_u, var m_v) unscaled, free (bool 9), iterations, converged
    """
    JTJ, MJ = np.empty((NP, NP)), np.empty((NP, NP))
    g, p, q = np.empty(NP), np.empty(NP), np.empty(NP)
    cost, best = np.inf, 0
    # the first row with its matrices, the others' costs alone: the matrices again only when
    # one of those is better (the first row: the warm start in a video, usually the best)
    for k in range(starts.shape[0]):
        for a in range(NP):
            q[a] = starts[k, a] if a != 5 and a != 6 else 0.0
        if k == 0:
            ck = _evaluate(patch, pi, pj, clipped, level, sat_eff, q, c, JTJ, g, MJ)
        else:
            n = n_points(math.sqrt(q[2] * q[2] + q[3] * q[3]), math.exp(q[8]), c[0], c[3])
            ck = _EVALUATE(patch, pi, pj, clipped, level, sat_eff, q, n, n < 0, n < 0, JTJ, g,
                           MJ)
        if k == 0 or ck < cost or cost != cost:     # (a NaN first cost is not kept)
            cost, best = ck, k
            _copy(p, q)
    if best > 0:
        cost = _evaluate(patch, pi, pj, clipped, level, sat_eff, p, c, JTJ, g, MJ)
    free = np.ones(NP, np.bool_)
    free[5] = free[6] = False
    cost, it, converged = _lm(patch, pi, pj, clipped, level, sat_eff, p, cost, JTJ, g, MJ,
                              free, size, c, tol, max_iter)
    if converged and _score(JTJ, g, MJ, free) > score_limit:
        free[5] = free[6] = True
        cost, it2, converged = _lm(patch, pi, pj, clipped, level, sat_eff, p, cost, JTJ, g,
                                   MJ, free, size, c, tol, max_iter)
        it += it2
    return p, cost, _centre_cov(JTJ, MJ, free), free, it, converged


_PY.update({name: globals()[name] for name in ("path", "n_points", "_bound", "_evaluate", "_copy",
                                                 "_cholesky_solve", "_lm", "_where", "_score",
                                                 "_centre_cov")})




@once
def compiled_fit():
    """:func:`fit_loops` compiled by numba (numba imported, the helpers replaced by their
    compiled versions and :func:`_evaluate` bound to the compiled normal equations on the
    first call, ``cache=True``), or None when numba is missing or disabled."""
    kern = _compiled_kernel()
    if kern is None:
        return None
    jit = numba_or_none().njit(cache=True, error_model="numpy", nogil=True)
    mod = globals()
    mod["_EVALUATE"] = kern
    for name in ("n_points", "_bound", "_evaluate", "_copy", "_cholesky_solve", "_lm",
                 "_where", "_score", "_centre_cov"):
        mod[name] = jit(mod[name])
    return jit(fit_loops)   # nogil: the read-ahead thread decodes meanwhile


def compile_needed() -> bool:
    """True when the first compiled fit will compile (numba available, no cache file of
    :func:`fit_loops` yet): about 10 s, once per install (:func:`vision._numba.cache_missing`)."""
    return cache_missing(compiled_fit)
