"""The fast line fit of :func:`dsp.lines.refine_frequencies` after the FFT, compiled by numba.

:func:`fit_after_peaks` does in one call what :func:`dsp.lines._fast_fit` does with numpy
after it has picked the peaks: the close-peak separation (:func:`dsp.lines._separate_peaks`),
the Gauss-Newton fit from projections (:func:`dsp.line_gn.projection_fit`) and the look at
the residual near the lines (:func:`dsp.lines._residual_holds_line`).  The same equations,
as loops: the numpy path spends most of its time in numpy's per-call overhead on
(3K) x (3K) matrices, which this avoids; the projections of the record stay one matrix
product (BLAS) per iteration.  The two give the same numbers to rounding
(``tests/test_dsp_line_kernel.py``).

numba is imported only when the kernel is first asked for (:func:`compiled`), and
:mod:`dsp.lines` asks only after a process has made a few estimates (importing numba and
loading the kernel from its cache costs about as much as a few hundred estimates), so a
command that makes one or two never pays it.  ``STAND_DISABLE_JIT=1`` or
``NUMBA_DISABLE_JIT=1`` keeps the numpy path.
"""
from __future__ import annotations

import functools
import importlib.util
import math
import os
import sys

import numpy as np


__all__ = ["fit_after_peaks", "compiled", "load_cost", "warm", "OK", "DECLINED",
           "CHECK_RESIDUAL"]

OK, DECLINED, CHECK_RESIDUAL = 0, 1, 2      #: status of :func:`fit_after_peaks`
TWO_PI = 2.0 * math.pi
BLOCK = 128                                  #: as dsp.line_gn.BLOCK
HANN_SHIFT = (0.0, 1.0, -1.0)                #: dsp.line_gn.HANN: w = sum weight e^{2 pi i shift m/n}
HANN_WEIGHT = (0.5, 0.25, 0.25)

_compiled = None        # None: not tried yet; False: unavailable; else the dispatcher


# ---------------------------------------------------------------- shared with dsp.line_gn
# (plain floats: the numpy path calls them as Python, the kernel compiles them; kept in this
# one file so that numba's cache, invalidated per source file, never holds a stale copy)

def dirichlet_core(th, n, s2, s4, s6, s8):
    """(S0, Im S1, S2) of :func:`dirichlet_sums`: S0 = sin(n theta/2) / sin(theta/2),
    S1 = -i S0', S2 = -S0'', a Taylor series in theta where n |theta| < 1 (``s2`` .. ``s8``:
    sum m^p over the grid, :func:`_power_sums`).  Plain floats: also compiled by numba
    (here, with the kernel)."""
    if n * abs(th) < 1.0:
        t2 = th * th
        S0 = n - t2 / 2 * s2 + t2 * t2 / 24 * s4 - t2 ** 3 / 720 * s6 + t2 ** 4 / 40320 * s8
        S1 = th * (s2 - t2 / 6 * s4 + t2 * t2 / 120 * s6 - t2 ** 3 / 5040 * s8)
        S2 = s2 - t2 / 2 * s4 + t2 * t2 / 24 * s6 - t2 ** 3 / 720 * s8
        return S0, S1, S2
    a, b = 0.5 * n, 0.5
    f, fp, fpp = math.sin(a * th), a * math.cos(a * th), -a * a * math.sin(a * th)
    g, gp, gpp = math.sin(b * th), b * math.cos(b * th), -b * b * math.sin(b * th)
    D = f / g
    num = fp * g - f * gp
    Dp = num / (g * g)
    Dpp = (fpp * g - f * gpp) / (g * g) - 2 * gp * num / g ** 3
    return D, -Dp, -Dpp


def hann_delta(ym, y0, yp):
    """Offset [bins] of a line from the bin of magnitude ``y0`` between its neighbours of
    magnitudes ``ym`` (below) and ``yp`` (above) in a Hann-windowed DFT: with the larger
    neighbour's ratio alpha = y / y0 the Hann kernel gives alpha = (1 + delta) / (2 - delta)
    for a line delta bins away, so delta = (2 alpha - 1) / (1 + alpha) (exact for a lone
    line up to O(1/n); noise and other lines' leakage bias it, which the fit removes)."""
    if y0 <= 0.0:
        return 0.0
    side, alpha = (1.0, yp / y0) if yp >= ym else (-1.0, ym / y0)
    return side * min(max((2.0 * alpha - 1.0) / (1.0 + alpha), 0.0), 0.5)




def _disabled() -> bool:
    return any(os.environ.get(k, "") not in ("", "0")
               for k in ("STAND_DISABLE_JIT", "NUMBA_DISABLE_JIT"))


#: what getting the kernel into a process costs [s] (measured on the 2-core test machine):
STARTUP_S = 0.4          #: import numba and start its compiler (0 when numba is imported)
LOAD_S = 0.01            #: load the kernel from numba's cache
COMPILE_S = 15.0         #: compile it (once per install, or after an edit of this file)


def load_cost() -> float:
    """Seconds it would take to get the compiled kernel into this process: 0 when it is
    there, infinite when numba is missing or disabled (``STAND_DISABLE_JIT``,
    ``NUMBA_DISABLE_JIT``)."""
    if _compiled:
        return 0.0
    if _compiled is False or _disabled() or not _numba_installed():
        return math.inf
    return (0.0 if "numba" in sys.modules else STARTUP_S) + (LOAD_S if _in_cache() else COMPILE_S)


@functools.lru_cache(maxsize=1)
def _numba_installed() -> bool:
    return importlib.util.find_spec("numba") is not None


@functools.lru_cache(maxsize=1)
def _in_cache() -> bool:
    """Whether numba's cache next to this file holds the kernel (its index file; a cache
    elsewhere, ``NUMBA_CACHE_DIR``, is not looked for: then compiling is assumed)."""
    src = os.path.abspath(__file__)
    line = fit_after_peaks.__code__.co_firstlineno
    index = os.path.join(os.path.dirname(src), "__pycache__",
                         f"_line_kernel.fit_after_peaks-{line}.py"
                         f"{sys.version_info.major}{sys.version_info.minor}.nbi")
    try:                                 # written after the source's last edit
        return os.path.getmtime(index) >= os.path.getmtime(src)
    except OSError:
        return False


def warm() -> str:
    """Compile (or load from numba's cache) the kernel for the argument types
    :mod:`dsp.lines` passes; returns the engine ("numba" or "numpy" when unavailable)."""
    kern = compiled()
    if kern is None:
        return "numpy"
    n = 256
    m = np.arange(n) - 0.5 * (n - 1)
    z = np.exp(2j * math.pi * 0.1 * m) + 0.1 * np.exp(-2j * math.pi * 0.2 * m)
    w = 0.5 + 0.5 * np.cos(2 * math.pi * m / n)
    X = np.fft.fft(w * z)
    spec = np.abs(X)
    psums = np.array([float(np.sum((m * m) ** j)) for j in (1, 2, 3, 4)])
    kern(z, X, spec, np.array([26, 205], dtype=np.int64), np.array([0.1, -0.2]), True,
         psums, float(w.sum()), float(np.dot(w, w)), 4, 30, 100.0)
    return "numba"


def compiled():
    """The compiled :func:`fit_after_peaks` (numba imported and the kernel compiled or
    loaded from numba's cache on the first call), or None (numba missing or disabled)."""
    global _compiled
    if _compiled is None:
        _compiled = False
        if not _disabled():
            try:
                import numba
            except ImportError:
                return None
            jit = numba.njit(cache=True, error_model="numpy")
            mod = globals()
            for name in ("dirichlet_core", "hann_delta", "hann_response", "gram",
                         "normal_matrix", "separate_peaks", "fit_lines", "residual_near_max"):
                mod[name] = jit(mod[name])
            # the long sums may be reordered (vectorised): rounding-level changes
            sums = numba.njit(cache=True, error_model="numpy",
                              fastmath={"reassoc", "contract"})
            mod["projections"] = sums(projections)
            mod["sum_sq"] = sums(sum_sq)
            _compiled = jit(fit_after_peaks)
    return _compiled or None


def hann_response(j, nu, n):
    """Hann-windowed DFT at FFT bin ``j`` of a unit line e^{2 pi i nu m} on the centred grid
    (one entry of :func:`dsp.lines._hann_response`)."""
    m0 = -0.5 * (n - 1)
    dnu = (nu - j / n + 0.5) % 1.0 - 0.5
    kern = 0.0
    for h in range(3):
        y = math.pi * dnu + math.pi * HANN_SHIFT[h] / n + 1e-300
        kern += HANN_WEIGHT[h] * math.sin(n * y) / math.sin(y)
    ph = TWO_PI * (nu - dnu) * m0
    return complex(math.cos(ph), math.sin(ph)) * kern


def gram(nus, n, psums, G):
    """Gram sums G[p, j, k] = sum m^p conj(p_j) p_k of unit lines (uniform window; the
    closed form of :meth:`dsp.line_gn.Sums.gram_nu`) into ``G`` (3, K, K)."""
    K = nus.size
    for j in range(K):
        G[0, j, j] = n
        G[1, j, j] = 0.0
        G[2, j, j] = psums[0]
        for k in range(j + 1, K):
            s0, s1, s2 = dirichlet_core(TWO_PI * (nus[k] - nus[j]), n,
                                        psums[0], psums[1], psums[2], psums[3])
            G[0, j, k] = s0
            G[1, j, k] = 1j * s1
            G[2, j, k] = s2
            for p in range(3):
                G[p, k, j] = np.conj(G[p, j, k])


def projections(Zmat, m0, nus, Z, Z1):
    """Z_k = sum conj(p_k) z and Z1_k = sum m conj(p_k) z (:func:`dsp.line_gn._projections`)
    into ``Z``, ``Z1``; ``Zmat`` is z as (blocks, BLOCK)."""
    nb, B = Zmat.shape
    K = nus.size
    er = np.empty(B)
    ei = np.empty(B)
    for k in range(K):
        for b in range(B):
            ph = -TWO_PI * nus[k] * b
            er[b] = math.cos(ph)
            ei[b] = math.sin(ph)
        s = 0j
        s1 = 0j
        for a in range(nb):
            # the block's sums sum_b e_b z and sum_b b e_b z, in real arithmetic (no BLAS
            # call: a second BLAS thread pool, scipy's, would fight numpy's for the cores)
            v0r = 0.0
            v0i = 0.0
            v1r = 0.0
            v1i = 0.0
            for b in range(B):
                zr = Zmat[a, b].real
                zi = Zmat[a, b].imag
                pr = zr * er[b] - zi * ei[b]
                pi_ = zr * ei[b] + zi * er[b]
                v0r += pr
                v0i += pi_
                v1r += b * pr
                v1i += b * pi_
            am = m0 + B * a
            ph = -TWO_PI * nus[k] * am
            o = complex(math.cos(ph), math.sin(ph))
            v0 = complex(v0r, v0i)
            s += o * v0
            s1 += o * (am * v0 + complex(v1r, v1i))
        Z[k] = s
        Z1[k] = s1


def sum_sq(z):
    """sum |z|^2."""
    zz = 0.0
    for i in range(z.size):
        zz += z[i].real * z[i].real + z[i].imag * z[i].imag
    return zz


def normal_matrix(G, c, A):
    """Re(D^H D) for (nu_1..nu_K, Re c_1, Im c_1, ...) into ``A`` (3K, 3K)
    (:func:`dsp.line_gn.normal_matrix` with no offset)."""
    K = c.size
    for a in range(K):
        for b in range(K):
            A[a, b] = (TWO_PI * TWO_PI * np.conj(c[a]) * c[b] * G[2, a, b]).real
        for j in range(K):
            u = TWO_PI * np.conj(c[a]) * G[1, a, j]
            A[a, K + 2 * j] = u.imag
            A[a, K + 2 * j + 1] = u.real
            A[K + 2 * j, a] = u.imag
            A[K + 2 * j + 1, a] = u.real
    for j in range(K):
        for k in range(K):
            g0 = G[0, j, k]
            A[K + 2 * j, K + 2 * k] = g0.real
            A[K + 2 * j, K + 2 * k + 1] = -g0.imag
            A[K + 2 * j + 1, K + 2 * k] = g0.imag
            A[K + 2 * j + 1, K + 2 * k + 1] = g0.real


def separate_peaks(X, peaks, nus, n):
    """:func:`dsp.lines._separate_peaks` (one pass) for ``nus`` in place."""
    K = peaks.size
    c = np.empty(K, dtype=np.complex128)
    for k in range(K):
        c[k] = X[peaks[k] % n] / hann_response(peaks[k] % n, nus[k], n)
    new = np.empty(K)
    for k in range(K):
        mag = np.empty(3)
        for q in range(3):
            j = (peaks[k] + q - 1) % n
            x = X[j]
            for l in range(K):
                if l != k:
                    x -= c[l] * hann_response(j, nus[l], n)
            mag[q] = abs(x)
        nu = (peaks[k] + hann_delta(mag[0], mag[1], mag[2])) / n
        new[k] = nu - 1.0 if nu >= 0.5 else nu
    nus[:] = new


def fit_lines(z, nus, psums, max_iter, min_line_snr):
    """:func:`dsp.line_gn.projection_fit` as loops: (status, nus, c, Ainv, cost)."""
    n = z.size
    K = nus.size
    m0 = -0.5 * (n - 1)
    nb = (n + BLOCK - 1) // BLOCK
    if nb * BLOCK == n:
        Zmat = z.reshape((nb, BLOCK))
    else:
        zp = np.zeros(nb * BLOCK, dtype=np.complex128)
        zp[:n] = z
        Zmat = zp.reshape((nb, BLOCK))
    zz = sum_sq(z)
    P = 3 * K
    G = np.empty((3, K, K), dtype=np.complex128)
    Gt = np.empty((3, K, K), dtype=np.complex128)
    Z = np.empty(K, dtype=np.complex128)
    Z1 = np.empty(K, dtype=np.complex128)
    Zt = np.empty(K, dtype=np.complex128)
    Z1t = np.empty(K, dtype=np.complex128)
    A = np.empty((P, P))
    Ai = np.linalg.inv(np.eye(P))           # (typed as what the loop assigns)
    g = np.zeros(P)
    nus = nus.copy()
    trial = np.empty(K)
    projections(Zmat, m0, nus, Z, Z1)
    gram(nus, n, psums, G)
    c = np.linalg.solve(G[0], Z)
    cost = max(zz - np.vdot(c, Z).real, 0.0)
    tol = 1e-7 / n
    dof = max(2 * n - P, 1)
    converged = False
    for it in range(max_iter):
        normal_matrix(G, c, A)
        for k in range(K):
            r1 = Z1[k]
            for j in range(K):
                r1 -= G[1, k, j] * c[j]
            g[k] = (np.conj(TWO_PI * 1j * c[k]) * r1).real
        Ai = np.linalg.inv(A)
        d = np.zeros(P)
        for i in range(P):
            for j in range(K):                 # g is zero in the amplitudes
                d[i] += Ai[i, j] * g[j]
        # the convergence test of dsp.line_gn.projection_fit
        small = True
        for k in range(K):
            sd = math.sqrt(abs(Ai[k, k]) * (cost / dof))
            if not (2 * n * d[k] * d[k] < 0.1 * sd or abs(d[k]) < tol):
                small = False
        if small:
            for k in range(K):
                nus[k] += d[k]
                c[k] += d[K + 2 * k] + 1j * d[K + 2 * k + 1]
            gd = 0.0
            for k in range(K):
                gd += g[k] * d[k]
            cost = max(cost - gd, 0.0)
            converged = True
            break
        step = 1.0
        ct = c
        cost_t = cost
        while True:
            for k in range(K):
                trial[k] = nus[k] + step * d[k]
            projections(Zmat, m0, trial, Zt, Z1t)
            gram(trial, n, psums, Gt)
            ct = np.linalg.solve(Gt[0], Zt)
            cost_t = max(zz - np.vdot(ct, Zt).real, 0.0)
            if cost_t <= cost * (1 + 1e-12) or step < 1e-4:
                break
            step *= 0.5
        if cost_t > cost * (1 + 1e-12):
            converged = True                   # no step lowers the cost: as converged as it gets
            break
        nus[:] = trial
        c = ct
        cost = cost_t
        G[:] = Gt
        Z1[:] = Z1t
    if not converged:
        return 1, nus, c, Ai, cost
    srt = np.sort(nus)
    for k in range(K - 1):
        if srt[k + 1] - srt[k] < 0.5 / n:
            return 1, nus, c, Ai, cost
    noise = max(cost, 1e-300 * n) / n
    for k in range(K):
        if abs(c[k]) ** 2 * n < min_line_snr * noise:
            return 1, nus, c, Ai, cost
    return 0, nus, c, Ai, cost


def residual_near_max(X, spec, nus, c, n, near):
    """Largest |X - fitted lines' windowed spectra| within ``near`` bins of a line, and the
    largest of ``spec`` farther away (``spec`` is zeroed near the lines); both unscaled
    (:func:`dsp.lines._residual_holds_line`)."""
    K = nus.size
    best = 0.0
    for k in range(K):
        centre = int(np.rint(nus[k] * n))
        for off in range(-near, near + 1):
            j = (centre + off) % n
            x = X[j]
            for l in range(K):
                x -= c[l] * hann_response(j, nus[l], n)
            best = max(best, abs(x))
    for k in range(K):
        centre = int(np.rint(nus[k] * n))
        for off in range(-near, near + 1):
            spec[(centre + off) % n] = 0.0
    return best, spec.max()


def fit_after_peaks(z, X, spec, peaks, nus0, separate, psums, sw, sw2, near,
                    max_iter, min_line_snr):
    """Everything :func:`dsp.lines._fast_fit` does after picking the peaks (Hann window).

    Parameters
    ----------
    z : complex (n,)    the record;   X : complex (n,)    FFT of the Hann-windowed record;
    spec : float (n,)   |X| (scratch: zeroed near the lines);
    peaks : int (K,)    peak bins;    nus0 : float (K,)   their two-point frequencies;
    separate : bool     take the other lines out of each peak's bins first;
    psums : float (4,)  dsp.line_gn._power_sums(n);  sw, sw2 : sum of the window, of its
    square;  near : bins checked either side of a line;  max_iter, min_line_snr: as
    :func:`dsp.line_gn.projection_fit`.

    Returns
    -------
    (status, nus, c, Ainv, cost, threshold)
        status OK, DECLINED (the fit declined: the caller searches sequentially) or
        CHECK_RESIDUAL (the spectrum near or away from the lines exceeds ``threshold``
        [unit of z]: the caller looks at the exact residual).
    """
    n = z.size
    nus = nus0.copy()
    if separate:
        separate_peaks(X, peaks, nus, n)
    status, nus, c, Ai, cost = fit_lines(z, nus, psums, max_iter, min_line_snr)
    if status != 0:
        return status, nus, c, Ai, cost, 0.0
    level = 5.0 * math.sqrt(math.log(2.0) * cost / n * sw2) / sw
    thr = 0.3 * np.abs(c).min()
    if level > thr:
        thr = level
    near_max, far_max = residual_near_max(X, spec, nus, c, n, near)
    if near_max / sw > thr or far_max / sw > thr:
        return 2, nus, c, Ai, cost, thr
    return 0, nus, c, Ai, cost, thr
