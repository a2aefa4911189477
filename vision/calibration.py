"""Ring calibration of the laser screen (issue 6, item 3): image px <-> screen m,
and screen radius -> unbalance zone (monograph section 4.3.2).

Pixel convention: u = column (right), v = row (down), pixel centres at
integers.  Screen coordinates X, Y [m]: +X right, +Y up, origin at the common
centre of the calibration rings (the undeflected beam).

* :func:`detect_rings` -- the concentric family of dark rings in a calibration
  image, each as a sub-pixel :class:`Ellipse` (intensity-weighted conic fit to
  one connected ring), sorted by size;
* :func:`fit_homography` -- the homography screen (m) -> image (px) from the
  rings and their known radii (least squares on every ring pixel: radial
  distance on the screen minus the ring radius), returned as a
  :class:`Calibration` (scale m/px, centre, tilt amount and direction);
* :func:`scale_from_fiducials` -- a plain similarity (scale, rotation, shift)
  from >= 2 points of known screen position (ruler, fiducial marks);
* :func:`px_to_m`, :func:`m_to_px` -- apply a calibration;
* :func:`zone_map` -- screen radius -> zone i (i S / 16) and unbalance as a
  fraction of the capacity S.

The rotation of the screen about the ring centre cannot be seen from circles;
:func:`fit_homography` fixes it so that the screen +X axis maps onto the image
+u direction at the centre (and +Y onto -v: the screen is seen un-mirrored).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import NamedTuple, Optional, Sequence

import cv2
import numpy as np
from scipy.optimize import least_squares

from .camera_artefacts import distort_points, undistort_points

try:  # the package-wide error type, when the I/O module provides one
    from .io import VisionError  # type: ignore
except Exception:  # pragma: no cover - depends on the parallel work on vision.io
    class VisionError(ValueError):
        """Bad input to a vision function (blank image, nothing found, ...)."""

__all__ = ["VisionError", "Ellipse", "Calibration", "ZoneReading", "detect_rings",
           "fit_homography", "scale_from_fiducials", "px_to_m", "m_to_px", "apply_homography",
           "zone_map", "PARTS"]

PARTS = 16  #: the capacity S is divided into 16 parts (zones i S / 16)


# ---------------------------------------------------------------- ellipses
@dataclass(frozen=True)
class Ellipse:
    """One detected ring.

    centre : (u, v) px;  axes : (semi-major, semi-minor) px;  angle : rad, of
    the major axis from +u towards +v;  points : (N, 2) ring pixels (u, v);
    weights : (N,) ink coverage of those pixels (0..1);  rms : px, rms
    algebraic-distance residual of the fit, converted to px.
    """
    centre: tuple
    axes: tuple
    angle: float
    points: np.ndarray = field(repr=False)
    weights: np.ndarray = field(repr=False)
    rms: float = 0.0

    @property
    def size(self) -> float:
        """Mean semi-axis [px]."""
        return 0.5 * (self.axes[0] + self.axes[1])


def _fit_conic(u, v, w):
    """Weighted algebraic conic fit a u^2 + b uv + c v^2 + d u + e v + f = 0
    (normalised coordinates); returns the ellipse (centre, axes, angle) or None."""
    mu, mv = np.average(u, weights=w), np.average(v, weights=w)
    s = math.sqrt(max(np.average((u - mu) ** 2 + (v - mv) ** 2, weights=w), 1e-12))
    x, y = (u - mu) / s, (v - mv) / s
    D = np.stack([x * x, x * y, y * y, x, y, np.ones_like(x)], axis=1) * np.sqrt(w)[:, None]
    _, _, Vt = np.linalg.svd(D, full_matrices=False)
    a, b, c, d, e, f = Vt[-1]
    det = 4 * a * c - b * b
    if not det > 0:
        return None
    x0 = (b * e - 2 * c * d) / det
    y0 = (b * d - 2 * a * e) / det
    # value at the centre and the quadratic form's eigen-decomposition
    f0 = a * x0 * x0 + b * x0 * y0 + c * y0 * y0 + d * x0 + e * y0 + f
    M = np.array([[a, b / 2], [b / 2, c]])
    lam, vec = np.linalg.eigh(M)
    if not np.all(lam * -f0 > 0):
        return None
    semi = np.sqrt(-f0 / lam) * s             # semi-axes along the eigenvectors
    k = int(np.argmax(semi))
    ang = math.atan2(vec[1, k], vec[0, k])
    centre = (mu + x0 * s, mv + y0 * s)
    # residual: approx geometric distance |Q| / |grad Q|
    Q = a * x * x + b * x * y + c * y * y + d * x + e * y + f
    gx, gy = 2 * a * x + b * y + d, b * x + 2 * c * y + e
    dist = np.abs(Q) / np.maximum(np.hypot(gx, gy), 1e-300) * s
    rms = float(np.sqrt(np.average(dist * dist, weights=w)))
    return centre, (float(semi[k]), float(semi[1 - k])), ang, rms


def _as_gray(image) -> np.ndarray:
    img = np.asarray(image)
    if img.ndim == 3 and img.shape[2] in (3, 4):
        img = cv2.cvtColor(img[..., :3].astype(np.float32), cv2.COLOR_BGR2GRAY)
    if img.ndim != 2 or img.size == 0:
        raise VisionError(f"image: expected a 2-D grey image, got shape {np.shape(image)}")
    img = img.astype(np.float64)
    if not np.all(np.isfinite(img)):
        raise VisionError("image: contains non-finite values")
    return img


def detect_rings(image, *, min_points: int = 20, max_rms_px: float = 0.6,
                 centre_tol_px: Optional[float] = None, dark_rings: bool = True) -> list:
    """Detect the concentric calibration rings of an image.

    Ink pixels (darker than half-way between paper and ink; ``dark_rings=False``
    for bright rings on a dark ground) are split into connected components;
    each component with at least ``min_points`` pixels gets an ink-weighted
    conic fit; ellipses whose fit residual is below ``max_rms_px`` are kept,
    and of those the concentric family: centres within ``centre_tol_px``
    (default 2 px + 5 % of the ellipse size) of the size-weighted median centre.

    Returns
    -------
    list of Ellipse, sorted by size (innermost first).

    Raises
    ------
    VisionError
        Blank/flat image, no ring-like component, fewer than 2 concentric rings.
    """
    img = _as_gray(image)
    lo, hi = np.percentile(img, [0.5, 99.5])
    if not hi - lo > 1e-9 * max(1.0, abs(hi)) or hi - lo <= 0:
        raise VisionError("detect_rings: blank image (no contrast)")
    ink = (hi - img) / (hi - lo) if dark_rings else (img - lo) / (hi - lo)
    ink = np.clip(ink, 0.0, 1.0)
    mask = (ink > 0.5).astype(np.uint8)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
    # grow each component by one pixel so that the anti-aliased edges count too
    grown = cv2.dilate(labels.astype(np.float32), np.ones((3, 3), np.uint8))
    found = []
    for k in range(1, n):
        if stats[k, cv2.CC_STAT_AREA] < min_points:
            continue
        x0, y0, w, h = (stats[k, c] for c in (cv2.CC_STAT_LEFT, cv2.CC_STAT_TOP,
                                              cv2.CC_STAT_WIDTH, cv2.CC_STAT_HEIGHT))
        if min(w, h) < 5:
            continue
        sl = (slice(max(0, y0 - 1), y0 + h + 1), slice(max(0, x0 - 1), x0 + w + 1))
        sub = (labels[sl] == k) | ((grown[sl] == k) & (labels[sl] == 0))
        vv, uu = np.nonzero(sub)
        wt = ink[sl][vv, uu]
        keep = wt > 0.02
        uu = uu[keep] + sl[1].start
        vv = vv[keep] + sl[0].start
        wt = wt[keep]
        if uu.size < min_points:
            continue
        fit = _fit_conic(uu.astype(float), vv.astype(float), wt)
        if fit is None:
            continue
        centre, axes, ang, rms = fit
        if rms > max_rms_px or axes[1] < 2.0 or axes[1] / axes[0] < 0.5:
            continue
        # a ring: its pixels go round the centre (not a short arc or a blob)
        phi = np.arctan2(vv - centre[1], uu - centre[0])
        cover = np.unique(np.floor((phi + math.pi) / (2 * math.pi) * 36).astype(int)).size
        if cover < 18:
            continue
        found.append(Ellipse(centre=(float(centre[0]), float(centre[1])), axes=axes,
                             angle=float(ang), points=np.stack([uu, vv], 1).astype(float),
                             weights=wt, rms=rms))
    if not found:
        raise VisionError("detect_rings: no rings found (no closed ring-like curve in the image)")
    cu = np.median([e.centre[0] for e in found])
    cv_ = np.median([e.centre[1] for e in found])
    fam = []
    for e in found:
        tol = centre_tol_px if centre_tol_px is not None else 2.0 + 0.05 * e.size
        if math.hypot(e.centre[0] - cu, e.centre[1] - cv_) <= tol:
            fam.append(e)
    if len(fam) < 2:
        raise VisionError(f"detect_rings: fewer than 2 concentric rings found ({len(found)} "
                          f"ring-like curves, {len(fam)} sharing a centre)")
    fam.sort(key=lambda e: e.size)
    # nested rings: drop duplicates (same ring detected twice)
    out = [fam[0]]
    for e in fam[1:]:
        if e.size - out[-1].size > 1.0:
            out.append(e)
    return out


# ---------------------------------------------------------------- calibration
@dataclass(frozen=True)
class Calibration:
    """Screen (m) <-> image (px) mapping.

    homography : 3x3, [u w, v w, w] = H [X, Y, 1] (screen m -> image px)
    scale : m/px at the screen origin along the un-foreshortened direction (the
        camera's pixel pitch; the foreshortened direction has scale / cos(tilt))
    centre_px : (u, v) image of the screen origin (ring centre)
    tilt : rad, perspective tilt amount, arccos(minor/major principal scale) at the centre
    tilt_direction : rad, screen angle (from +X, anticlockwise) towards which the
        screen recedes (the scale in px/m shrinks); NaN without perspective
    ring_radii_m : the ring radii used (zones 0, 1, ...), or None
    rms_px : rms residual of the fit [px] (screen residual / scale)
    scale_std : standard uncertainty of ``scale`` [m/px] (:func:`fit_homography`: the
        larger of the pixel-noise covariance and the ring-clustered one, which counts
        a ring drawn too large or too small once, not once per pixel; 0 when not
        estimated).  A systematic error, common to every point mapped.
    lens : the declared lens distortion (:class:`vision.camera_artefacts.Lens`) or None;
        the homography maps to undistorted pixels, :func:`px_to_m` and :func:`m_to_px`
        undo and apply it.
    """
    homography: np.ndarray
    scale: float
    centre_px: tuple
    tilt: float = 0.0
    tilt_direction: float = float("nan")
    ring_radii_m: Optional[np.ndarray] = None
    rms_px: float = 0.0
    scale_std: float = 0.0
    lens: Optional[object] = None

    @property
    def homography_inverse(self) -> np.ndarray:
        return np.linalg.inv(self.homography)


def apply_homography(H, a, b):
    """Map points through a 3x3 homography: ``[x w, y w, w] = H [a, b, 1]``.

    Parameters
    ----------
    H : (3, 3) array
    a, b : array_like
        Coordinates of the points (any common shape; px or m).

    Returns
    -------
    x, y : ndarray or float
        Mapped coordinates, the shape of ``a`` and ``b`` (scalars for scalars).
    """
    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    p = np.asarray(H, dtype=float) @ np.stack([a.ravel(), b.ravel(), np.ones(a.size)])
    return (p[0] / p[2]).reshape(a.shape)[()], (p[1] / p[2]).reshape(a.shape)[()]


def px_to_m(u, v, cal: Calibration):
    """Image (u, v) px -> screen (X, Y) m, origin at the ring centre (the lens's
    distortion undone first)."""
    if cal.lens is not None:
        u, v = undistort_points(u, v, cal.lens)
    return apply_homography(cal.homography_inverse, u, v)


def m_to_px(X, Y, cal: Calibration):
    """Screen (X, Y) m -> image (u, v) px."""
    u, v = apply_homography(cal.homography, X, Y)
    return (u, v) if cal.lens is None else distort_points(u, v, cal.lens)


def _jacobian(H, X=0.0, Y=0.0, h=1e-6):
    """d(u, v)/d(X, Y) at a screen point (analytic for a homography)."""
    p = H @ np.array([X, Y, 1.0])
    w = p[2]
    J = np.empty((2, 2))
    for j in range(2):
        J[0, j] = (H[0, j] - p[0] / w * H[2, j]) / w
        J[1, j] = (H[1, j] - p[1] / w * H[2, j]) / w
    return J


def _finish(H, radii=None, rms_m=0.0) -> Calibration:
    """Normalise H (H22 = 1), fix the rotation gauge, derive scale and tilt."""
    H = H / H[2, 2]
    J = _jacobian(H)
    # rotate the screen about the origin so that +X maps along +u at the centre
    th = math.atan2(J[1, 0], J[0, 0])   # direction of the image of +X
    c, s = math.cos(th), math.sin(th)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])   # screen rotation by +th
    H = H @ R
    J = _jacobian(H)
    if J[1, 1] > 0:    # +Y must map upwards (-v): undo a mirror
        H = H @ np.diag([1.0, -1.0, 1.0])
        J = _jacobian(H)
    sv = np.linalg.svd(J, compute_uv=False)    # px per m
    scale = 1.0 / sv[0]
    tilt = math.acos(min(1.0, sv[1] / sv[0]))
    g = H[2, :2]
    tdir = math.atan2(g[1], g[0]) if np.hypot(*g) > 0 else float("nan")
    centre = (float(H[0, 2]), float(H[1, 2]))
    return Calibration(homography=H, scale=scale, centre_px=centre, tilt=tilt,
                       tilt_direction=tdir,
                       ring_radii_m=None if radii is None else np.asarray(radii, float),
                       rms_px=float(rms_m / scale))


def fit_homography(ellipses: Sequence[Ellipse], ring_radii_m, *, perspective: bool = True,
                   lens=None, estimate_lens: bool = False) -> Calibration:
    """Fit the homography screen (m) -> image (px) to detected concentric rings.

    The detected rings (sorted by size) are matched to the positive entries of
    ``ring_radii_m`` (sorted, zone 0 with radius 0 draws nothing): equal
    counts, or -- when fewer rings were found -- the innermost ones (so rings
    cut by the image border may be missing at the outside).  Unknowns: the
    inverse homography G (image -> screen, 8 parameters; 6 with
    ``perspective=False``); residuals: for every ring pixel, ink-weighted,
    |G(u, v)| - r_i (the ring centre is the screen origin).  With a declared ``lens``
    (:class:`vision.camera_artefacts.Lens`) the ring pixels are undistorted first
    (``cv2.undistortPoints``) and the calibration keeps it.  ``estimate_lens``: its k1, k2
    are fitted too (from where ``lens`` starts them, its focal length and principal point
    kept: the image centre and any normalising length, e.g. the image width), and the
    scale's std carries their uncertainty.

    Raises
    ------
    VisionError
        Fewer than 2 rings, more rings than radii, non-increasing radii, or a
        fit that fails.
    """
    ell = sorted(list(ellipses), key=lambda e: e.size)
    r = np.asarray(ring_radii_m, dtype=float).ravel()
    if r.size == 0 or not np.all(np.isfinite(r)) or np.any(np.diff(r) <= 0) or r[0] < 0:
        raise VisionError("ring_radii_m: must be a non-empty increasing array of radii >= 0 (m)")
    r = r[r > 0]
    if len(ell) < 2:
        raise VisionError(f"fit_homography: need at least 2 rings, got {len(ell)}")
    if len(ell) > r.size:
        raise VisionError(f"fit_homography: {len(ell)} rings detected but only {r.size} "
                          f"positive ring radii given")
    # which radii: the contiguous run whose radii are best proportional to the sizes
    sizes = np.array([e.size for e in ell])
    best = None
    for k in range(r.size - len(ell) + 1):
        rk = r[k:k + len(ell)]
        p = float(np.sum(rk * sizes) / np.sum(sizes * sizes))
        err = float(np.sqrt(np.mean((sizes * p / rk - 1.0) ** 2)))
        if best is None or err < best[0]:
            best = (err, k)
    if best[0] > 0.1:
        raise VisionError(f"fit_homography: the ring sizes are not proportional to the given "
                          f"radii (best match {100 * best[0]:.0f} % off); wrong radii or junk rings")
    r = r[best[1]:best[1] + len(ell)]
    U = np.concatenate([e.points[:, 0] for e in ell])
    V = np.concatenate([e.points[:, 1] for e in ell])
    U_d, V_d = U, V
    if lens is not None:
        U, V = undistort_points(U, V, lens)
    if estimate_lens and lens is None:
        raise VisionError("fit_homography: estimate_lens needs a lens to start from (its "
                          "focal length and principal point)")
    Wt = np.sqrt(np.concatenate([e.weights for e in ell]))
    Rr = np.concatenate([np.full(e.points.shape[0], ri) for e, ri in zip(ell, r)])
    # initial guess: similarity from the ellipses' centres and sizes
    p0 = float(np.sum(r * sizes) / np.sum(sizes * sizes))          # m per px
    u0 = float(np.average([e.centre[0] for e in ell], weights=sizes))
    v0 = float(np.average([e.centre[1] for e in ell], weights=sizes))
    # normalised pixel coordinates for conditioning
    L = max(float(np.max(sizes)), 1.0)

    def xy(q):
        if not estimate_lens:
            return (U - u0) / L, (V - v0) / L
        uu, vv = undistort_points(U_d, V_d, dataclasses.replace(lens, k1=q[n_h], k2=q[n_h + 1]))
        return (uu - u0) / L, (vv - v0) / L

    def G_of(q):
        g = np.array([[q[0], q[1], q[2]], [q[3], q[4], q[5]],
                      [q[6], q[7], 1.0] if perspective else [0.0, 0.0, 1.0]])
        return g

    n_h = 8 if perspective else 6

    def resid(q):
        g = G_of(q)
        x, y = xy(q)
        w = g[2, 0] * x + g[2, 1] * y + 1.0
        X = (g[0, 0] * x + g[0, 1] * y + g[0, 2]) / w
        Y = (g[1, 0] * x + g[1, 1] * y + g[1, 2]) / w
        return (np.hypot(X, Y) - Rr / (p0 * L)) * Wt

    q0 = np.array([1.0, 0.0, 0.0, 0.0, -1.0, 0.0] + ([0.0, 0.0] if perspective else [])
                  + ([lens.k1, lens.k2] if estimate_lens else []))
    sol = least_squares(resid, q0, method="lm", xtol=1e-12, ftol=1e-12)
    if not sol.success or not np.all(np.isfinite(sol.x)):
        raise VisionError(f"fit_homography: the fit failed ({sol.message})")
    G = G_of(sol.x)
    # undo the normalisation: screen = p0 L * G(norm(px)),  norm = T px
    T = np.array([[1 / L, 0, -u0 / L], [0, 1 / L, -v0 / L], [0, 0, 1.0]])
    S = np.diag([p0 * L, p0 * L, 1.0])
    Ginv_full = S @ G @ T                       # image -> screen
    H = np.linalg.inv(Ginv_full)
    rms_m = float(np.sqrt(np.mean((sol.fun / np.maximum(Wt, 1e-12)) ** 2
                                  * (Wt > 0)))) * p0 * L
    cal = _finish(H, radii=np.asarray(ring_radii_m, float), rms_m=rms_m)

    def scale_of(q):
        return _finish(np.linalg.inv(S @ G_of(q) @ T)).scale

    ring_of = np.concatenate([np.full(e.points.shape[0], k) for k, e in enumerate(ell)])
    std = _scale_std(scale_of, sol.x, sol.jac, sol.fun, ring_of)
    if estimate_lens:
        lens = dataclasses.replace(lens, k1=float(sol.x[n_h]), k2=float(sol.x[n_h + 1]))
    return Calibration(**{**cal.__dict__, "scale_std": std, "lens": lens})


def _scale_std(scale_of, q, J, f, cluster) -> float:
    """Standard uncertainty of ``scale_of(q)`` at the least-squares solution ``q``
    (Jacobian ``J``, residuals ``f``): the larger of the white-noise covariance
    s^2 (J^T J)^-1 and the cluster-robust sandwich over the ``cluster`` labels (the
    rings: a ring's residuals share its printing and detection error), propagated by a
    central difference of ``scale_of``."""
    J = np.asarray(J, float)
    n, p = J.shape
    try:
        A = np.linalg.inv(J.T @ J)
    except np.linalg.LinAlgError:
        return float("nan")
    h = 1e-6 * np.maximum(np.abs(q), 1e-3)
    g = np.array([(scale_of(q + hk * e) - scale_of(q - hk * e)) / (2 * hk)
                  for hk, e in zip(h, np.eye(p))])
    white = float(f @ f) / max(n - p, 1) * float(g @ A @ g)
    B = np.zeros((p, p))
    for c in np.unique(cluster):
        s = J[cluster == c].T @ f[cluster == c]
        B += np.outer(s, s)
    k = np.unique(cluster).size
    robust = k / max(k - 1, 1) * float(g @ A @ B @ A @ g)
    return math.sqrt(max(white, robust, 0.0))


def scale_from_fiducials(points_px, points_m, *, mirror: bool = True) -> Calibration:
    """A plain similarity calibration from >= 2 points of known screen position.

    Least squares (Umeyama) for screen = s R (u, +/-v) + t: one scale, one
    rotation, a shift.  ``mirror=True`` (default): the image row axis points
    down while the screen Y axis points up (the usual view of the screen).

    Parameters
    ----------
    points_px : (N, 2) image points (u, v)
    points_m : (N, 2) the same points on the screen (X, Y) [m]

    Raises
    ------
    VisionError
        Fewer than 2 points, coincident points, shapes that disagree.
    """
    P = np.asarray(points_px, dtype=float)
    Q = np.asarray(points_m, dtype=float)
    if P.ndim != 2 or P.shape[1] != 2 or Q.shape != P.shape or P.shape[0] < 2:
        raise VisionError(f"scale_from_fiducials: need matching (N, 2) arrays with N >= 2, got "
                          f"{P.shape} and {Q.shape}")
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(Q))):
        raise VisionError("scale_from_fiducials: non-finite coordinates")
    A = P * np.array([1.0, -1.0 if mirror else 1.0])
    ma, mq = A.mean(0), Q.mean(0)
    a, q = A - ma, Q - mq
    va = float(np.sum(a * a))
    vq = float(np.sum(q * q))
    if not (va > 0 and vq > 0):
        raise VisionError("scale_from_fiducials: the points coincide (no length to measure)")
    C = q.T @ a
    Uc, Sc, Vt = np.linalg.svd(C)
    D = np.diag([1.0, np.sign(np.linalg.det(Uc @ Vt)) or 1.0])
    R = Uc @ D @ Vt
    s = float(np.trace(np.diag(Sc) @ D) / va)          # m per px
    t = mq - s * R @ ma
    M = np.eye(3)
    M[:2, :2] = s * R @ np.diag([1.0, -1.0 if mirror else 1.0])
    M[:2, 2] = t
    H = np.linalg.inv(M)
    H = H / H[2, 2]
    res = Q - (np.c_[P, np.ones(len(P))] @ M.T)[:, :2]
    u0, v0 = apply_homography(H, 0.0, 0.0)
    return Calibration(homography=H, scale=s, centre_px=(float(u0), float(v0)), tilt=0.0,
                       rms_px=float(np.sqrt(np.mean(np.sum(res * res, 1)))) / s)


# ---------------------------------------------------------------- zones
class ZoneReading(NamedTuple):
    zone: np.ndarray        #: i with radii[i] <= r < radii[i + 1] (last zone beyond the last ring)
    unbalance: np.ndarray   #: fraction of S, linear in the radius between rings (i / 16 at ring i)


def zone_map(radius_m, ring_radii_m, *, parts: int = PARTS, zones=None) -> ZoneReading:
    """Screen radius [m] -> calibration zone and unbalance (fraction of S).

    ``ring_radii_m[k]`` is the ring of zone ``zones[k]`` (default k = 0, 1, ...;
    unbalance zones[k] S / parts).  ``zone``: the i with radii[i] <= r <
    radii[i+1] (monograph section 4.3.2; the last zone beyond the last ring);
    ``unbalance``: linear interpolation between the rings (the whirl radius is
    proportional to the unbalance), extrapolated beyond the last ring.
    """
    radii = np.asarray(ring_radii_m, dtype=float).ravel()
    if radii.size < 2 or not np.all(np.isfinite(radii)) or np.any(np.diff(radii) <= 0):
        raise VisionError("ring_radii_m: need >= 2 increasing finite radii (m)")
    z = np.arange(radii.size, dtype=float) if zones is None else np.asarray(zones, float).ravel()
    if z.size != radii.size:
        raise VisionError("zones: must have one entry per ring radius")
    r = np.asarray(radius_m, dtype=float)
    idx = np.clip(np.searchsorted(radii, r, side="right") - 1, 0, radii.size - 1)
    frac = np.interp(r, radii, z) / parts
    slope = (z[-1] - z[-2]) / (radii[-1] - radii[-2])
    frac = np.where(r > radii[-1], (z[-1] + (r - radii[-1]) * slope) / parts, frac)
    return ZoneReading(zone=z[idx].astype(int), unbalance=frac)
