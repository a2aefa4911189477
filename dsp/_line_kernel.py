"""The fast line fit of :func:`dsp.lines.refine_frequencies` after the FFT, compiled by numba.

:func:`fit_after_peaks` does in one call what :func:`dsp.line_fast._fast_fit` does with numpy
after it has picked the peaks: the close-peak separation (:func:`dsp.line_fast._separate_peaks`),
the Gauss-Newton fit from projections (:func:`dsp.line_gn.projection_fit`) and the spectrum
of the residual near and away from the lines (:func:`dsp.line_fast._residual_extremes`).  The
same equations, as loops: the numpy path spends most of its time in numpy's per-call
overhead on (3K) x (3K) matrices, which this avoids.  No BLAS call inside (scipy's BLAS,
which numba calls, has a thread pool of its own that fights numpy's for the cores).  The
two give the same numbers to rounding (``tests/test_dsp_line_kernel.py``).

numba is imported only when the kernel is first asked for (:func:`compiled`); which
estimates ask is :func:`dsp.line_fast._compiled_kernel`'s rule (at once when numba is already
imported and the kernel is in its cache, else once the numpy path has spent what loading
it costs, :func:`load_cost`), so a command that makes a few estimates never pays for it.
``STAND_DISABLE_JIT=1`` or ``NUMBA_DISABLE_JIT=1`` keeps the numpy path.

Also here, shared with :mod:`dsp.line_gn` as plain Python: :func:`dirichlet_core`,
:func:`hann_delta`, :func:`power_sums`, the Hann window's exponentials :data:`HANN` and the
projection block :data:`BLOCK` (numba's cache is invalidated per source file: code compiled
into the kernel lives in this one file).  This module is the bottom of the line estimator:
it imports nothing of ``dsp``.
"""
from __future__ import annotations

import functools
import hashlib
import importlib.util
import math
import os
import sys
import threading
import types
import warnings

import numpy as np

__all__ = ["fit_after_peaks", "fit_acceptable", "step_is_last", "compiled", "disable",
           "load_cost", "warm", "OK", "DECLINED", "HANN", "BLOCK", "MIN_LINE_SNR", "power_sums"]

OK, DECLINED = 0, 1      #: status of :func:`fit_after_peaks`
TWO_PI = 2.0 * math.pi
BLOCK = 128              #: the record as (blocks x BLOCK) for the projections
MIN_LINE_SNR = 100.0     #: a line is one when |c|^2 N >= this x the residual power per sample
#: the Hann window of dsp.lines.window_weights on the centred grid, as exponentials:
#: w = 0.5 + 0.25 e^{+i 2 pi m / n} + 0.25 e^{-i 2 pi m / n}  ((shift, weight) pairs)
HANN = ((0, 0.5), (1, 0.25), (-1, 0.25))
HANN_SHIFT = tuple(float(h) for h, _ in HANN)
HANN_WEIGHT = tuple(float(w) for _, w in HANN)

_compiled = None        # None: not tried yet; False: unavailable; else the dispatcher
_lock = threading.Lock()
#: compiled in a namespace of their own (the module keeps its Python functions)
_KERNEL = ("dirichlet_core", "hann_delta", "hann_response", "gram", "normal_matrix",
           "separate_peaks", "fit_lines", "step_is_last", "fit_acceptable", "residual_extremes",
           "fit_after_peaks")
_SUMS = ("projections", "sum_sq")   # long sums, which may be reordered (vectorised)


# ---------------------------------------------------------------- shared with dsp.line_gn
# (plain floats: the numpy path calls them as Python, the kernel compiles them; kept in this
# one file so that numba's cache, invalidated per source file, never holds a stale copy)

def dirichlet_core(th, n, s2, s4, s6, s8):
    """(S0, Im S1, S2) of :func:`dirichlet_sums`: S0 = sin(n theta/2) / sin(theta/2),
    S1 = -i S0', S2 = -S0'', a Taylor series in theta where n |theta| < 0.2 (``s2`` .. ``s8``:
    sum m^p over the grid, :func:`power_sums`).  Plain floats: also compiled by numba
    (here, with the kernel)."""
    if n * abs(th) < 0.2:      # the series (to theta^8) and the closed form meet at ~5e-14
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


@functools.lru_cache(maxsize=64)
def power_sums(n):
    """sum m^p over the centred grid of n samples, p = 2, 4, 6, 8 (the ``s2`` .. ``s8`` of
    :func:`dirichlet_core`)."""
    k = np.arange(n) - 0.5 * (n - 1)
    k2 = k * k
    return tuple(float(np.sum(k2 ** j)) for j in (1, 2, 3, 4))


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


def _cache_folders() -> list:
    """The folders where numba's cache locators would keep this file's compiled kernels,
    in numba's order (found without importing numba): ``$NUMBA_CACHE_DIR``, the
    ``__pycache__`` beside this file, the user-wide cache (``$XDG_CACHE_HOME``/numba or
    ~/.cache/numba, used where the package folder is read-only)."""
    folder = os.path.dirname(os.path.abspath(__file__))
    # numba.core.caching._CacheLocator.get_suitable_cache_subpath
    sub = "_".join([os.path.basename(folder), hashlib.sha1(folder.encode()).hexdigest()])
    user = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    places = [os.path.join(folder, "__pycache__"), os.path.join(user, "numba", sub)]
    if os.environ.get("NUMBA_CACHE_DIR"):
        places.insert(0, os.path.join(os.environ["NUMBA_CACHE_DIR"], sub))
    return places


@functools.lru_cache(maxsize=1)
def _in_cache() -> bool:
    """Whether numba's on-disk cache holds the kernel: its index file, written after the
    source's last edit, in one of :func:`_cache_folders`."""
    src = os.path.abspath(__file__)
    name = (f"_line_kernel.fit_after_peaks-{fit_after_peaks.__code__.co_firstlineno}.py"
            f"{sys.version_info.major}{sys.version_info.minor}.nbi")
    try:
        stamp = os.path.getmtime(src)
    except OSError:
        return False
    for place in _cache_folders():
        try:
            if os.path.getmtime(os.path.join(place, name)) >= stamp:
                return True
        except OSError:
            continue
    return False


def warm() -> str:
    """Compile (or load from numba's cache) the kernel for the argument types
    :func:`dsp.line_fast._fast_fit` passes, by calling it on two lines 3.2 bins apart
    (``tests/test_dsp_line_kernel.py`` checks that ``_fast_fit`` then needs no other
    signature); returns the engine ("numba", or "numpy" when the kernel is unavailable)."""
    kernel = compiled()
    if kernel is None:
        return "numpy"
    n = 256
    m = np.arange(n) - 0.5 * (n - 1)
    z = np.exp(2j * math.pi * 0.1 * m) + 0.1 * np.exp(2j * math.pi * (0.1 + 3.2 / n) * m)
    X = np.fft.fft(z)
    spec = np.abs(X)
    peaks = np.sort(np.argsort(spec)[-2:]).astype(np.int64)
    # the scalars as _fast_fit passes them: a bool, then ints (NEAR, MAX_ITER) and a float
    kernel(z, X, spec, peaks, peaks / n, True, np.array(power_sums(n)), 4, 30, MIN_LINE_SNR)
    return "numba" if compiled() is not None else "numpy"


def compiled():
    """The compiled :func:`fit_after_peaks` (numba imported, the kernel compiled or loaded
    from numba's cache on its first call), or None (numba missing, disabled, or failed)."""
    global _compiled
    if _compiled is None:
        with _lock:
            if _compiled is None:
                _compiled = _build() or False
    return _compiled or None


def disable(reason: str) -> None:
    """Stop using the compiled kernel in this process (it failed: ``reason``), with a warning."""
    global _compiled
    _compiled = False
    warnings.warn(f"dsp: the compiled line fit failed ({reason}); using numpy from now on",
                  RuntimeWarning, stacklevel=3)


def _build():
    if _disabled():
        return None
    try:
        import numba
    except ImportError:
        return None
    jit = numba.njit(cache=True, error_model="numpy")
    sums = numba.njit(cache=True, error_model="numpy", fastmath={"reassoc", "contract"})
    ns = dict(globals())
    for name in _KERNEL + _SUMS:
        f = globals()[name]
        g = types.FunctionType(f.__code__, ns, f.__name__, f.__defaults__, f.__closure__)
        g.__qualname__, g.__module__, g.__doc__ = f.__qualname__, f.__module__, f.__doc__
        ns[name] = (sums if name in _SUMS else jit)(g)
    return ns["fit_after_peaks"]


def hann_response(j, nu, n):
    """Hann-windowed DFT at FFT bin ``j`` of a unit line e^{2 pi i nu m} on the centred grid
    (one entry of :func:`dsp.line_fast._hann_response`)."""
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
    """:func:`dsp.line_fast._separate_peaks` (one pass) for ``nus`` in place."""
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
    for k in range(K):
        nus[k] = new[k]


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
        for i in range(n):
            zp[i] = z[i]
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
        if step_is_last(d, Ai, cost / dof, n, tol):
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
        for k in range(K):
            nus[k] = trial[k]
        c = ct
        cost = cost_t
        G, Gt = Gt, G                          # Gt, Z1t are rewritten before they are read
        Z1, Z1t = Z1t, Z1
    if not converged:
        return DECLINED, nus, c, Ai, cost
    var = np.empty(K)
    for k in range(K):
        var[k] = Ai[k, k]
    if not fit_acceptable(nus, c, var, cost, n, min_line_snr):
        return DECLINED, nus, c, Ai, cost
    return OK, nus, c, Ai, cost


def step_is_last(d, Ai, noise_var, n, tol):
    """Whether the Gauss-Newton step ``d`` (frequencies first, [cycles/sample]) may be taken on
    the linear model and the fit stop there (:func:`dsp.line_gn.projection_fit`): for every
    frequency the error the step leaves, ~ C n d^2 with C below 2 per bin, is below a tenth
    of its uncertainty sqrt(Ai[k, k] noise_var), or the step is below ``tol``.  Plain
    Python: the numpy path calls it as it is."""
    for k in range(len(d) // 3):          # d holds K frequencies, then 2K amplitude parts
        sd = math.sqrt(abs(Ai[k, k]) * noise_var)
        if not (2 * n * d[k] * d[k] < 0.1 * sd or abs(d[k]) < tol):
            return False
    return True


def fit_acceptable(nus, c, var, cost, n, min_line_snr):
    """Whether a converged fit of K lines is one (else the caller searches sequentially):
    every frequency in [-1/2, 1/2) cycles per sample with a positive variance ``var``
    (a diagonal of the inverse normal matrix), no two within half a bin of each other --
    also across +-1/2, where a phasor repeats itself up to its sign -- and every line above
    ``min_line_snr`` (|c|^2 n against the residual power per sample).  Plain Python: the
    numpy path (:func:`dsp.line_gn.projection_fit`) calls it as it is."""
    K = nus.size
    for k in range(K):
        if not (-0.5 <= nus[k] < 0.5) or not (var[k] > 0.0):
            return False
    # two within half a bin: some pair is iff two neighbours in sorted order are (no sort:
    # numba's compiles for seconds)
    lo, hi = math.inf, -math.inf
    for k in range(K):
        lo, hi = min(lo, nus[k]), max(hi, nus[k])
        for j in range(k + 1, K):
            if abs(nus[j] - nus[k]) < 0.5 / n:
                return False
    if K > 1 and lo + 1.0 - hi < 0.5 / n:
        return False
    noise = max(cost, 1e-300 * n) / n
    for k in range(K):
        if abs(c[k]) ** 2 * n < min_line_snr * noise:
            return False
    return True


def residual_extremes(X, spec, nus, c, n, near):
    """(Largest |X - the fitted lines' windowed spectra| within ``near`` bins of a line,
    largest of ``spec`` farther away), unscaled; ``spec`` is zeroed near the lines
    (:func:`dsp.line_fast._residual_extremes`)."""
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


def fit_after_peaks(z, X, spec, peaks, nus0, separate, psums, near, max_iter, min_line_snr):
    """Everything :func:`dsp.line_fast._fast_fit` does after picking the peaks (Hann window).

    Parameters
    ----------
    z : complex (n,)    the record;   X : complex (n,)    FFT of the Hann-windowed record;
    spec : float (n,)   |X| (scratch: zeroed near the lines);
    peaks : int (K,)    peak bins;    nus0 : float (K,)   their two-point frequencies;
    separate : bool     take the other lines out of each peak's bins first;
    psums : float (4,)  power_sums(n);  near : bins checked either side of a
    line;  max_iter, min_line_snr: as :func:`dsp.line_gn.projection_fit`.

    Returns
    -------
    (status, nus, c, Ainv, cost, near_max, far_max)
        status OK or DECLINED (the caller then searches sequentially); the residual's
        spectrum extremes (:func:`residual_extremes`; 0 when declined) for the caller's
        threshold.
    """
    n = z.size
    nus = nus0.copy()
    if separate:
        separate_peaks(X, peaks, nus, n)
    status, nus, c, Ai, cost = fit_lines(z, nus, psums, max_iter, min_line_snr)
    if status != OK:
        return status, nus, c, Ai, cost, 0.0, 0.0
    near_max, far_max = residual_extremes(X, spec, nus, c, n, near)
    return OK, nus, c, Ai, cost, near_max, far_max
