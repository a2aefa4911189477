"""Gauss-Newton for sums of complex exponentials, with the structured normal equations.

The model z[m] = c_0 + sum_k c_k p_k[m], p_k[m] = e^{2 pi i nu_k m} (m the sample
index, centred; nu in cycles per sample) has the derivatives d/d nu_k =
2 pi i m c_k p_k, d/d Re c_j = col_j, d/d Im c_j = i col_j.  The real normal
matrix Re(D^H W D) therefore needs only the sums sum w m^p conj(col_j) col_k
(p = 0, 1, 2) -- constants on the diagonal, one length-N product per pair of
lines off it -- and the gradient Re(D^H W r) the sums sum w m^p conj(p_k) r:
a few dot products per iteration, never an N x P Jacobian.  The phasors are an
outer product of two short exponentials (BLOCK and N / BLOCK of them).  Used
by :mod:`dsp.lines` (the one line estimator of ``dsp``), :mod:`dsp.line_fit` and
:mod:`dsp.line_fast`.
"""
from __future__ import annotations

import functools
import math

import numpy as np

from ._line_kernel import (BLOCK, HANN, MIN_LINE_SNR, dirichlet_core, fit_acceptable,
                           hann_delta, power_sums as _power_sums, step_is_last)

__all__ = ["phasor", "columns", "wls", "Sums", "normal_matrix", "gauss_newton", "peak_nu",
           "hann_peak_nu", "hann_delta", "dirichlet_sums", "dirichlet_core", "windowed_sums", "windowed_kernel",
           "projection_fit"]

MAX_ITER = 30              #: Gauss-Newton iterations at most
LOBE = 2.0                 #: half-width of the Hann main lobe, in frequency resolutions 1/T
TWO_PI = 2.0 * math.pi


def phasor(nu, m0, n):
    """e^{2 pi i nu (m0 + k)}, k = 0..n-1 (outer product of two short exponentials)."""
    nb = -(-n // BLOCK)
    outer = np.exp(2j * math.pi * nu * (m0 + BLOCK * np.arange(nb)))
    inner = np.exp(2j * math.pi * nu * np.arange(BLOCK))
    return (outer[:, None] * inner[None, :]).ravel()[:n]


def columns(m0, n, nus, offset):
    """The model's columns: a constant (with ``offset``), then one phasor per line."""
    cols = [np.ones(n, dtype=complex)] if offset else []
    return cols + [phasor(nu, m0, n) for nu in nus]


def wls(cols, z, w, G0=None):
    """Weighted linear least squares: the complex coefficients of ``cols`` (normal equations
    with their Gram matrix ``G0`` = sum w conj(col_j) col_k, computed when not given)."""
    if not cols:
        return np.zeros(0, complex)
    if G0 is None:
        G0 = Sums(np.zeros(z.size), w).gram(cols, powers=1)[0]
    wz = w * z
    rhs = np.array([np.vdot(col, wz) for col in cols])
    try:
        return np.linalg.solve(G0, rhs)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(G0, rhs, rcond=None)[0]


@functools.lru_cache(maxsize=16)
def _hann(n):
    """The Hann window of ``n`` samples, symmetric about the record's middle (what
    ``dsp.lines.window_weights(n, "hann")`` copies), cached and read-only."""
    w = 0.5 - 0.5 * np.cos(2.0 * math.pi * (np.arange(n) + 0.5) / n)
    w.flags.writeable = False
    return w


def dirichlet_sums(theta, n):
    """(S0, S1, S2) with S_p = sum_m m^p e^{i theta m} over the centred grid
    m = -(n-1)/2 .. (n-1)/2 (step 1), in closed form (:func:`dirichlet_core`).

    ``theta`` [rad per sample] is a float; S0 and S2 are real, S1 imaginary (all returned
    as complex).  Scalar arithmetic on purpose: the Gram sums of a few lines need a handful
    of these, where numpy's per-call overhead would cost more than the arithmetic."""
    s0, s1, s2 = dirichlet_core(float(theta), n, *_power_sums(n))
    return complex(s0), complex(0.0, s1), complex(s2)


#: the Hann window's square as exponentials, like HANN (:mod:`dsp._line_kernel`)
HANN2 = ((0, 0.375), (1, 0.25), (-1, 0.25), (2, 0.0625), (-2, 0.0625))


def windowed_sums(dnu, n, terms):
    """(S0, S1, S2): sum_m W(m) m^p e^{2 pi i dnu m}, p = 0, 1, 2, for a window W given as
    exponentials ``terms`` ((shift, weight): W = sum weight e^{2 pi i shift m / n});
    ``dnu`` a float [cycles per sample]."""
    out = [0j, 0j, 0j]
    for shift, weight in terms:
        for p, Sp in enumerate(dirichlet_sums(2 * math.pi * (dnu + shift / n), n)):
            out[p] += weight * Sp
    return out


def windowed_kernel(dnu, n, terms):
    """S0 of :func:`windowed_sums` for an array ``dnu`` [cycles per sample]:
    sum_h weight_h sin(n y_h) / sin(y_h) with y_h = pi (dnu + shift_h / n) (each term is
    the Dirichlet kernel S0(2 y_h); a y_h of exactly 0 is moved to 1e-300, where the ratio
    is its limit n)."""
    dnu = np.asarray(dnu, dtype=float)
    shifts, weights = _term_arrays(terms, n, dnu.ndim)
    y = math.pi * dnu + shifts + 1e-300
    return (weights * np.sin(n * y) / np.sin(y)).sum(axis=0)


@functools.lru_cache(maxsize=32)
def _term_arrays(terms, n, ndim):
    """(pi shift / n, weight) of window ``terms`` as arrays broadcasting over ``ndim`` axes."""
    shape = (len(terms),) + (1,) * ndim
    shifts = np.array([math.pi * t[0] / n for t in terms]).reshape(shape)
    weights = np.array([t[1] for t in terms], dtype=float).reshape(shape)
    shifts.flags.writeable = weights.flags.writeable = False      # shared by every caller
    return shifts, weights


@functools.lru_cache(maxsize=64)
def _diagonal_sums(n, terms):
    """The Gram sums of a column with itself (real: the window's moments)."""
    return tuple(complex(v.real) for v in windowed_sums(0.0, n, terms))


class Sums:
    """The window times powers of m, and the Gram sums of a set of columns.

    On the centred grid with a uniform or the Hann window (the cases of ``dsp.lines``) the
    Gram sums are closed-form (:func:`dirichlet_sums`, shifted for the Hann window's
    exponentials); otherwise they are length-N dot products.
    """

    def __init__(self, m, w):
        self.m, self.w, self.n = m, w, m.size
        self.wm = w * m
        self.wm2 = self.wm * m
        self.const = (float(w.sum()), float(self.wm.sum()), float(self.wm2.sum()))
        n = m.size
        self.kind = None
        if n > 2 and abs(m[0] + m[-1]) < 1e-9 * n and abs(m[1] - m[0] - 1) < 1e-9:
            if np.all(w == w[0]):
                self.kind, self.scale = "rect", float(w[0])
            elif w is _hann(n) or (w[0] == _hann(n)[0] and np.array_equal(w, _hann(n))):
                self.kind, self.scale = "hann", 1.0

    @classmethod
    def centred(cls, n):
        """The sums of the uniform window on the centred grid of ``n`` samples, without
        arrays (only the closed-form :meth:`gram_nu` is available)."""
        S = cls.__new__(cls)
        S.n, S.kind, S.scale = int(n), "rect", 1.0
        return S

    def gram_nu(self, nus, offset, weight2=False):
        """Closed-form Gram sums of the columns (offset = a phasor of frequency 0) from the
        frequencies alone; ``weight2``: with the squared window (the sandwich covariance)."""
        allnu = ([0.0] if offset else []) + [float(nu) for nu in nus]
        q = len(allnu)
        if self.kind == "rect":
            terms = ((0, self.scale ** 2 if weight2 else self.scale),)
        else:
            terms = HANN2 if weight2 else HANN
        rows = [[None] * q for _ in range(q)]
        diag = _diagonal_sums(self.n, terms)
        for j in range(q):
            rows[j][j] = diag
            for k in range(j + 1, q):        # G[p, j, k]: the frequency nu_k - nu_j
                s = windowed_sums(allnu[k] - allnu[j], self.n, terms)
                rows[j][k] = s
                rows[k][j] = [v.conjugate() for v in s]
        return np.array(rows, dtype=complex).reshape(q, q, 3).transpose(2, 0, 1)

    def gram(self, cols, weight=None, powers=3):
        """G[p, j, k] = sum W m^p conj(col_j) col_k, p = 0 .. powers-1 (W = the window or
        ``weight``)."""
        if weight is None:
            Ws, const = (self.w, self.wm, self.wm2), self.const
        else:
            Ws = (weight, weight * self.m, weight * self.m ** 2)
            const = tuple(float(x.sum()) for x in Ws)
        q = len(cols)
        G = np.zeros((powers, q, q), complex)
        for k in range(q):
            G[:, k, k] = const[:powers]           # |col_k| = 1
            if k == 0:
                continue
            for p in range(powers):
                wc = Ws[p] * cols[k]
                for j in range(k):
                    G[p, j, k] = np.vdot(cols[j], wc)
                    G[p, k, j] = np.conj(G[p, j, k])
        return G


def normal_matrix(G, c, K, j0):
    """Re(D^H W D) for the parameters (nu_1..nu_K, Re c_0, Im c_0, Re c_1, ...); lines are
    the columns ``j0 .. j0 + K - 1`` of the Gram sums ``G``."""
    q = c.size
    P = K + 2 * q
    A = np.empty((P, P))
    cl = c[j0:j0 + K]
    # nu-nu block: 4 pi^2 Re(conj(c_a) c_b G2_ab)
    A[:K, :K] = (TWO_PI ** 2 * (np.conj(cl)[:, None] * cl[None, :])
                 * G[2, j0:j0 + K, j0:j0 + K]).real
    # nu-coefficient block: Re(-i u), Re(u) = Im(u), Re(u) with u = 2 pi conj(c_k) G1_kj
    u = TWO_PI * np.conj(cl)[:, None] * G[1, j0:j0 + K, :]     # (K, q)
    A[:K, K::2] = u.imag
    A[:K, K + 1::2] = u.real
    # coefficient block: [[Re G0, -Im G0], [Im G0, Re G0]] interleaved
    g0 = G[0]
    A[K::2, K::2] = g0.real
    A[K::2, K + 1::2] = -g0.imag
    A[K + 1::2, K::2] = g0.imag
    A[K + 1::2, K + 1::2] = g0.real
    A[K:, :K] = A[:K, K:].T
    return A


def _residual(z, cols, c):
    r = z.copy()
    for j, col in enumerate(cols):
        r -= c[j] * col
    return r


def gauss_newton(m0, m, z, w, nus, offset, max_iter=MAX_ITER):
    """Weighted least-squares fit of the lines (start ``nus`` [cycles/sample]) and the offset.

    Each step solves the structured normal equations; a halving line search keeps every
    step downhill.  Stops when the frequency steps fall below 1e-7 of a bin (1e-7 / N
    cycles per sample; the convergence is quadratic, so the last step is far smaller).

    Returns
    -------
    (nus, c, cols, residual, sums)
        Frequencies [cycles/sample], complex coefficients (offset first), the columns at
        the final frequencies, z minus the model, and the :class:`Sums`.
    """
    n = z.size
    S = Sums(m, w)
    K = len(nus)
    j0 = int(offset)
    nus = np.asarray(nus, float).copy()
    cols = columns(m0, n, nus, offset)

    def gram(nus, cols):
        return S.gram_nu(nus, offset) if S.kind else S.gram(cols)

    G = gram(nus, cols)
    c = wls(cols, z, w, G[0])
    r = _residual(z, cols, c)
    cost = float(np.dot(w, r.real ** 2 + r.imag ** 2))
    tol = 1e-7 / n                                   # cycles per sample: 1e-7 of a bin
    for _ in range(max_iter if K else 0):
        A = normal_matrix(G, c, K, j0)
        g = np.empty(A.shape[0])
        wr, wmr = w * r, S.wm * r
        for k in range(K):
            s1 = np.vdot(cols[j0 + k], wmr)
            g[k] = (np.conj(2j * math.pi * c[j0 + k]) * s1).real
        for j in range(c.size):
            s0 = np.vdot(cols[j], wr)
            g[K + 2 * j] = s0.real
            g[K + 2 * j + 1] = s0.imag
        try:
            d = np.linalg.solve(A, g)
        except np.linalg.LinAlgError:
            d = np.linalg.lstsq(A, g, rcond=None)[0]
        step = 1.0
        while True:
            nus_t = nus + step * d[:K]
            cols_t = columns(m0, n, nus_t, offset)
            c_t = c + step * (d[K::2] + 1j * d[K + 1::2])
            r_t = _residual(z, cols_t, c_t)
            cost_t = float(np.dot(w, r_t.real ** 2 + r_t.imag ** 2))
            if cost_t <= cost * (1 + 1e-12) or step < 1e-4:
                break
            step *= 0.5
        if cost_t > cost * (1 + 1e-12):
            break
        small = np.max(np.abs(step * d[:K])) < tol
        nus, cols, c, r, cost = nus_t, cols_t, c_t, r_t, cost_t
        G = gram(nus, cols)
        if small:
            break
    if cols:                                        # amplitudes exactly at the final frequencies
        c = wls(cols, z, w, G[0])
        r = _residual(z, cols, c)
    S.last_gram = G
    return nus, c, cols, r, S


def peak_nu(spec, i, nfft):
    """Frequency [cycles/sample] of a spectrum peak at bin ``i``: a parabola through the
    log-magnitudes of the bins around it."""
    ym, y0, yp = (math.log(max(float(spec[(i + d) % nfft]), 1e-300)) for d in (-1, 0, 1))
    den = ym - 2 * y0 + yp
    delta = 0.5 * (ym - yp) / den if den < 0 else 0.0
    nu = (i + max(-0.5, min(0.5, delta))) / nfft
    return nu - 1.0 if nu >= 0.5 else nu


def _projections(Zmat, a_idx, b_idx, ab_phase, nus):
    """(sum conj(p_k) z, sum m conj(p_k) z) for the lines ``nus`` (see :func:`projection_fit`;
    ``ab_phase`` = -2 pi i [b_idx; a_idx])."""
    K = nus.size
    e = np.exp(ab_phase * nus)                          # (BLOCK + blocks, K): inner, outer
    inner, outer = e[:BLOCK], e[BLOCK:]
    v = Zmat @ np.concatenate((inner, b_idx * inner), axis=1)    # (blocks, 2K)
    v0 = v[:, :K]
    return (outer * v0).sum(axis=0), (outer * (a_idx * v0 + v[:, K:])).sum(axis=0)


def hann_peak_nu(spec, i, n):
    """Frequency [cycles/sample] of a line from the peak bin ``i`` of the magnitude of an
    unpadded Hann-windowed DFT of ``n`` samples (:func:`hann_delta` on the bins i-1, i,
    i+1)."""
    y0 = float(spec[i])
    if y0 <= 0.0:
        return peak_nu(spec, i, n)
    nu = (i + hann_delta(float(spec[(i - 1) % n]), y0, float(spec[(i + 1) % n]))) / n
    return nu - 1.0 if nu >= 0.5 else nu


def projection_fit(z, nus, max_iter=MAX_ITER, min_line_snr=MIN_LINE_SNR):
    """Unweighted least-squares fit of lines on the centred grid, from projections only.

    Variable projection: with the amplitudes at their optimum for the current frequencies
    (c = G0^-1 Z, Z_k = sum conj(p_k) z) the cost is sum |z|^2 - Re(c^H Z) and its gradient
    in nu_k is g_k = Re(conj(2 pi i c_k) (Z1_k - (G1 c)_k)) with Z1_k = sum m conj(p_k) z
    (zero in the amplitudes).  The Gauss-Newton step solves the full normal matrix
    (:func:`normal_matrix`) built from the Gram sums sum m^p conj(p_j) p_k in closed form
    (:func:`dirichlet_sums`); its inverse, kept from the last step, is the covariance
    up to the noise variance.  Per iteration: one projection of z (:func:`_projections`)
    and (3K) x (3K) algebra; no residual array, no N x P Jacobian.

    Returns
    -------
    (nus, c, Ainv, cost) or None
        Frequencies [cycles/sample], complex amplitudes, the inverse of the normal matrix
        of (nu, Re c, Im c) at the last step (times the noise variance per real
        component: the covariance) and the residual sum of squares.  None when it does not
        converge, a Gram matrix is singular, or the fit is not one of K lines
        (:func:`dsp._line_kernel.fit_acceptable`: two lines merge, also across +-1/2, a
        frequency leaves [-1/2, 1/2) or has no positive variance, a line is too weak):
        the caller then takes the sequential search.
    """
    n = z.size
    m0 = -0.5 * (n - 1)
    S = Sums.centred(n)
    zz = float(np.vdot(z, z).real)
    K = len(nus)
    nus = np.asarray(nus, float).copy()
    # projections without forming the phasors: z as a (blocks x BLOCK) matrix, m = a + b
    # (a the block's first index, b = 0..BLOCK-1), so that
    #   sum conj(p) z   = outer . v0,             v0 = Zmat . inner,
    #   sum m conj(p) z = (a outer) . v0 + outer . v1,   v1 = Zmat . (b inner)
    # with outer = e^{-2 pi i nu a}, inner = e^{-2 pi i nu b}: one small matrix product
    nb = -(-n // BLOCK)
    if nb * BLOCK == n:
        Zmat = np.ascontiguousarray(z).reshape(nb, BLOCK)
    else:
        zp = np.zeros(nb * BLOCK, complex)
        zp[:n] = z
        Zmat = zp.reshape(nb, BLOCK)
    a_idx = (m0 + BLOCK * np.arange(nb))[:, None]
    b_idx = np.arange(BLOCK, dtype=float)[:, None]
    ab_phase = -2j * math.pi * np.concatenate((b_idx, a_idx))

    def state(nus):
        """Amplitudes, sum m conj(p_k) z, Gram sums and the cost at ``nus``."""
        Z, Z1 = _projections(Zmat, a_idx, b_idx, ab_phase, nus)
        G = S.gram_nu(nus, False)
        try:
            c = np.linalg.solve(G[0], Z)
        except np.linalg.LinAlgError:
            return None
        return c, Z1, G, max(zz - float(np.vdot(c, Z).real), 0.0)

    st = state(nus)
    if st is None:
        return None
    c, Z1, G, cost = st
    tol = 1e-7 / n
    dof = max(2 * n - 3 * K, 1)
    g = np.zeros(3 * K)
    for _ in range(max_iter):
        A = normal_matrix(G, c, K, 0)
        g[:K] = (np.conj(TWO_PI * 1j * c) * (Z1 - G[1] @ c)).real
        try:
            Ai = np.linalg.inv(A)
        except np.linalg.LinAlgError:
            return None
        d = Ai @ g
        dnu = d[:K]
        # converged when the error left after this step is below 10 % of the frequencies'
        # own uncertainty sd (or the step below 1e-7 of a bin): the step is then taken on
        # the linear model, without another projection.  Gauss-Newton converges
        # quadratically: the error after a step d is ~ C n d^2 with C below 2 (per bin;
        # 0.03-0.06 for separated lines, up to 1.6 for lines 3 bins apart on the bench
        # signals), so 2 n d^2 < 0.1 sd is enough.  From the Hann peak interpolation
        # (:func:`hann_peak_nu`) that usually holds at the first step.
        if step_is_last(d.tolist(), Ai, cost / dof, n, tol):
            nus = nus + dnu
            c = c + d[K::2] + 1j * d[K + 1::2]
            cost = max(cost - float(g @ d), 0.0)
            break
        step = 1.0
        while True:
            st = state(nus + step * dnu)
            if st is None:
                return None
            if st[3] <= cost * (1 + 1e-12) or step < 1e-4:
                break
            step *= 0.5
        if st[3] > cost * (1 + 1e-12):
            break
        nus = nus + step * dnu
        c, Z1, G, cost = st
    else:
        return None
    if not fit_acceptable(nus, c, Ai.diagonal()[:K], cost, n, min_line_snr):
        return None
    return nus, c, Ai, cost
