"""Rendering of laser-spot camera frames: a compiled kernel and streaming wrappers.

The kernel :func:`render_frame` draws one frame:

1. **Spot.**  For every sub-sample position (u, v) [px] with weight w (its
   fraction of the exposure) it adds a Gaussian of flux
   ``peak * w * 2 pi sigma_u sigma_v`` (so a still spot reads ``peak`` DN at its
   centre), integrated exactly over each pixel's area (differences of ``erf``),
   inside a window of +-``window`` sigma around the position only.  The
   window's flux is renormalised to the full flux, and the window is cut at
   exactly +-window sigma (not at a pixel edge), so the spot stays symmetric and
   its intensity centroid is the position to ~1e-4 px.  The cost is
   proportional to K * window^2, not to the image size.  The default window is
   4 sigma (3 sigma leaves a step of 1.1 % of the peak, visible at 8 bits).
2. **Background, shot and read noise, quantisation.**  The signal in DN is
   ``background + spot``; with shot noise the signal in electrons
   ``lambda = signal * electrons_per_dn`` is Poisson -- exact (Knuth) below
   20 e-, a normal approximation above -- then the read noise (normal, DN rms)
   is added and the value is rounded (half up) and clipped to
   ``[0, 2**bit_depth - 1]`` (saturation).
   Pixels that the spot does not touch all have the same distribution: the
   exact distribution of the quantised background (Poisson x normal x
   rounding x clipping) is computed once per camera (:func:`background_table`)
   and such pixels are drawn from it by table inversion with one 32-bit random
   number each (an exact method, to 2**-32 in probability).  This makes the
   whole-image pass cost about one nanosecond per pixel.
3. **Random numbers.**  splitmix64 (a counter-based generator) started per
   frame from a hash of (seed, frame index): every frame is reproducible on its
   own, and frames can be rendered in any order or in parallel.

``noise=False`` gives the noiseless frame: ``round(background + spot)``, clipped.

The kernel is compiled by numba (``cache=True``, ``error_model="numpy"``);
with ``STAND_DISABLE_JIT=1`` it runs as plain Python (slow, for checking).

Pixel convention (OpenCV's): pixel (row i, column j) has its centre at
u = j, v = i; ``positions[..., 0]`` is u (column, to the right),
``positions[..., 1]`` is v (row, downwards).
"""
from __future__ import annotations

import functools
import math
from typing import Iterator, Optional

import numpy as np

from stand._jit import njit
from vision.camera_artefacts import hot_pixels, sensor_artefacts

__all__ = ["render_frame", "render_frames", "render_long_exposure", "background_table",
           "frame_seed", "WINDOW_SIGMAS", "GUIDE_BITS"]

WINDOW_SIGMAS = 4.0     #: half-width of the drawing window, in sigma
GUIDE_BITS = 12         #: 2**GUIDE_BITS entries in the inversion guide table
EXACT_POISSON_BELOW = 20.0   #: electrons; Poisson exact below, normal approximation above
_GSHIFT = np.int64(32 - GUIDE_BITS)

_M64 = (1 << 64) - 1
_U11 = np.uint64(11)
_U27 = np.uint64(27)
_U30 = np.uint64(30)
_U31 = np.uint64(31)
_U32 = np.uint64(32)
_LO32 = np.uint64(0xFFFFFFFF)
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_TWO32 = 4294967296

_INV53 = 1.0 / 9007199254740992.0
_SQRT2 = math.sqrt(2.0)
_TWO_PI = 2.0 * math.pi


# ---------------------------------------------------------------- random numbers
def frame_seed(seed: int, index: int) -> np.uint64:
    """Initial random state (splitmix64 counter) of frame ``index`` for ``seed``.

    A splitmix64 hash of (seed, index) (Steele, Lea & Flood 2014).
    """
    z = (int(seed) * 0x9E3779B97F4A7C15 + (int(index) + 1) * 0xD1B54A32D192ED03) & _M64
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & _M64
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & _M64
    z = z ^ (z >> 31)
    return np.uint64(z if z else 0x9E3779B97F4A7C15)


@njit(cache=True, error_model="numpy", inline="always")
def _next(s):
    """splitmix64 (counter-based): new state, 64-bit output."""
    s += _GOLDEN
    z = s
    z = (z ^ (z >> _U30)) * _MIX1
    z = (z ^ (z >> _U27)) * _MIX2
    return s, z ^ (z >> _U31)


@njit(cache=True, error_model="numpy")
def _uniform(s):
    """Uniform double in (0, 1)."""
    s, r = _next(s)
    return s, (float(r >> _U11) + 0.5) * _INV53


@njit(cache=True, error_model="numpy")
def _normal_pair(s):
    """Two independent standard normals (Box-Muller)."""
    s, a = _uniform(s)
    s, b = _uniform(s)
    rad = math.sqrt(-2.0 * math.log(a))
    return s, rad * math.cos(_TWO_PI * b), rad * math.sin(_TWO_PI * b)


@njit(cache=True, error_model="numpy")
def _poisson_small(s, lam):
    """Poisson(lam) for small lam (Knuth's multiplication method)."""
    limit = math.exp(-lam)
    p = 1.0
    n = 0
    while True:
        s, a = _uniform(s)
        p *= a
        if p <= limit:
            return s, n
        n += 1


# ---------------------------------------------------------------- the kernel
@njit(cache=True, error_model="numpy")
def _edge_integrals(c, sigma, half, lo, hi, g):
    """Fraction of a 1-D Gaussian (centre c, sigma) cut at c +- half, falling on
    each pixel lo..hi (pixel k covers [k - 0.5, k + 0.5]); renormalised to 1."""
    a = c - half
    b = c + half
    scale = 1.0 / (_SQRT2 * sigma)
    norm = 1.0 / math.erf(half * scale)
    prev = -1.0
    for k in range(lo, hi + 1):
        left = k - 0.5
        if left < a:
            left = a
        right = k + 0.5
        if right > b:
            right = b
        if k == lo:
            prev = math.erf((left - c) * scale)
        cur = math.erf((right - c) * scale)
        g[k - lo] = 0.5 * (cur - prev) * norm
        prev = cur


@njit(cache=True, error_model="numpy", inline="always")
def _draw(x, thresholds, guide, kmin):
    """Background value for the 32-bit uniform integer ``x`` (guide-table inversion).

    guide[g] >= 0: every uniform of bucket g gives that value; guide[g] < 0:
    search the thresholds from index -guide[g] - 1.
    """
    e = guide[x >> _GSHIFT]
    if e >= 0:
        return e
    k = -e - 1
    while x >= thresholds[k]:
        k += 1
    return kmin + k


@njit(cache=True, error_model="numpy", inline="always")
def _fill_background(out, i, a, b, s, thresholds, guide, kmin):
    """Draw spot-free pixels out[i, a:b] from the background law, two per random word."""
    j = a
    while j + 1 < b:
        s, r = _next(s)
        out[i, j] = _draw(np.int64(r >> _U32), thresholds, guide, kmin)
        out[i, j + 1] = _draw(np.int64(r & _LO32), thresholds, guide, kmin)
        j += 2
    if j < b:
        s, r = _next(s)
        out[i, j] = _draw(np.int64(r >> _U32), thresholds, guide, kmin)
    return s


@njit(cache=True, error_model="numpy", inline="always")
def _window_box(uk, vk, wk, half_u, half_v, W, H):
    """Pixels (columns a..b, rows c..d) of one sub-sample's drawing window.

    The window is +-``half_u`` x +-``half_v`` [px] around the position (uk, vk)
    [px], clipped to the W x H image; ``a = -1`` (all -1) when the sub-sample
    draws nothing: non-finite position, zero weight ``wk``, or a window
    entirely outside the image.
    """
    if not (math.isfinite(uk) and math.isfinite(vk)) or wk == 0.0:
        return -1, -1, -1, -1
    if uk + half_u < -0.5 or uk - half_u > W - 0.5:
        return -1, -1, -1, -1
    if vk + half_v < -0.5 or vk - half_v > H - 0.5:
        return -1, -1, -1, -1
    a = max(0, int(math.floor(uk - half_u + 0.5)))
    b = min(W - 1, int(math.floor(uk + half_u + 0.5)))
    c = max(0, int(math.floor(vk - half_v + 0.5)))
    d = min(H - 1, int(math.floor(vk + half_v + 0.5)))
    return a, b, c, d


@njit(cache=True, error_model="numpy")
def render_frame(u, v, weights, sigma_u, sigma_v, peak, background, read_noise,
                 electrons_per_dn, shot_noise, max_dn, noise, state, thresholds, guide,
                 kmin, window, acc, out):
    """Render one frame into ``out`` (shape (H, W); the wrappers pass uint16 and
    copy 8-bit frames out, so that one compiled specialisation serves all depths).

    Parameters
    ----------
    u, v : float64 arrays (K,)
        Sub-sample spot centres [px] (u = column, v = row; pixel centres at
        integers).  Non-finite positions are skipped.
    weights : float64 array (K,)
        Fraction of the exposure of each sub-sample (sum 1 for a full exposure).
    sigma_u, sigma_v : float
        Gaussian standard deviations along u and v [px] (1/e^2 diameter / 4).
    peak : float
        DN at the centre of a still spot over the full exposure.
    background : float
        DN.
    read_noise : float
        DN rms.
    electrons_per_dn : float
    shot_noise : bool
    max_dn : int
        Saturation value, 2**bits - 1.
    noise : bool
        False: noiseless frame round(background + spot).
    state : uint64
        Initial random state of this frame (:func:`frame_seed`).
    thresholds : int64 array; guide : int32 array; kmin : int
        The background distribution from :func:`background_table` (unused
        when ``noise`` is False).
    window : float
        Half-width of the drawing window in sigma.
    acc : float64 array (H, W)
        Workspace; any content (only the spot's bounding box is zeroed and used).
    out : uint16 (or uint8) array (H, W)

    Returns
    -------
    int
        Number of pixels touched by the spot (drawn with the per-pixel noise model).
    """
    H, W = out.shape
    K = u.shape[0]
    half_u = window * sigma_u
    half_v = window * sigma_v
    # bounding box of all windows, clipped to the image
    i0, i1, j0, j1 = H, -1, W, -1
    for k in range(K):
        a, b, c, d = _window_box(u[k], v[k], weights[k], half_u, half_v, W, H)
        if a < 0:
            continue
        j0 = min(j0, a)
        j1 = max(j1, b)
        i0 = min(i0, c)
        i1 = max(i1, d)
    for i in range(i0, i1 + 1):
        for j in range(j0, j1 + 1):
            acc[i, j] = 0.0
    # spot: separable pixel integrals inside each window
    gu = np.empty(int(2.0 * half_u) + 3)
    gv = np.empty(int(2.0 * half_v) + 3)
    flux0 = peak * _TWO_PI * sigma_u * sigma_v
    for k in range(K):
        a, b, c, d = _window_box(u[k], v[k], weights[k], half_u, half_v, W, H)
        if a < 0:
            continue
        _edge_integrals(u[k], sigma_u, half_u, a, b, gu)
        _edge_integrals(v[k], sigma_v, half_v, c, d, gv)
        f = flux0 * weights[k]
        for i in range(c, d + 1):
            fi = f * gv[i - c]
            for j in range(a, b + 1):
                acc[i, j] += fi * gu[j - a]
    # background, noise, quantisation
    top = float(max_dn)
    touched = 0
    if not noise:
        q = math.floor(background + 0.5)
        bq = int(min(max(q, 0.0), top))
        for i in range(H):
            inrow = i0 <= i <= i1
            for j in range(W):
                if inrow and j0 <= j <= j1 and acc[i, j] > 0.0:
                    q = math.floor(background + acc[i, j] + 0.5)
                    out[i, j] = int(min(max(q, 0.0), top))
                    touched += 1
                else:
                    out[i, j] = bq
        return touched
    s = state
    have_normal = False
    spare_normal = 0.0
    for i in range(H):
        if i < i0 or i > i1:
            s = _fill_background(out, i, 0, W, s, thresholds, guide, kmin)
            continue
        s = _fill_background(out, i, 0, j0, s, thresholds, guide, kmin)
        for j in range(j0, j1 + 1):
            sig = acc[i, j]
            if sig > 0.0:
                touched += 1
                dn = background + sig
                std = read_noise
                if shot_noise:
                    lam = dn * electrons_per_dn
                    if lam < EXACT_POISSON_BELOW:
                        s, n = _poisson_small(s, lam)
                        dn = n / electrons_per_dn
                    else:
                        std = math.sqrt(lam / (electrons_per_dn * electrons_per_dn)
                                        + read_noise * read_noise)
                if std > 0.0:
                    if have_normal:
                        z = spare_normal
                        have_normal = False
                    else:
                        s, z, spare_normal = _normal_pair(s)
                        have_normal = True
                    dn += std * z
                q = math.floor(dn + 0.5)
                out[i, j] = int(min(max(q, 0.0), top))
            else:
                s, r = _next(s)
                out[i, j] = _draw(np.int64(r >> _U32), thresholds, guide, kmin)
        s = _fill_background(out, i, j1 + 1, W, s, thresholds, guide, kmin)
    return touched


# ---------------------------------------------------------------- background law
@functools.lru_cache(maxsize=64)
def background_table(background: float, read_noise: float, shot_noise: bool,
                     electrons_per_dn: float, max_dn: int):
    """Exact distribution of a spot-free pixel, as inversion tables.

    The pixel reads ``clip(round(N / electrons_per_dn + read_noise * Z))`` with
    N ~ Poisson(background * electrons_per_dn) (or N = background *
    electrons_per_dn without shot noise) and Z standard normal.  For more than
    1e5 electrons the Poisson law is replaced by its normal approximation.

    Returns
    -------
    thresholds : int64 array (n,)
        round(2**32 * P(value <= kmin + k)); the last one is 2**32.
    guide : int32 array (2**GUIDE_BITS,)
        For the uniforms x in bucket g = x >> (32 - GUIDE_BITS): the value
        itself (>= 0) if the whole bucket maps to one value, else -(k + 1) with
        k the smallest index with thresholds[k] > g * 2**(32 - GUIDE_BITS).
    kmin : int
        Smallest value with non-negligible probability.
    """
    lam = background * electrons_per_dn if shot_noise else 0.0
    read = read_noise
    if shot_noise and lam > 1e5:  # normal approximation of a huge Poisson count
        read = math.sqrt(read ** 2 + lam / electrons_per_dn ** 2)
        dn, p = np.array([background]), np.array([1.0])
    elif shot_noise and lam > 0:
        half = 12.0 * math.sqrt(lam) + 12.0
        n = np.arange(max(0, math.floor(lam - half)), math.ceil(lam + half) + 1)
        p = np.exp(n * math.log(lam) - lam - _gammaln(n + 1.0))
        p /= p.sum()
        dn = n / electrons_per_dn
    else:
        dn, p = np.array([background]), np.array([1.0])
    if read > 0:
        lo = max(0, math.floor(dn.min() - 10.0 * read))
        hi = min(max_dn, math.ceil(dn.max() + 10.0 * read) + 1)
        k = np.arange(lo, hi + 1)
        cdf = np.empty(k.size)
        for a in range(0, k.size, 256):  # bounded memory
            kk = k[a:a + 256, None]
            cdf[a:a + 256] = _ndtr((kk + 0.5 - dn[None, :]) / read) @ p
        cdf[-1] = 1.0
    else:
        vals = np.clip(np.floor(dn + 0.5), 0, max_dn).astype(np.int64)
        lo, hi = int(vals.min()), int(vals.max())
        cdf = np.cumsum(np.bincount(vals - lo, weights=p, minlength=hi - lo + 1))
        cdf[-1] = 1.0
    thresholds = np.minimum(np.round(np.clip(cdf, 0.0, 1.0) * _TWO32), _TWO32).astype(np.int64)
    thresholds = np.maximum.accumulate(thresholds)
    thresholds[-1] = _TWO32
    step = 1 << (32 - GUIDE_BITS)
    first = np.arange(1 << GUIDE_BITS, dtype=np.int64) * step
    start = np.searchsorted(thresholds, first, side="right")
    pure = first + step <= thresholds[start]       # the whole bucket maps to one value
    guide = np.where(pure, lo + start, -start - 1).astype(np.int32)
    thresholds.setflags(write=False)
    guide.setflags(write=False)
    return thresholds, guide, int(lo)


#: tables up to this many values are computed with the math module: importing scipy.special
#: (gammaln, ndtr) costs about 0.2 s of a ``stand run`` that renders a screen
_SMALL_TABLE = 65536


def _gammaln(x: np.ndarray) -> np.ndarray:
    """log Gamma(x) elementwise (x > 0)."""
    if x.size > _SMALL_TABLE:
        from scipy.special import gammaln

        return gammaln(x)
    return np.array([math.lgamma(v) for v in x.ravel()]).reshape(x.shape)


def _ndtr(x: np.ndarray) -> np.ndarray:
    """Standard normal CDF elementwise (scipy.special.ndtr's erf/erfc split)."""
    if x.size > _SMALL_TABLE:
        from scipy.special import ndtr

        return ndtr(x)
    r = 1.0 / math.sqrt(2.0)
    return np.array([0.5 + 0.5 * math.erf(v * r) if abs(v) < r
                     else (0.5 * math.erfc(-v * r) if v < 0 else 1.0 - 0.5 * math.erfc(v * r))
                     for v in x.ravel()]).reshape(x.shape)


# ---------------------------------------------------------------- wrappers
def _render_kernel():
    """:func:`render_frame` precompiled (no numba import: a ``stand run`` with a screen starts
    as fast as one without), or on numba's JIT (stand.integrate.kernel_set.extra)."""
    from stand.integrate.kernel_set import extra

    return extra(render_frame)


def render_frame_signature():
    """numba's signature of :func:`render_frame` for its precompiled module (readonly arrays
    need the type objects; :func:`stand.integrate.kernel_set.extra`)."""
    from numba import types

    a1 = types.Array(types.float64, 1, "C")
    ro = lambda t: types.Array(t, 1, "C", readonly=True)  # noqa: E731
    f8, i8, b1 = types.float64, types.int64, types.boolean
    return types.int64(a1, a1, a1, f8, f8, f8, f8, f8, f8, b1, i8, b1, types.uint64,
                       ro(types.int64), ro(types.int32), i8, f8, types.Array(f8, 2, "C"),
                       types.Array(types.uint16, 2, "C"))


def _settings(cam):
    su, sv = cam.sigma_px
    return dict(sigma_u=su, sigma_v=sv, peak=float(cam.peak), background=float(cam.background),
                read_noise=float(cam.read_noise), electrons_per_dn=float(cam.electrons_per_dn),
                shot_noise=bool(cam.shot_noise), max_dn=int(cam.max_dn))


class _Renderer:
    """Holds the workspace and tables for one camera; renders frame after frame."""

    def __init__(self, cam, noise: bool = True, window: float = WINDOW_SIGMAS, gain: float = 1.0):
        self.cam, self.noise, self.window = cam, bool(noise), float(window)
        self.p = _settings(cam)
        self.p["background"] *= gain          # the lamps' flicker lights the screen
        self.acc = np.zeros((cam.height, cam.width))
        if self.noise:
            self.thr, self.guide, self.kmin = background_table(
                self.p["background"], self.p["read_noise"], self.p["shot_noise"],
                self.p["electrons_per_dn"], self.p["max_dn"])
        else:
            self.thr = np.full(1, _TWO32, np.int64)
            self.guide = np.zeros(1 << GUIDE_BITS, np.int32)
            self.kmin = 0
            # read-only like the cached tables: one compiled specialisation for both modes
            self.thr.setflags(write=False)
            self.guide.setflags(write=False)

    def render(self, u, v, weights, state, out):
        p = self.p
        with np.errstate(over="ignore"):  # uint64 wrap-around in the plain-Python path
            return _render_kernel()(u, v, weights, p["sigma_u"], p["sigma_v"], p["peak"],
                                p["background"], p["read_noise"], p["electrons_per_dn"],
                                p["shot_noise"], p["max_dn"], self.noise, state, self.thr,
                                self.guide, self.kmin, self.window, self.acc, out)


def _as_positions(block) -> tuple[np.ndarray, np.ndarray]:
    a = np.asarray(block, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 2:
        raise ValueError(f"positions of one frame must have shape (K, 2) [px], got {a.shape}")
    return np.ascontiguousarray(a[:, 0]), np.ascontiguousarray(a[:, 1])


def render_frames(positions_px, cam, seed: Optional[int] = None, *, noise: bool = True,
                  weights=None, first_index: int = 0, reuse: bool = False,
                  window: float = WINDOW_SIGMAS, gains=None, rows=None) -> Iterator[np.ndarray]:
    """Render frames one by one (a generator: no (F, H, W) array in memory).

    Parameters
    ----------
    positions_px : array (F, K, 2) or iterable of (K, 2) arrays
        Spot centre [px] at each frame's K sub-sample times (u = column,
        v = row), e.g. from :func:`stand.instruments.screen.spot_positions` at
        :func:`~stand.instruments.screen.exposure_times`.
    cam : ScreenCamera
    seed : int, optional
        Default ``cam.seed``.  Frame f uses the random stream
        ``frame_seed(seed, first_index + f)``.
    noise : bool
        False: noiseless frames.
    weights : array (K,), optional
        Fraction of the exposure per sub-sample; default 1/K each.
    first_index : int
        Index of the first frame (so a long video can be rendered in chunks and
        reproduce the same frames).
    reuse : bool
        Yield the same output buffer every time (the caller copies or writes it
        before asking for the next frame); default a new array per frame.
    window : float
        Drawing half-window in sigma.
    gains : array (F,), optional
        Brightness of each frame (1): the lamps' flicker
        (:func:`vision.camera_artefacts.flicker_gain`) on the spot and the background.
    rows : array (F, H, K, 2), optional
        A rolling shutter: the spot [px] at each row's own exposure sub-sample times; each
        row the spot reaches (``positions_px`` +- the window) is drawn from them (one render
        per such row, only when given).

    Yields
    ------
    ndarray (H, W), ``cam.dtype`` (uint8 for 8 bits, else uint16)
    """
    seed = cam.seed if seed is None else int(seed)
    r = _Renderer(cam, noise, window)
    shape = (cam.height, cam.width)
    look = functools.partial(sensor_artefacts, saturation=cam.saturation, full_scale=cam.max_dn,
                             hot=hot_pixels(shape, cam.hot_pixels, cam.seed) if noise else None,
                             jpeg_quality=cam.jpeg_quality if noise else None)   # docs/scene.md
    # the kernel always writes uint16 (one compiled specialisation); 8-bit frames
    # are copied out of it (~10 us per 640 x 480 frame)
    wide = cam.dtype == np.uint16
    work = None if wide else np.empty(shape, dtype=np.uint16)
    buf = np.empty(shape, dtype=cam.dtype)
    w = None if weights is None else np.ascontiguousarray(weights, dtype=np.float64)
    for f, block in enumerate(positions_px):
        u, v = _as_positions(block)
        wk = np.full(u.size, 1.0 / max(u.size, 1)) if w is None else w
        if wk.shape != u.shape:
            raise ValueError(f"weights: shape {wk.shape}, expected ({u.size},)")
        g = 1.0 if gains is None else float(gains[f])
        rf = r if g == 1.0 else _Renderer(cam, noise, window, g)   # flicker: spot and background
        out = buf if reuse else np.empty(shape, dtype=cam.dtype)
        rf.render(u, v, wk * g, frame_seed(seed, first_index + f), out if wide else work)
        if rows is not None:          # rolling shutter: the rows the spot reaches, each at its time
            vv, reach = np.asarray(rows[f])[..., 1], window * max(cam.sigma_px) + 1.0
            lo, hi = min(v.min(), vv.min()) - reach, max(v.max(), vv.max()) + reach
            band = np.empty_like(work if not wide else out)
            for k in range(max(0, int(lo)), min(shape[0], int(hi) + 1)):
                rf.render(*_as_positions(rows[f][k]), wk * g, frame_seed(seed, first_index + f), band)
                (out if wide else work)[k] = band[k]
        if not wide:
            np.copyto(out, work, casting="unsafe")
        yield look(out)



def h264_frames(frames, cam):
    """The rendered 8-bit ``frames`` through H.264 at ``cam.h264_qp`` and back
    (:func:`vision.compression.h264`, at the camera's frame rate).

    Raises
    ------
    SceneError
        PyAV is not installed (naming the key and ``pip install av``).
    """
    try:
        import av  # noqa: F401
    except ImportError:
        from stand.errors import SceneError

        raise SceneError(f"{cam.table}.h264_qp = {cam.h264_qp}: H.264 needs PyAV: pip install av "
                         "(or pip install 'autobalancer-stand[video]')") from None
    from vision.compression import h264

    return h264(frames, cam.h264_qp, cam.frame_rate)


def render_long_exposure(positions_px, cam, seed: Optional[int] = None, *, noise: bool = True,
                         weights=None, index: int = 0,
                         window: float = WINDOW_SIGMAS) -> np.ndarray:
    """One frame integrating all of ``positions_px`` (K, 2) [px] (e.g. a whole
    whirl period sampled densely: the circle or epitrochoid of the book's
    photographs).  The exposure is the camera's: a still spot reads ``peak``."""
    return next(render_frames([positions_px], cam, seed, noise=noise, weights=weights,
                              first_index=index, window=window))
