"""Synthetic frames with known truth, for testing and benchmarking :mod:`vision`.

In the spirit of ``trackpy.artificial``: small drawing functions whose truth is
known exactly, so that the image-processing code can be checked without the
simulator.  The models are the ones the stand's instruments draw (the laser
screen camera, the calibration rings, the light-slot stroboscope), written
again here because ``vision`` must not import ``stand``.

Laser-spot frames (:class:`Camera`, :func:`spot_frame`, :func:`spot_frames`)
    A Gaussian spot of sigma ``sigma_px`` reading ``peak`` DN at its centre
    when still, integrated exactly over each pixel (differences of erf) inside
    +-``window_sigmas`` sigma and renormalised to the full flux, so that its
    intensity centroid is its position.  A frame integrates K sub-sample
    positions (a motion-blurred arc, or a long exposure of a whirl:
    :func:`orbit_positions`), each with its fraction of the exposure; the
    exposure-averaged centre (:func:`exposure_centre`) is the truth a centroid
    estimates.  Then background, shot noise (Poisson in electrons), read noise
    (Gaussian, DN rms), rounding half up and clipping to ``[0, 2**bits - 1]``
    (saturation).  Pixels the spot does not reach are drawn from the exact
    distribution of the quantised background.
Calibration rings (:func:`camera_homography`, :func:`ring_image`)
    Thin anti-aliased circles on the screen seen through a pinhole camera
    tilted about its u axis (a homography: ellipses in the image).
Stroboscope frames (:class:`StrobeSetup`, :func:`strobe_frame`, :func:`image_multiplicity`)
    The lit rotor disk, its rim, the reference mark and the weights (balls as
    discs) at given angles, blurred over the slot's angular width, averaged
    over the flashes of an exposure, with shot and read noise.

Pixel convention: u = column (right), v = row (down), pixel centres at
integers (OpenCV's, as :mod:`vision.spot`).
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Iterable, Iterator, Optional

import numpy as np
from scipy import special

from .calibration import apply_homography

__all__ = ["Camera", "spot_signal", "expose", "spot_frame", "spot_frames", "orbit_positions",
           "exposure_centre", "camera_homography", "ring_image", "StrobeSetup", "strobe_frame",
           "image_multiplicity"]

TWO_PI = 2.0 * math.pi
FULL_WELL = 10_000.0        #: electrons at full scale for the default electrons_per_dn
READ_NOISE_DN = {8: 1.0, 10: 2.0, 12: 4.0, 14: 8.0, 16: 16.0}   #: default read noise [DN rms]
NORMAL_LENS = 1.4           #: default camera distance / imaged screen width
CHUNK = 2048                #: sub-sample positions drawn per matrix product
GUIDE_BITS = 16             #: bucket table of the background inversion: 2**16 entries


class _Quantised:
    """Full scale and frame type of a sensor with ``bit_depth`` bits."""

    __slots__ = ()
    max_dn = property(lambda self: (1 << self.bit_depth) - 1,
                      doc="Full scale (saturation) 2**bit_depth - 1 [DN].")
    dtype = property(lambda self: np.dtype(np.uint8 if self.bit_depth <= 8 else np.uint16),
                     doc="Frame type: uint8 up to 8 bits, else uint16.")


# ---------------------------------------------------------------- spot frames
@dataclass(frozen=True)
class Camera(_Quantised):
    """Sensor and spot of synthetic laser-spot frames (DN: digital numbers).

    Attributes
    ----------
    width, height : int
        Frame size [px].
    sigma_px : float or (float, float)
        Gaussian sigma of the spot [px] (along u and v); a 1/e^2 diameter D
        on a screen seen at pitch p gives D / (4 p).
    bit_depth : int
        8 (uint8 frames) or 10, 12, 14, 16 (uint16); saturation at 2**bits - 1.
    peak : float, optional
        DN above the background at the centre of a still spot; default 0.8 of
        full scale, rounded (204 at 8 bits).
    background : float, optional
        Mean DN of the spot-free screen; default 0.03 of full scale, rounded.
    read_noise : float, optional
        DN rms; default 1, 2, 4, 8, 16 at 8, 10, 12, 14, 16 bits.
    electrons_per_dn : float, optional
        Conversion gain [e-/DN]; default 10 000 e- at full scale.
    shot_noise : bool
        Poisson noise of the signal in electrons.
    window_sigmas : float
        Half-width of the drawing window [sigma].
    """

    width: int = 640
    height: int = 480
    sigma_px: object = 2.0
    bit_depth: int = 8
    peak: Optional[float] = None
    background: Optional[float] = None
    read_noise: Optional[float] = None
    electrons_per_dn: Optional[float] = None
    shot_noise: bool = True
    window_sigmas: float = 4.0

    def __post_init__(self):
        if self.bit_depth not in READ_NOISE_DN:
            raise ValueError(f"bit_depth = {self.bit_depth!r}: must be one of 8, 10, 12, 14, 16")
        top = self.max_dn
        for key, value in (("peak", float(round(0.8 * top))),
                           ("background", float(round(0.03 * top))),
                           ("read_noise", READ_NOISE_DN[self.bit_depth]),
                           ("electrons_per_dn", FULL_WELL / top)):
            if getattr(self, key) is None:
                object.__setattr__(self, key, value)
        su, sv = self.sigma_uv
        if not (su > 0 and sv > 0):
            raise ValueError(f"sigma_px = {self.sigma_px!r}: must be > 0 (px)")

    @property
    def sigma_uv(self) -> tuple:
        """(sigma_u, sigma_v) [px]."""
        s = np.broadcast_to(np.asarray(self.sigma_px, dtype=float), (2,))
        return float(s[0]), float(s[1])


def _pixel_fractions(c, sigma, half, lo, n):
    """(K, n) fraction of 1-D Gaussians (centres c, cut at c +- half and
    renormalised) falling on pixels lo..lo+n-1 (pixel k covers k +- 0.5)."""
    # the n + 1 pixel edges clipped to the cut: pixel k's right edge is pixel k+1's left one,
    # so erf is evaluated once per edge (pixels outside the cut get erf(e) - erf(e) = 0)
    edges = np.clip((lo + np.arange(n + 1))[None, :] - 0.5, (c - half)[:, None],
                    (c + half)[:, None])
    s = 1.0 / (math.sqrt(2.0) * sigma)
    E = special.erf((edges - c[:, None]) * s)
    return np.maximum(E[:, 1:] - E[:, :-1], 0.0) / (2.0 * special.erf(half * s))


def spot_signal(positions_px, cam: Camera, weights=None) -> np.ndarray:
    """Noise-free spot signal [DN above background] of one exposure.

    Parameters
    ----------
    positions_px : array_like (K, 2)
        Spot centre (u, v) [px] at K sub-samples of the exposure; non-finite
        rows are skipped (a spot off the screen).
    cam : Camera
    weights : array_like (K,), optional
        Fraction of the exposure of each sub-sample (default 1/K each); a
        still spot of weight 1 reads ``cam.peak`` at its centre.

    Returns
    -------
    numpy.ndarray (height, width), float64
    """
    p = np.asarray(positions_px, dtype=float).reshape(-1, 2)
    w = np.full(len(p), 1.0 / max(len(p), 1)) if weights is None else np.asarray(weights, float)
    if w.shape != (len(p),):
        raise ValueError(f"weights: shape {w.shape}, expected ({len(p)},)")
    su, sv = cam.sigma_uv
    hu, hv = cam.window_sigmas * su, cam.window_sigmas * sv
    u, v = p[:, 0], p[:, 1]
    ok = (np.isfinite(u) & np.isfinite(v) & (w != 0) & (u + hu >= -0.5) & (u - hu <= cam.width - 0.5)
          & (v + hv >= -0.5) & (v - hv <= cam.height - 0.5))
    out = np.zeros((cam.height, cam.width))
    if not ok.any():
        return out
    u, v, w = u[ok], v[ok], w[ok]
    j0 = max(0, int(math.floor(u.min() - hu + 0.5)))
    j1 = min(cam.width - 1, int(math.floor(u.max() + hu + 0.5)))
    i0 = max(0, int(math.floor(v.min() - hv + 0.5)))
    i1 = min(cam.height - 1, int(math.floor(v.max() + hv + 0.5)))
    flux = cam.peak * TWO_PI * su * sv * w
    box = out[i0:i1 + 1, j0:j1 + 1]
    for a in range(0, u.size, CHUNK):                   # bounded memory for long exposures
        s = slice(a, a + CHUNK)
        gu = _pixel_fractions(u[s], su, hu, j0, j1 - j0 + 1) * flux[s, None]
        gv = _pixel_fractions(v[s], sv, hv, i0, i1 - i0 + 1)
        box += gv.T @ gu
    return out


@functools.lru_cache(maxsize=32)
def _background_law(background, read_noise, shot_noise, electrons_per_dn, max_dn):
    """Law of a spot-free pixel, clip(round(N / e + read Z)) with N Poisson:
    (values, 32-bit cdf thresholds, bucket table) for :func:`_draw_background`."""
    lam = background * electrons_per_dn if shot_noise else 0.0
    read = read_noise
    if lam > 1e5:                                   # normal approximation of a huge count
        read = math.sqrt(read * read + lam / electrons_per_dn ** 2)
        lam = 0.0
    if lam > 0:
        n = np.arange(max(0, math.floor(lam - 12 * math.sqrt(lam) - 12)),
                      math.ceil(lam + 12 * math.sqrt(lam) + 12) + 1)
        p = np.exp(n * math.log(lam) - lam - special.gammaln(n + 1.0))
        dn = n / electrons_per_dn
    else:
        p, dn = np.ones(1), np.array([background])
    p = p / p.sum()
    if read > 0:
        k = np.arange(max(0, math.floor(dn.min() - 10 * read)),
                      min(max_dn, math.ceil(dn.max() + 10 * read) + 1) + 1)
        cdf = special.ndtr((k[:, None] + 0.5 - dn[None, :]) / read) @ p
    else:
        q = np.clip(np.floor(dn + 0.5), 0, max_dn).astype(int)
        k = np.arange(q.min(), q.max() + 1)
        cdf = np.cumsum(np.bincount(q - q.min(), weights=p))
    # inversion of a 32-bit uniform x: value index = #(thresholds <= x); the
    # bucket table (top GUIDE_BITS bits of x) holds the value itself unless the
    # bucket straddles a threshold (-1)
    thr = np.minimum(np.round(cdf * 2.0 ** 32), 2.0 ** 32).astype(np.int64)
    thr[-1] = 1 << 32
    start = np.arange(1 << GUIDE_BITS, dtype=np.int64) << (32 - GUIDE_BITS)
    first = np.searchsorted(thr, start, side="right")
    last = np.searchsorted(thr, start + (1 << (32 - GUIDE_BITS)) - 1, side="right")
    guide = np.where(first == last, k[np.minimum(first, k.size - 1)], -1).astype(np.int32)
    for a in (k, thr, guide):
        a.setflags(write=False)
    return k, thr, guide


def _draw_background(shape, law, rng):
    """Background pixels drawn from the quantised law (exact to 2**-32)."""
    values, thr, guide = law
    n = int(np.prod(shape))
    x = rng.bit_generator.random_raw((n + 1) // 2).view(np.uint32)[:n]
    out = guide[x >> (32 - GUIDE_BITS)]
    odd = np.flatnonzero(out < 0)
    out[odd] = values[np.searchsorted(thr, x[odd].astype(np.int64), side="right")]
    return out.reshape(shape)


def expose(signal_dn, cam: Camera, rng=None, *, noise: bool = True) -> np.ndarray:
    """Quantised frame of a signal [DN above background].

    ``noise=False``: ``round(background + signal)`` (half up), clipped.  With
    noise: the signal in electrons ``(background + signal) x electrons_per_dn``
    is Poisson (when ``shot_noise``), plus Gaussian read noise [DN rms], then
    rounded half up and clipped to ``[0, max_dn]``; pixels without signal are
    drawn from the exact law of the quantised background.

    Returns
    -------
    numpy.ndarray (height, width), ``cam.dtype``
    """
    s = np.asarray(signal_dn, dtype=float)
    if not noise:
        return np.clip(np.floor(cam.background + s + 0.5), 0, cam.max_dn).astype(cam.dtype)
    rng = np.random.default_rng(rng)
    law = _background_law(float(cam.background), float(cam.read_noise), bool(cam.shot_noise),
                          float(cam.electrons_per_dn), cam.max_dn)
    out = _draw_background(s.shape, law, rng)
    lit = s > 0
    dn = cam.background + s[lit]
    if cam.shot_noise:
        dn = rng.poisson(dn * cam.electrons_per_dn) / cam.electrons_per_dn
    dn = dn + cam.read_noise * rng.standard_normal(dn.shape)
    out[lit] = np.clip(np.floor(dn + 0.5), 0, cam.max_dn)
    return out.astype(cam.dtype)


def spot_frame(positions_px, cam: Camera, rng=None, *, noise: bool = True,
               weights=None) -> np.ndarray:
    """One frame of the spot at ``positions_px`` (K, 2) [px]: :func:`spot_signal`
    then :func:`expose`; ``rng`` a seed or :class:`numpy.random.Generator`."""
    return expose(spot_signal(positions_px, cam, weights), cam, rng, noise=noise)


def spot_frames(positions_px: Iterable, cam: Camera, *, seed: int = 0, noise: bool = True,
                weights=None) -> Iterator[np.ndarray]:
    """Frames one by one for ``positions_px`` (F, K, 2) [px] (or an iterable of
    (K, 2) arrays); frame f uses the random stream (seed, f), so every frame
    is reproducible on its own."""
    for f, block in enumerate(positions_px):
        yield spot_frame(block, cam, np.random.default_rng([seed, f]), noise=noise,
                         weights=weights)


def orbit_positions(centre_px, radius_px: float, n: int, *, turns: float = 1.0,
                    phase: float = 0.0, epicycle_px: float = 0.0,
                    epicycle_order: int = -2) -> np.ndarray:
    """(n, 2) positions [px] of a spot whirling on a circle during an exposure.

    ``z = radius e^{i th} + epicycle e^{i order th}``, th = phase + 2 pi turns
    k / n (k = 0..n-1), about ``centre_px`` (u, v): ``turns`` < 1 draws an arc
    (motion blur), several turns a long-exposure circle; an epicycle gives a
    non-circular (epitrochoid) trace.  Angles count from +u towards +v.
    """
    th = phase + TWO_PI * turns * np.arange(n) / n
    z = radius_px * np.exp(1j * th) + epicycle_px * np.exp(1j * epicycle_order * th)
    return np.column_stack([z.real, z.imag]) + np.asarray(centre_px, dtype=float)


def exposure_centre(positions_px, weights=None) -> np.ndarray:
    """Exposure-averaged spot centre [px] of (..., K, 2) positions: the truth an
    intensity centroid estimates for an unsaturated, fully visible frame."""
    p = np.asarray(positions_px, dtype=float)
    if weights is None:
        return p.mean(axis=-2)
    w = np.asarray(weights, dtype=float)
    return np.tensordot(w, p, axes=([0], [-2])) / w.sum()


# ---------------------------------------------------------------- calibration rings
def camera_homography(width: int, height: int, pixel_pitch: float, tilt: float = 0.0,
                      camera_distance: Optional[float] = None) -> np.ndarray:
    """3x3 homography screen (X, Y) [m] -> image (u, v) [px] of a pinhole camera.

    The camera looks at the screen point imaged at the frame centre
    ((width - 1)/2, (height - 1)/2) from ``camera_distance`` [m] (default
    1.4 x the imaged screen width, a normal lens), tilted by ``tilt`` [rad]
    about the image u axis (the screen's +Y side recedes for tilt > 0);
    ``pixel_pitch`` [m/px] at the centre along u; +X right, +Y up::

        u = c_u + (X / p) / (1 + s Y / d),  v = c_v - (Y cos(tilt) / p) / (1 + s Y / d)
    """
    p = float(pixel_pitch)
    d = NORMAL_LENS * width * p if camera_distance is None else float(camera_distance)
    s, c = math.sin(tilt), math.cos(tilt)
    cu, cv = 0.5 * (width - 1), 0.5 * (height - 1)
    return np.array([[1.0 / p, cu * s / d, cu], [0.0, cv * s / d - c / p, cv], [0.0, s / d, 1.0]])


def ring_image(radii_m, homography, shape, *, centre_m=(0.0, 0.0), line_width: float = 1.0,
               paper: int = 255, ink: int = 0) -> np.ndarray:
    """Calibration image: concentric rings on the screen as the camera sees them.

    Each ring of radius r [m] about ``centre_m`` is an anti-aliased line
    ``line_width`` px wide: a pixel's ink coverage is
    ``clip(line_width / 2 + 1/2 - d, 0, 1)`` with d its distance to the ring in
    px (the screen distance |rho - r| over |grad rho| in m/px, exact for the
    homography).  A zero radius draws nothing.

    Parameters
    ----------
    radii_m : array_like
        Ring radii on the screen [m].
    homography : (3, 3) array
        Screen [m] -> image [px] (:func:`camera_homography`).
    shape : (height, width)
    centre_m : (X, Y)
        Common centre [m].
    line_width : float
        [px].
    paper, ink : int
        Grey levels [DN].

    Returns
    -------
    numpy.ndarray (height, width), uint8
    """
    H, W = shape
    G = np.linalg.inv(np.asarray(homography, dtype=float))        # image -> screen
    v, u = np.mgrid[0:H, 0:W].astype(float)
    q = G[2, 0] * u + G[2, 1] * v + G[2, 2]
    X, Y = apply_homography(G, u, v)
    dx, dy = X - centre_m[0], Y - centre_m[1]
    rho = np.hypot(dx, dy)
    # d rho / d(u, v) through the Jacobian of the projective map
    dX = [(G[0, j] - X * G[2, j]) / q for j in (0, 1)]
    dY = [(G[1, j] - Y * G[2, j]) / q for j in (0, 1)]
    grad = np.hypot(dx * dX[0] + dy * dY[0], dx * dX[1] + dy * dY[1]) / np.maximum(rho, 1e-300)
    cover = np.zeros((H, W))
    for r in np.asarray(radii_m, dtype=float).ravel():
        if r > 0:
            d = np.abs(rho - r) / np.maximum(grad, 1e-300)
            np.maximum(cover, np.clip(0.5 * line_width + 0.5 - d, 0.0, 1.0), out=cover)
    return np.rint(paper + (ink - paper) * cover).astype(np.uint8)


# ---------------------------------------------------------------- stroboscope
#: grey levels of the stroboscope image, fractions of full scale
LEVELS = {"interior": 0.20, "rim": 0.45, "mark": 0.50, "ball": 0.95}
MARK_SPAN = (0.80, 0.97)    #: reference mark, fractions of the rim radius


@dataclass(frozen=True)
class StrobeSetup(_Quantised):
    """The light-slot stroboscope's view of the rotor (lengths in m).

    Attributes
    ----------
    width, height : int
        Image size [px].
    pixel_pitch : float
        [m/px] in the rotor plane.
    slot_radius : float
        Rotor radius at the slot = drawn rim radius [m].
    slot_width : float
        Widest slot [m]: each flash lasts while the rotor turns by
        ``slot_width / slot_radius`` rad (:attr:`blur`).
    track_radius : float
        Radius of the weights' centres [m].
    ball_radius : float
        Drawn ball radius [m].
    background : float
        Housing level outside the rotor, fraction of full scale.
    read_noise : float
        Gaussian read noise, rms fraction of full scale.
    full_well : float
        Electrons at full scale for the shot noise (0: none).
    bit_depth : int
        Frames are uint8 up to 8 bits, else uint16.
    """

    width: int = 320
    height: int = 320
    pixel_pitch: float = 1.0e-3
    slot_radius: float = 0.12
    slot_width: float = 0.002
    track_radius: float = 0.08
    ball_radius: float = 0.01
    background: float = 0.04
    read_noise: float = 0.004
    full_well: float = 10000.0
    bit_depth: int = 8

    @property
    def blur(self) -> float:
        """Angular blur of every image, slot_width / slot_radius [rad]."""
        return self.slot_width / self.slot_radius


def _coverage(d, half):
    """Anti-aliased coverage of a pixel at distance ``d`` [px] from a shape's
    centre line (or edge, for half = radius) of half-width ``half`` [px]."""
    return np.clip(half + 0.5 - d, 0.0, 1.0)


def _segment_distance(X, Y, a, b):
    """Distance [px] of pixels (X, Y) from the segments a[k] -> b[k] (k, 2): (k, ...)."""
    d = (b - a)[:, :, None, None]
    rel = np.stack([X, Y])[None] - a[:, :, None, None]
    L2 = np.maximum((d * d).sum(axis=1), 1e-300)
    s = np.clip((rel * d).sum(axis=1) / L2, 0.0, 1.0)
    return np.hypot(rel[:, 0] - s * d[:, 0], rel[:, 1] - s * d[:, 1])


def _box(points, half, W, H):
    """The pixels a shape of half-width ``half`` [px] about ``points`` (k, 2) can cover:
    ``_coverage`` is exactly 0 at ``d >= half + 0.5``, so the pixels outside add exactly
    nothing (the same image, drawn over a box instead of the frame).  ``None``: off the frame."""
    if not np.all(np.isfinite(points)):
        return np.s_[:, :]
    m = half + 1.0
    u0, v0 = np.floor(points.min(axis=0) - m).astype(int)
    u1, v1 = np.ceil(points.max(axis=0) + m).astype(int) + 1
    u0, v0, u1, v1 = max(u0, 0), max(v0, 0), min(u1, W), min(v1, H)
    if u0 >= u1 or v0 >= v1:
        return None
    return np.s_[v0:v1, u0:u1]


def strobe_frame(relative_angles, setup: StrobeSetup = StrobeSetup(), rng=None, *,
                 flash_angle: float = 0.0, centre_px=None,
                 weight_speed_ratio: float = 1.0) -> np.ndarray:
    """A stroboscope frame integrating one or more flashes.

    At every flash the reference mark points at ``flash_angle`` and weight j
    at ``flash_angle + relative_angles[k, j]`` (angles anticlockwise from +u,
    with +v down: a point at angle a is drawn at (u_c + r cos a, v_c - r sin a)).
    Across the slot the rotor turns by :attr:`StrobeSetup.blur` and the
    weights by ``weight_speed_ratio`` x that (their speed over the rotor's);
    each flash is the mean of sub-images across it, the frame the mean of its
    flashes (a weight seen in one of K flashes shows at 1/K contrast).

    Parameters
    ----------
    relative_angles : array_like (K, n) or (n,)
        Weight angles from the mark [rad] at each of the K flashes.
    setup : StrobeSetup
    rng : seed or numpy.random.Generator, optional
        Noise; ``None`` draws fresh noise.
    flash_angle : float
        Rotor angle at the flashes [rad].
    centre_px : (u, v), optional
        Drawn rotor centre; default the image centre.
    weight_speed_ratio : float
        Weight speed / rotor speed (1: weights locked to the rotor).

    Returns
    -------
    numpy.ndarray (height, width), uint8 or uint16
    """
    rel = np.atleast_2d(np.asarray(relative_angles, dtype=float))
    s = setup
    W, H = s.width, s.height
    uc, vc = (0.5 * (W - 1), 0.5 * (H - 1)) if centre_px is None else map(float, centre_px)
    Rr, track, ball = s.slot_radius / s.pixel_pitch, s.track_radius / s.pixel_pitch, \
        s.ball_radius / s.pixel_pitch
    n_sub = int(np.clip(math.ceil(s.blur * max(Rr, track) / 0.25), 1, 64))
    offsets = ((np.arange(n_sub) + 0.5) / n_sub - 0.5) * s.blur if n_sub > 1 else np.zeros(1)
    X, Y = np.meshgrid(np.arange(W, dtype=float), np.arange(H, dtype=float))
    r = np.hypot(X - uc, Y - vc)
    base = np.full((H, W), s.background)
    base += (LEVELS["interior"] - base) * _coverage(r, Rr)
    base += (LEVELS["rim"] - base) * _coverage(np.abs(r - Rr), 1.0)

    def at(radius, angles):
        return np.column_stack([uc + radius * np.cos(angles), vc - radius * np.sin(angles)])

    mark = flash_angle + offsets
    a0, a1 = at(MARK_SPAN[0] * Rr, mark), at(MARK_SPAN[1] * Rr, mark)
    box = _box(np.vstack([a0, a1]), 1.5, W, H)
    if box is not None:
        d_mark = _segment_distance(X[box], Y[box], a0, a1)
        base[box] += (LEVELS["mark"] - base[box]) * _coverage(d_mark, 1.5).mean(axis=0)
    acc = np.zeros((H, W))
    for flash in rel:
        img = base.copy()
        for a in flash:
            c = at(track, flash_angle + a + weight_speed_ratio * offsets)
            box = _box(c, ball, W, H)
            if box is None:
                continue
            Xb, Yb = X[box], Y[box]
            d = np.hypot(Xb[None] - c[:, 0, None, None], Yb[None] - c[:, 1, None, None])
            img[box] += (LEVELS["ball"] - img[box]) * _coverage(d, ball).mean(axis=0)
        acc += img
    acc /= len(rel)
    rng = np.random.default_rng(rng)
    if s.full_well > 0:
        acc = rng.poisson(np.clip(acc, 0, None) * s.full_well) / s.full_well
    if s.read_noise > 0:
        acc = acc + rng.normal(0.0, s.read_noise, acc.shape)
    return np.rint(np.clip(acc, 0.0, 1.0) * s.max_dn).astype(s.dtype)


def image_multiplicity(angles, blur: float) -> int:
    """Number of distinct weight images expected for ``angles`` [rad] (any shape).

    Angles on the circle closer than ``blur`` [rad] merge into one image
    (chains of neighbours each within ``blur``); for drawn balls the natural
    ``blur`` is ``2 ball_radius / track_radius + slot_width / slot_radius``.
    """
    a = np.sort(np.mod(np.ravel(np.asarray(angles, dtype=float)), TWO_PI))
    if a.size == 0:
        return 0
    gaps = np.diff(a, append=a[0] + TWO_PI)
    return max(1, int(np.count_nonzero(gaps > blur)))
