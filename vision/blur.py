"""Motion-blurred, possibly saturated laser spot: a least-squares model fit.

The laser spot on a whirling shaft moves on a circle; during one exposure it
draws an arc.  The camera integrates the spot along that arc and clips the
result at full scale.  The intensity centroid estimates the exposure-averaged
position only while nothing is clipped: clipping removes the flux of the
arc's core, and on a curved arc (or one whose brightness varies along it)
what it removes is not symmetric about the mean position, so the centroid is
biased: 0.2-0.65 px on synthetic curved arcs clipped at 80x full scale
(``tests/test_video_track.py``), 0.22 px RMS and up to 1.0 px on the stand's
video sample (``data_samples/video/``).  This module fits the image instead.

Model
-----
Pixel (u, v) [px] reads ``b + A * integral of G_s(u - p_u(x), v - p_v(x)) dx/2``
over the exposure, clipped at full scale: a still spot of peak ``A`` [DN above
the background b], a Gaussian of sigma ``s`` [px] integrated over each pixel's
area, swept along the path p(x), x in [-1, 1] the time through the exposure:

    p(x) = m + (T(x) + a2 P2(x)) h + (N(x) + a3 P3(x)) J h

* m = (m_u, m_v) [px]: the **exposure-averaged position** (what
  ``truth/screen/centre_px`` of a recording holds) -- every other term has
  zero mean over x, so m is a fitted parameter with its own uncertainty;
* h = (h_u, h_v) [px]: the path's direction (tangent at mid-exposure) and its
  half-length l = |h| along the path; J h is h turned by +90 deg;
* kappa [1/px]: curvature (signed, 0 = a straight segment): with beta = kappa l,
  T = sin(beta x)/beta and N = (sin(beta)/beta - cos(beta x))/beta describe a
  circular arc swept at constant speed (series near beta = 0, so the path is
  smooth through a straight segment and through h = 0, a still spot);
* a2, a3 (dimensionless): the speed changing along the arc (P2 = x^2 - 1/3
  along h) and the curvature changing along it (P3 = x^3 - 3x/5 across h).  A
  shaft whirling at the rotor speed while its free vibration (or the balls'
  drift) is not yet gone moves the spot on such a path: on the stand's video
  sample a constant-speed arc misses the true path by up to 1.1 px, this one by
  0.11 px.

The integral is a sum over n points at equal steps of time (at most one sigma
apart) with Gregory's end corrections (weights 3/8, 7/6, 23/24, 1, ...): the
plain midpoint sum errs by ~step^2/(24 s^2) near the path's ends (4 % at one
sigma), which biased curved arcs by 0.02-0.04 px.  A short path (l <= 2.5 s)
takes 4, 5 or 6 Gauss-Legendre nodes instead of the 7 steps (l <= s, 1.5 s,
2.5 s; :func:`vision._blur_kernel.n_points`): its largest pixel error relative
to the model's peak, against 4001 points, is at most 0.29, 0.25 and 0.53 times
the 7 steps' (s = 0.35-3 px, l = 0.05-2.5 s, kappa s = 0, +-0.5, +-1, the
tightest bend allowed; e.g. s = 2 px, kappa s = 1: l = s 1.8e-4 for 7.1e-4,
l = 2.5 s 3.5e-3 for 6.9e-3), at 4/7-6/7 of the cost.

Fit
---
Levenberg-Marquardt on the pixels of the blob and a margin (``mask``), with
an analytic Jacobian; parameters (m_u, m_v, h_u, h_v, kappa, a2, a3, ln A,
ln s).  First with a2 = a3 = 0 (a constant-speed arc); then, when a robust
score test says the data ask for them (chi-square with 2 degrees of freedom
above ``SCORE_LIMIT``, p = 0.05), with them free: on noiseless constant-speed
arcs they would only add noise.  A **clipped pixel** (at full scale) only says M >= full scale - 0.5 DN:
its residual is that value minus M while the model is below it, else 0 (and
it then leaves the Jacobian) -- a censored residual.  Starting values: the
blob's moments (centroid, principal axis, second and third moments) and, for
long blobs, an algebraic circle fit; the amplitude by linear least squares on
the unclipped pixels.  In a video the previous frame's A and s start the next
fit, and a short blob's fit also tries the previous path turned by the whirl's
step first (``warm``, :func:`vision.spot.track`).  The loop and the normal equations are
:mod:`vision._blur_kernel` (compiled by numba) or :mod:`vision._blur_numpy` (plain
Python and numpy).

The centre's uncertainty is the (m_u, m_v) block of the sandwich covariance
``B^-1 M B^-1`` (B = J^T J, M = sum r^2 J J^T): the camera's noise model is not
assumed (the bright pixels' shot noise is larger than the background's), and a
misfit widens it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ._blur_start import half_sweep as _half_sweep

half_sweep = getattr(_half_sweep, "py_func", _half_sweep)   # the plain function, compiled or not

__all__ = ["BlurFit", "fit_blurred_spot", "fit_prepared", "initial_guesses", "arc_points", "model_image",
           "warm", "compile_needed", "MAX_ITER", "CENTRE_TOL"]

MAX_ITER = 40           #: Levenberg-Marquardt iterations at most
#: px, last step of the centre at convergence (that step is taken; what it leaves is of
#: second order): against 2e-3 on the video sample the centres moved by 0.0005 px RMS,
#: 0.005 px at most (their stated std 0.006 px, their error 0.014 px RMS, unchanged), in
#: 5 % fewer iterations
CENTRE_TOL = 5e-3
COST_TOL = 1e-2         #: ... and relative decrease of the residual sum of squares
MAX_SWEEP = math.pi     #: rad, largest half-angle beta = kappa l of the arc (a full circle)
MAX_SHAPE = 0.5         #: largest |a2|, |a3| (beyond, the path folds back on itself)
MIN_SIGMA = 0.35        #: px, smallest spot sigma accepted
MAX_POINTS = 4000       #: points along the path at most
N_PARAMS = 9
IA, IS = 7, 8           #: indices of ln A and ln s (a2, a3 are 5, 6)
SCORE_LIMIT = 6.0       #: score statistic (chi-square, 2 dof) above which a2, a3 are fitted (p = 0.05)


@dataclass
class BlurFit:
    """Result of :func:`fit_blurred_spot` (pixels, u = column, v = row, in the
    coordinates of the patch passed in).

    Attributes
    ----------
    u, v : float
        Exposure-averaged spot position (the mean over the path) [px].
    u_std, v_std : float
        Standard uncertainties of ``u``, ``v`` [px].
    half_path : (float, float)
        h = (h_u, h_v) [px]: the path's direction (its tangent at mid-exposure) and
        half-length l = |h| measured along it.
    curvature : float
        kappa [1/px], signed (positive: the path turns towards +90 deg from h).
    shape : (float, float)
        (a2, a3): speed and curvature changes along the path (module docstring).
    amplitude : float
        A [DN above background]: the peak of the still spot.
    sigma : float
        s [px], the spot's Gaussian sigma.
    chi2 : float
        Residual sum of squares per degree of freedom [DN^2].
    n_pixels, n_clipped : int
        Pixels fitted, and how many of them were at full scale.
    iterations : int
    converged : bool
    """

    u: float
    v: float
    u_std: float
    v_std: float
    half_path: tuple
    curvature: float
    shape: tuple
    amplitude: float
    sigma: float
    chi2: float
    n_pixels: int
    n_clipped: int
    iterations: int
    converged: bool

    @property
    def length(self) -> float:
        """Length of the path [px] (2 l, measured along the arc)."""
        return 2.0 * math.hypot(*self.half_path)


# ---------------------------------------------------------------- path
def _n_points(ell: float, s: float) -> int:
    """Points along a path of half-length ``ell`` [px] (:func:`vision._blur_kernel.n_points`):
    4-6 Gauss-Legendre nodes up to 2.5 sigma ``s``, else at most one sigma apart, at least 7."""
    from ._blur_kernel import n_points

    return n_points(float(ell), float(s), MIN_SIGMA, MAX_POINTS)


def arc_points(u, v, half_path, curvature, shape=(0.0, 0.0), n: int = 64):
    """Points (u_k, v_k) [px] of a path (the parameters of a :class:`BlurFit`) at
    ``n`` equal steps of time, both ends included."""
    from ._blur_kernel import path

    pts = path(float(u), float(v), float(half_path[0]), float(half_path[1]),
               float(curvature), float(shape[0]), float(shape[1]), max(int(n), 7))
    return pts[0], pts[1]


def _dense_model(p, shape) -> np.ndarray:
    """Unclipped model above background over a whole (rows, columns) patch; ``p``
    in the internal form (..., ln A, ln s)."""
    from ._blur_kernel import path
    from ._blur_numpy import _profile

    s = math.exp(p[IS])
    u, v, w, _, _ = path(p[0], p[1], p[2], p[3], p[4], p[5], p[6],
                         _n_points(math.hypot(p[2], p[3]), s))
    gu = _profile(np.arange(shape[1], dtype=float)[None, :] - u[:, None], s)[0] * w[:, None]
    gv = _profile(np.arange(shape[0], dtype=float)[None, :] - v[:, None], s)[0]
    return math.exp(p[IA]) * (gv.T @ gu)


def model_image(shape, u, v, half_path, curvature, amplitude, sigma, *, path_shape=(0.0, 0.0),
                background=0.0, saturation=None) -> np.ndarray:
    """The model image (rows x columns = ``shape``) of given parameters [px, DN],
    clipped at ``saturation`` when given (for plots and tests)."""
    p = np.array([u, v, half_path[0], half_path[1], curvature, path_shape[0], path_shape[1],
                  math.log(amplitude), math.log(sigma)], float)
    m = _dense_model(p, shape) + background
    return m if saturation is None else np.minimum(m, saturation)


# ---------------------------------------------------------------- initial values
def _circle_guess(w, du, dv, tot):
    """A long blob's arc: intensity-weighted algebraic circle fit (Kasa) in coordinates
    (du, dv) about the centroid -> ``(l, t_u, t_v, kappa, radial sd)``, or None.

    The arc's half-angle beta from the weights' mean cosine about their mean
    direction, ``sin(beta)/beta`` for a uniform sweep; l = R beta; h along the
    counter-clockwise tangent at the arc's middle, so kappa = +1/R (the centre on
    the +90 deg side of h).
    """
    sel = w > 0
    x = np.broadcast_to(du, w.shape)[sel]
    y = np.broadcast_to(dv, w.shape)[sel]
    ww = w[sel]
    z = x * x + y * y
    M = np.stack([x, y, np.ones_like(x)], axis=1)
    Mw = M * ww[:, None]
    try:
        D, E, F = np.linalg.solve(Mw.T @ M, -(Mw.T @ z))
    except np.linalg.LinAlgError:
        return None
    cu, cv = -0.5 * D, -0.5 * E
    R2 = cu * cu + cv * cv - F
    if not 0 < R2 < 1e8:          # no circle, or practically straight
        return None
    R = math.sqrt(R2)
    ang = np.arctan2(y - cv, x - cu)
    c0 = float((ww * np.cos(ang)).sum()) / tot
    s0 = float((ww * np.sin(ang)).sum()) / tot
    mid = math.atan2(s0, c0)
    C = min(math.hypot(c0, s0), 1.0)
    b = half_sweep(C, MAX_SWEEP)                               # sin(b)/b = C
    rad = np.hypot(x - cu, y - cv) - R
    sd = math.sqrt(float((ww * rad * rad).sum()) / tot)
    return R * b, -math.sin(mid), math.cos(mid), 1.0 / R, sd


def _amplitude(p, patch, mask, level, clipped) -> float:
    """ln A for the geometry and sigma of ``p``: linear least squares on the unclipped
    pixels, raised to reach full scale on every clipped pixel."""
    q = p.copy()
    q[IA] = 0.0
    unit = _dense_model(q, patch.shape)
    use = mask & ~clipped
    den = float((unit[use] ** 2).sum())
    A = float(((patch[use] - level) * unit[use]).sum()) / den if den > 0 else 1.0
    if clipped.any():
        need = float(((patch[clipped] - level) / np.maximum(unit[clipped], 1e-12)).max())
        A = max(A, need)
    return math.log(max(A, 1e-6))


def initial_guesses(patch: np.ndarray, mask: np.ndarray, level: float, clipped: np.ndarray,
                    sigma: Optional[float] = None, amplitude: Optional[float] = None,
                    engine: str = "auto") -> list:
    """Starting parameters from the blob's moments (patch coordinates, internal form
    (m_u, m_v, h_u, h_v, kappa, a2, a3, ln A, ln s)): one or two candidates, the fit
    starts from the better.

    * segment: centroid -> m; principal axis -> direction of h; a uniform segment
      of half length l has variance l^2/3 + s^2 along and s^2 across (their
      difference is l^2/3 also when clipping widens the blob); the curvature
      from the third moment E[n (t^2 - E t^2)] = kappa l^4 * 2/45 of a circular arc;
    * for a long blob (l > 5 s) also the arc of an algebraic circle fit.

    ``sigma`` [px] and ``amplitude`` [DN] (e.g. the previous frame's fit) replace
    the moment estimates of s and A.  ``engine``: as in :func:`fit_blurred_spot` (the
    compiled loops of :mod:`vision._blur_start` or numpy: the same numbers).
    """
    from ._blur_start import compiled_start

    shrink = 0.8 if clipped.any() else 1.0
    fast = compiled_start() if engine != "numpy" else None
    if fast is not None:
        out = list(fast(np.ascontiguousarray(patch, dtype=np.float64), mask, float(level),
                        float(sigma or 0.0), shrink, MAX_SWEEP))
        if not out:
            raise ValueError("blob: no signal above the background")
    else:
        out = _moment_guesses(patch, mask, level, shrink, sigma)
    for p in out:
        p[IA] = math.log(amplitude) if amplitude else _amplitude(p, patch, mask, level, clipped)
    return out


def _moment_guesses(patch, mask, level, shrink, sigma) -> list:
    """:func:`initial_guesses` in numpy, without the amplitude."""
    H, W = patch.shape
    w = np.where(mask, np.maximum(patch - level, 0.0), 0.0)
    tot = float(w.sum())
    if not tot > 0:
        raise ValueError("blob: no signal above the background")
    rows = np.arange(H, dtype=float)
    cols = np.arange(W, dtype=float)
    mu = float(w.sum(axis=0) @ cols) / tot
    mv = float(w.sum(axis=1) @ rows) / tot
    du = cols[None, :] - mu
    dv = rows[:, None] - mv
    cuu = float((w * du * du).sum()) / tot
    cvv = float((w * dv * dv).sum()) / tot
    cuv = float((w * du * dv).sum()) / tot
    tr, det = cuu + cvv, cuu * cvv - cuv * cuv
    disc = math.sqrt(max(0.25 * tr * tr - det, 0.0))
    lam1, lam2 = 0.5 * tr + disc, max(0.5 * tr - disc, 0.0)
    ang = 0.5 * math.atan2(2.0 * cuv, cuu - cvv)
    tu, tv = math.cos(ang), math.sin(ang)
    # a clipped core flattens the profile (shrink): its across variance overestimates s^2
    s0 = sigma if sigma else max(math.sqrt(lam2) * shrink, 0.7)
    # (clipping widens both directions alike: the difference stays l^2 / 3)
    ell = math.sqrt(max(3.0 * (lam1 - lam2), 0.0))
    kap = 0.0
    if ell > 2.0 * s0:
        t = du * tu + dv * tv
        nn = -du * tv + dv * tu
        m3 = float((w * nn * (t * t - lam1)).sum()) / tot
        kap = m3 * 45.0 / (2.0 * ell ** 4)
        kap = max(min(kap, 0.5 * MAX_SWEEP / ell), -0.5 * MAX_SWEEP / ell)
    out = [np.array([mu, mv, ell * tu, ell * tv, kap, 0.0, 0.0, 0.0, math.log(s0)])]
    if ell > 5.0 * s0:
        arc = _circle_guess(w, du, dv, tot)
        if arc is not None:
            el, cu_, cv_, ka, s_arc = arc
            s1 = sigma if sigma else max(s_arc * shrink, 0.7)
            out.append(np.array([mu, mv, el * cu_, el * cv_, ka, 0.0, 0.0, 0.0, math.log(s1)]))
    return out


# ---------------------------------------------------------------- fit
def fit_blurred_spot(patch, mask, level: float, *, saturation: Optional[float] = None,
                     p0=None, sigma: Optional[float] = None, amplitude: Optional[float] = None,
                     max_iter: int = MAX_ITER, engine: str = "auto", warm=None) -> BlurFit:
    """Fit the motion-blurred, clipped spot model to one blob.

    Parameters
    ----------
    patch : 2-D array
        The image around the blob [DN] (any dtype); coordinates of the result are
        the patch's (pixel centres at integers).
    mask : 2-D bool array (patch's shape)
        Pixels to fit: the blob and a margin of about 2 sigma around it.
    level : float
        Background [DN].
    saturation : float, optional
        Full-scale value [DN]; pixels at or above it are clipped (censored).
    p0 : array (9,), optional
        Starting parameters (m_u, m_v, h_u, h_v, kappa, a2, a3, A, s) [px, 1/px, 1,
        1, DN, px]; default :func:`initial_guesses`.
    sigma, amplitude : float, optional
        Starting s [px] and A [DN] (e.g. the previous frame's fit, in a video);
        default from the blob's moments.
    max_iter : int
    warm : (float, float, float), optional
        A further starting path (h_u, h_v, kappa) [px, px, 1/px], tried first, about the
        blob's centroid with the moments' sigma (or ``sigma``): in a video the previous
        frame's path turned by the whirl's step (:func:`vision.spot.track`; not for a
        long blob, :func:`_with_warm`): on the video sample 4.76 -> 4.09 iterations per
        fit (at ``CENTRE_TOL`` 2e-3 px; 4.62 -> 3.89 at 5e-3).
    engine : {"auto", "numba", "numpy"}
        The fit loop and normal equations (:mod:`vision._blur_kernel`): compiled by
        numba, or plain Python and numpy (the same numbers); "auto": compiled when
        numba is available and not disabled (``STAND_DISABLE_JIT``, ``NUMBA_DISABLE_JIT``).

    Returns
    -------
    BlurFit

    Raises
    ------
    ValueError
        Shapes that differ, a blob without signal, a mask of fewer than 2 x 9 pixels.
    """
    patch = np.ascontiguousarray(patch, dtype=np.float64)   # one compiled specialisation
    mask = np.asarray(mask, dtype=bool)
    if patch.ndim != 2 or mask.shape != patch.shape:
        raise ValueError(f"patch {patch.shape} and mask {mask.shape}: expected the same 2-D shape")
    n_pix = int(mask.sum())
    if n_pix < 2 * N_PARAMS:
        raise ValueError(f"mask: {n_pix} pixels, need at least {2 * N_PARAMS}")
    if saturation is not None:
        clipped = mask & (patch >= float(saturation))
        sat_eff = float(saturation) - 0.5       # a pixel at full scale read >= sat - 0.5
    else:
        clipped = np.zeros_like(mask)
        sat_eff = math.inf
    pi, pj = np.nonzero(mask)
    if p0 is None:
        starts = initial_guesses(patch, mask, level, clipped, sigma, amplitude, engine)
        if warm is not None:
            starts = list(_with_warm(np.array(starts, float), warm))
    else:
        p = np.array(p0, float)
        if p.shape != (N_PARAMS,):
            raise ValueError(f"p0: expected {N_PARAMS} parameters, got shape {p.shape}")
        p[IA], p[IS] = math.log(max(p[IA], 1e-6)), math.log(max(p[IS], MIN_SIGMA))
        starts = [p]
    return _fit(patch, pi.astype(np.int64), pj.astype(np.int64), clipped[pi, pj], level, sat_eff,
                np.array(starts, float), max_iter, engine)


def fit_prepared(patch, mask, pi, pj, clipped, starts, level: float,
                 saturation: Optional[float], amplitude: Optional[float] = None,
                 warm=None) -> BlurFit:
    """:func:`fit_blurred_spot` (compiled engine) from the inputs
    :func:`vision._blur_start.blob_inputs` prepared in one compiled pass: the mask's pixels
    ``pi``, ``pj`` (int64), which are ``clipped`` (bool), the starting rows (ln A filled
    here: ``amplitude`` [DN], else by least squares); ``warm`` as in
    :func:`fit_blurred_spot`."""
    if pi.size < 2 * N_PARAMS:
        raise ValueError(f"mask: {pi.size} pixels, need at least {2 * N_PARAMS}")
    if not starts.shape[0]:
        raise ValueError("blob: no signal above the background")
    if warm is not None:
        starts = _with_warm(starts, warm)
    if amplitude:
        starts[:, IA] = math.log(amplitude)
    else:
        cl = mask & (patch >= saturation) if saturation is not None else np.zeros_like(mask)
        for p in starts:
            p[IA] = _amplitude(p, patch, mask, level, cl)
    sat_eff = math.inf if saturation is None else float(saturation) - 0.5
    return _fit(patch, pi, pj, clipped, level, sat_eff, starts, MAX_ITER, "auto")


def _with_warm(starts, warm):
    """The starting rows with ``warm`` (h_u, h_v, kappa) first: its centre, sigma (and
    amplitude) the first row's.  Not for a long blob (two rows, the moments' and the circle
    fit's): there the moments' row was the best start in 117 of 119 fits of the video
    sample, the warm one in 2 (a short blob's: the warm one in 359 of 384)."""
    if starts.shape[0] > 1:
        return starts
    out = np.empty((starts.shape[0] + 1, N_PARAMS))
    out[1:] = starts
    out[0] = starts[0]
    out[0, 2:5] = warm
    return out


_CONSTS = np.array([MIN_SIGMA, MAX_SWEEP, MAX_SHAPE, MAX_POINTS], float)
_TOL = np.array([CENTRE_TOL, COST_TOL])


def _fit(patch, pi, pj, clipped, level, sat_eff, starts, max_iter, engine) -> BlurFit:
    """The fit (:func:`_fit_function`) from its starting rows; the centre's sandwich
    covariance scaled by n / dof."""
    p, cost, var, free, it, converged = _fit_function(engine)(
        patch, pi, pj, clipped, float(level), sat_eff, starts, math.hypot(*patch.shape),
        _CONSTS, _TOL, int(max_iter), float(SCORE_LIMIT))
    n_pix = pi.size
    dof = max(n_pix - int(np.count_nonzero(free)), 1)
    scale = n_pix / dof
    p, (vu, vv) = p.tolist(), var.tolist()      # (Python floats: fewer numpy scalars)
    return BlurFit(p[0], p[1], math.sqrt(max(vu * scale, 0.0)), math.sqrt(max(vv * scale, 0.0)),
                   (p[2], p[3]), p[4], (p[5], p[6]), math.exp(p[IA]), math.exp(p[IS]),
                   float(cost / dof), n_pix, int(np.count_nonzero(clipped)), int(it),
                   bool(converged))


_FITS = {}      # engine -> the compiled fit, once found (a per-frame lookup in a video)


def _fit_function(engine: str = "auto"):
    """The fit (:func:`vision._blur_kernel.fit_loops`) for ``engine``: "numba" compiled
    (numba imported on the first call, ``cache=True``), "numpy" the plain Python loop over
    the numpy normal equations (:mod:`vision._blur_numpy`), "auto" the first available.
    Raises RuntimeError for "numba" without it."""
    if engine in _FITS:
        return _FITS[engine]
    from ._blur_kernel import compiled_fit
    from ._blur_numpy import python_fit

    if engine in ("auto", "numba"):
        fit = compiled_fit()
        if fit is not None:
            return _FITS.setdefault(engine, fit)
        if engine == "numba":
            raise RuntimeError("engine='numba': numba is not available (or disabled)")
    return python_fit()


def warm() -> str:
    """Compile the fit ahead (or load it from numba's cache: about 10 s the first time
    after an install, then 0.3 s per process) for the argument types
    :func:`fit_blurred_spot` passes; returns the engine, "numba" or "numpy"."""
    from ._blur_kernel import compiled_available

    engine = "numba" if compiled_available() else "numpy"
    rows, cols = np.mgrid[0:24, 0:24]
    patch = 8.0 + 200.0 * np.exp(-((cols - 11.7) ** 2 + (rows - 12.2) ** 2) / 8.0)
    pi = rows.ravel().astype(np.int64)
    pj = cols.ravel().astype(np.int64)
    start = np.array([[11.5, 12.0, 1.0, 0.5, 0.0, 0.0, 0.0, math.log(200.0), math.log(2.0)]])
    _fit_function(engine)(patch, pi, pj, np.zeros(pi.size, np.bool_), 8.0, np.inf, start,
                          34.0, np.array([0.35, math.pi, 0.5, 4000.0]), np.array([2e-3, 1e-2]),
                          40, 6.0)
    initial_guesses(patch, np.ones(patch.shape, bool), 8.0, np.zeros(patch.shape, bool),
                    engine=engine)          # the compiled starting values too
    if engine == "numba":                   # and the tracker's front and one-call preparation
        from ._blur_start import compiled_blob_inputs
        from ._spot_front import compiled_front

        for labels in (np.ones(patch.shape, np.int32), np.ones(patch.shape, np.uint8)):
            compiled_blob_inputs()(patch, labels, 1, 0, 0, np.ones((3, 3), np.uint8), 255.0,
                                   8.0, 0.0, MAX_SWEEP)
        frame = np.clip(patch, 0, 255).astype(np.uint8)   # (regions are passed contiguous)
        compiled_front()(frame, frame.astype(np.float32), 11, 12, 208.0, math.nan, math.nan,
                         247.0, 4, 2)
    return engine


def compile_needed() -> bool:
    """True when the first fit in this process will compile (no cache yet): a command can
    say so before the wait."""
    from ._blur_kernel import compile_needed as _needed

    return _needed()
