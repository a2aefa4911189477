"""Frames of the light-slot stroboscope, as the camera above the rotor films them.

Monograph section 4.3.1, digest ch5 section 6.1; the flashes and the settings
are those of :mod:`stand.instruments.strobe_readings`.

Conventions of the images
-------------------------
The camera looks down the shaft axis and is fixed to the machine body, so the
image is in the fixed frame: pixel column = ``(width - 1)/2 + X / pixel_pitch``,
row = ``(height - 1)/2 - Y / pixel_pitch`` (X right, Y up, angles counter-
clockwise from X).  At a flash the rotor's reference mark points at the flash
angle and each weight at its absolute angle (the reference mark plus its
relative angle), i.e. the rotor frame as the eye sees it through the slot.
With ``shaft_motion`` the rotor is drawn around the displaced shaft centre
(x, y) (the whirl is seen); otherwise around the image centre.

What is drawn (intensities as fractions of full scale, see the ``LEVEL_*``
constants): outside the rotor the housing at ``background``; inside the rotor
outline (radius ``slot_radius``) the lit interior; the rim; the reference mark
(a radial bar at 0.80..0.97 of the rim radius); the weights -- balls as discs,
pendulums as a rod from the shaft axis (the pivot) plus a bob.  Body weights
(:class:`stand.instruments.strobe_readings.BodyLook`): a tilting weight
(two-axis pendulum, coupled pair) or the damper's weight as a faint housing
circle (``HOUSING_FACTOR * arm`` around the pivot), a rod from the pivot and a
bob (a steel ball of its mass unless ``ball_radius`` is set) at its centre of
mass -- at the apparent radial offset ``arm |sin(tilt)|`` (damper ``arm
|(n_x, n_y)|``) in the direction the body's coordinates give; a liquid as the
crescent between its chamber wall (radius R, centred on the shaft point) and
its free-surface circle (radius r, centred ``-liquid / kappa`` from the
chamber centre), a float drawn inside the free surface for ``liquid_float``.
Liquids are drawn under the reference mark, bodies over it, balls last.
Every flash is
the average of sub-images across the slot's angular width (the rotor turns by
``slot_width / slot_radius`` rad while the slots overlap; the light is taken as
uniform over that span); a frame is the mean of its flashes (a weight seen in
one of K flashes shows at 1/K contrast, as a persistence-of-vision ghost).
Then shot noise (Poisson, ``full_well`` electrons at full scale), read noise
(Gaussian, ``read_noise`` of full scale), clipping and quantisation to
``bit_depth`` bits (uint8 up to 8 bits, else uint16).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterator, Optional

import numpy as np

from stand.errors import SceneError
from stand.instruments.strobe_readings import (PATH, TWO_PI, Stroboscope, body_coordinates, body_looks,
                              default_ball_radius, flash_times, point_weights)
from stand.instruments.timing import sample_trajectory, shaft_velocity, time_window, wrap

__all__ = ["StrobeFrame", "render_strobe_frames", "drawn_weights", "LEVEL_INTERIOR", "LEVEL_RIM",
           "LEVEL_MARK", "LEVEL_ROD", "LEVEL_BALL", "LEVEL_LIQUID", "LEVEL_FLOAT",
           "LEVEL_HOUSING", "MARK_SPAN"]

# intensities, fractions of full scale
LEVEL_INTERIOR = 0.20
LEVEL_RIM = 0.45
LEVEL_MARK = 0.50
LEVEL_ROD = 0.70
LEVEL_BALL = 0.95
LEVEL_LIQUID = 0.32        #: liquid in a chamber (darker than the mark: the mark stays seen)
LEVEL_FLOAT = 0.26         #: the float of a liquid_float balancer
LEVEL_HOUSING = 0.30       #: housing circle of a tilting weight / damper, chamber wall
MARK_SPAN = (0.80, 0.97)   #: reference mark, fractions of the rim radius
MAX_SUBPOSITIONS = 64
MAX_PIXELS = 4096 * 4096


@dataclass
class StrobeFrame:
    """One stroboscope frame and its ground truth.

    Attributes
    ----------
    index : int                 frame number (0, 1, ...) in the rendered sequence
    image : (height, width)     uint8 (bit_depth <= 8) or uint16
    t : (K,)                    flash times in the exposure [s]; ``time`` = t[0]
    rotor_angle : (K,)          rotor angle at the flashes [rad]
    weight_angle : (K, n)       absolute weight angles [rad]
    relative_angle : (K, n)     weight angles from the reference mark, wrapped [rad]
    centre_px : (K, 2)          drawn rotor centre (column, row) [px]
    weight_px : (K, n, 2)       drawn weight centres (column, row) at the flash centre [px]
    bodies : dict               body weight name -> its coordinates at the flashes
                                (:func:`stand.instruments.strobe_readings.body_coordinates`,
                                (K,) arrays) plus ``px`` (K, 2): the drawn bob centre, or for a
                                liquid the free-surface centre (column, row) [px]

    ``weight_angle``, ``relative_angle`` and ``weight_px`` cover the balls and
    pendulums (n of them); body weights are in ``bodies``.
    """

    index: int
    image: np.ndarray
    t: np.ndarray
    rotor_angle: np.ndarray
    weight_angle: np.ndarray
    relative_angle: np.ndarray
    centre_px: np.ndarray
    weight_px: np.ndarray
    bodies: dict = field(default_factory=dict)

    @property
    def time(self) -> float:
        """Timestamp of the frame: its first flash [s]."""
        return float(self.t[0])


def _cov_disk(X, Y, cx, cy, r):
    d = np.hypot(X - cx, Y - cy)
    return np.clip(r - d + 0.5, 0.0, 1.0)


def _cov_ring(X, Y, cx, cy, r, half):
    d = np.abs(np.hypot(X - cx, Y - cy) - r)
    return np.clip(half - d + 0.5, 0.0, 1.0)


def _cov_segment(X, Y, x0, y0, x1, y1, half):
    dx, dy = x1 - x0, y1 - y0
    L2 = dx * dx + dy * dy
    u = np.clip(((X - x0) * dx + (Y - y0) * dy) / L2, 0.0, 1.0) if L2 > 0 else 0.0
    d = np.hypot(X - (x0 + u * dx), Y - (y0 + u * dy))
    return np.clip(half - d + 0.5, 0.0, 1.0)


class _Canvas:
    """Pixel grids and bounding-box helpers for one image size."""

    def __init__(self, width: int, height: int):
        self.W, self.H = width, height
        self.cols = np.arange(width, dtype=float)
        self.rows = np.arange(height, dtype=float)

    def box(self, xs, ys, margin):
        c0 = max(0, int(math.floor(np.min(xs) - margin)))
        c1 = min(self.W, int(math.ceil(np.max(xs) + margin)) + 1)
        r0 = max(0, int(math.floor(np.min(ys) - margin)))
        r1 = min(self.H, int(math.ceil(np.max(ys) + margin)) + 1)
        if c1 <= c0 or r1 <= r0:
            return None
        X, Y = np.meshgrid(self.cols[c0:c1], self.rows[r0:r1])
        return (slice(r0, r1), slice(c0, c1)), X, Y


def _weight_geometry(scene, strobe: Stroboscope, n: int):
    """Per-weight drawn radius of the centres [m], ball radius [m], kind (balls and
    pendulums; ``n`` of them)."""
    b = scene.balancer if scene is not None else None
    kind = b.type if (b is not None and b.count == n) else "balls"
    if n == 0:
        return np.zeros(0), np.zeros(0), kind
    if strobe.track_radius is not None:
        track = np.full(n, strobe.track_radius)
    elif b is not None and b.count == n:
        track = np.asarray(b.radius, float)
    else:
        raise SceneError(f"{PATH}.track_radius: missing; the trajectory carries no balancer "
                         f"geometry for its {n} weights (m)")
    if strobe.ball_radius is not None:
        ball = np.full(n, strobe.ball_radius)
    elif b is not None and b.count == n:
        ball = default_ball_radius(b.mass)
    else:
        raise SceneError(f"{PATH}.ball_radius: missing; the trajectory carries no weight "
                         f"masses to size the balls (m)")
    return track, ball, kind


def render_strobe_frames(traj, strobe: Stroboscope, t_start: Optional[float] = None,
                         t_end: Optional[float] = None,
                         max_frames: Optional[int] = None) -> Iterator[StrobeFrame]:
    """Stroboscope frames of a run, streamed one at a time.

    Frame ``i`` integrates flashes ``i*stride .. i*stride + exposure_flashes - 1``
    of the window (``stride`` = ``frame_every`` or ``exposure_flashes``); an
    incomplete last group is dropped.  The settings are checked before the
    first frame is produced (this function validates eagerly and returns a
    generator).

    Parameters
    ----------
    traj : Trajectory
        Needs ``t, x, y, rotor_angle, rotor_speed, weight_angle, weight_speed``,
        the shaft velocity (:func:`stand.instruments.timing.shaft_velocity`) when
        ``shaft_motion``, and ``scene.balancer`` for the weights' kind and size
        unless ``track_radius`` and ``ball_radius`` are set.  Body weights
        (``scene.bodies``) are drawn from their coordinates in ``traj.weights``
        (a :class:`stand.integrate.result.Run`); ``weight_angle`` then means the balls and
        pendulums only.
    strobe : Stroboscope
    t_start, t_end : float, optional
        Window [s].
    max_frames : int, optional
        Stop after this many frames.

    Yields
    ------
    StrobeFrame

    Raises
    ------
    SceneError
        ``exposure_flashes > 1`` while the rotor does not turn the
        ``exposure_flashes - 1`` revolutions a frame needs in the window
        ("exposure over flashes with no rotation"); weights drawn outside the
        image; image too large.
    """
    t0, t1 = time_window(traj, t_start, t_end, "stroboscope")
    K, stride = strobe.exposure_flashes, strobe.stride
    tf = flash_times(traj, strobe, t0, t1)
    if K > 1 and tf.size < K:
        sel = (traj.t >= t0) & (traj.t <= t1)
        turns = float(np.ptp(traj.rotor_angle[sel])) / TWO_PI if np.any(sel) else 0.0
        top = float(np.max(np.abs(traj.rotor_speed[sel]))) / TWO_PI if np.any(sel) else 0.0
        raise SceneError(f"{PATH}.exposure_flashes = {K}: exposure over flashes with no "
                         f"rotation: the rotor turns {turns:.3g} rev in [{t0:.6g}, {t1:.6g}] s "
                         f"(speed at most {top:.3g} rev/s) and gives {tf.size} flash(es); a frame "
                         f"needs {K} flashes ({K - 1} revolutions); use exposure_flashes = 1 or "
                         f"a window in which the rotor runs")
    if strobe.width * strobe.height > MAX_PIXELS:
        raise SceneError(f"{PATH}.width * height = {strobe.width * strobe.height}: more than "
                         f"{MAX_PIXELS} px")
    view = point_weights(traj)
    n = int(np.shape(view.weight_angle)[1]) if np.ndim(view.weight_angle) == 2 else 0
    scene = getattr(traj, "scene", None)
    track, ball, kind = _weight_geometry(scene, strobe, n)
    looks = body_looks(scene, strobe)
    body_coordinates(traj, looks, traj.t[:1])   # every body's coordinates are in the run
    half_w = 0.5 * strobe.width * strobe.pixel_pitch
    half_h = 0.5 * strobe.height * strobe.pixel_pitch
    if n and float(np.max(track + ball)) > min(half_w, half_h):
        raise SceneError(f"{PATH}.pixel_pitch = {strobe.pixel_pitch!r}: the weights (track "
                         f"radius + ball radius = {float(np.max(track + ball)):.4g} m) do not fit "
                         f"in the {strobe.width} x {strobe.height} px image "
                         f"({2 * half_w:.4g} x {2 * half_h:.4g} m); lower pixel_pitch or "
                         f"enlarge width/height (m/px)")
    for lk in looks:
        if lk.reach > min(half_w, half_h):
            raise SceneError(f"{PATH}.pixel_pitch = {strobe.pixel_pitch!r}: the body weight "
                             f"{lk.name} (drawn out to {lk.reach:.4g} m from the shaft) does not "
                             f"fit in the {strobe.width} x {strobe.height} px image "
                             f"({2 * half_w:.4g} x {2 * half_h:.4g} m); lower pixel_pitch or "
                             f"enlarge width/height (m/px)")
    n_frames = 0 if tf.size < K else (tf.size - K) // stride + 1
    if max_frames is not None:
        n_frames = min(n_frames, int(max_frames))
    velocities = shaft_velocity(traj) if strobe.shaft_motion else None
    return _frames(traj, view, strobe, tf, n_frames, track, ball, kind, looks, velocities)


def drawn_weights(scene, strobe: Stroboscope) -> list:
    """What the frames show of each weight, as plain dicts (stored with the frames, JSON).

    Balls and pendulums: ``name``, ``type``, ``drawn`` (``"ball"`` / ``"pendulum"``),
    ``track_radius_m`` / ``_px``, ``ball_radius_m`` / ``_px``; body weights:
    :meth:`stand.instruments.strobe_readings.BodyLook.to_dict` (``drawn`` ``"pendulum"``:
    ``arm``, ``bob_radius``, ``housing_radius``; ``"crescent"``: ``chamber_radius``,
    ``surface_radius``, ``kappa``), lengths in m and px.  Empty when the geometry of the
    balls is unknown (no balancer and no ``track_radius``/``ball_radius`` settings).
    """
    from stand.integrate.result import weight_names

    out = []
    pitch = strobe.pixel_pitch
    if scene is not None:
        names = weight_names(scene.weights)[0]
        try:
            track, ball, kind = _weight_geometry(scene, strobe, len(names))
        except SceneError:
            track = ball = np.zeros(0)
            kind = "balls"
        for nm, tr, bl in zip(names, track, ball):
            out.append({"name": nm, "type": kind, "drawn": "pendulum" if kind == "pendulums"
                        else "ball", "track_radius_m": float(tr), "track_radius_px": float(tr) / pitch,
                        "ball_radius_m": float(bl), "ball_radius_px": float(bl) / pitch})
    out.extend(lk.to_dict(pitch) for lk in body_looks(scene, strobe))
    return out


def _draw(img, sl, cov, level):
    """Blend ``level`` into ``img[sl]`` with the coverage ``cov`` in [0, 1]."""
    img[sl] += (level - img[sl]) * cov


def _draw_rod(img, canvas, cx, cy, px, py, n_sub):
    """A pendulum's rod from the pivot (cx, cy) to the bob at each sub-instant (px, py) [px]."""
    bx = canvas.box(np.append(px, cx), np.append(py, cy), 3.0)
    if bx is not None:
        sl, X, Y = bx
        cov = np.zeros_like(X)
        for a, b_ in zip(px, py):
            cov += _cov_segment(X, Y, cx, cy, a, b_, 1.0)
        _draw(img, sl, cov / n_sub, LEVEL_ROD)


def _draw_bob(img, canvas, px, py, radius, n_sub):
    """A ball or a pendulum's bob of ``radius`` [px] at each sub-instant (px, py) [px]."""
    bx = canvas.box(px, py, radius + 2.0)
    if bx is not None:
        sl, X, Y = bx
        cov = np.zeros_like(X)
        for a, b_ in zip(px, py):
            cov += _cov_disk(X, Y, a, b_, radius)
        _draw(img, sl, cov / n_sub, LEVEL_BALL)


def _draw_liquid(img, canvas, cx, cy, lk, sx, sy, pitch):
    """The chamber wall, the liquid's crescent and (liquid_float) the float, one flash."""
    R = lk.chamber_radius / pitch
    r = lk.surface_radius / pitch
    fx, fy = cx + sx / pitch, cy - sy / pitch        # free-surface centre [px]
    bx = canvas.box(np.array([cx - R, cx + R]), np.array([cy - R, cy + R]), 2.0)
    if bx is None:
        return
    sl, X, Y = bx
    surface = _cov_disk(X, Y, fx, fy, r)
    _draw(img, sl, _cov_disk(X, Y, cx, cy, R) * (1.0 - surface), LEVEL_LIQUID)
    if lk.type == "liquid_float":
        _draw(img, sl, surface, LEVEL_FLOAT)
    _draw(img, sl, _cov_ring(X, Y, cx, cy, R, 1.0), LEVEL_HOUSING)


def _draw_pendulum_body(img, canvas, cx, cy, lk, ox, oy, pitch, n_sub):
    """Housing circle, rod and bob of a tilting weight / the damper over the sub-instants
    of one flash (``ox``, ``oy``: the centre of mass from the pivot [m], per sub-instant)."""
    H = lk.housing_radius / pitch
    bx = canvas.box(np.array([cx - H, cx + H]), np.array([cy - H, cy + H]), 2.0)
    if bx is not None:
        sl, X, Y = bx
        _draw(img, sl, 0.6 * _cov_ring(X, Y, cx, cy, H, 0.5), LEVEL_HOUSING)
    px = cx + np.asarray(ox) / pitch
    py = cy - np.asarray(oy) / pitch
    _draw_rod(img, canvas, cx, cy, px, py, n_sub)
    _draw_bob(img, canvas, px, py, lk.bob_radius / pitch, n_sub)


def _frames(traj, view, strobe, tf, n_frames, track, ball, kind, looks, velocities):
    K, stride = strobe.exposure_flashes, strobe.stride
    pitch = strobe.pixel_pitch
    W, H = strobe.width, strobe.height
    cx0, cy0 = 0.5 * (W - 1), 0.5 * (H - 1)
    canvas = _Canvas(W, H)
    Xg, Yg = np.meshgrid(canvas.cols, canvas.rows)
    rng = np.random.default_rng(strobe.seed)
    n = track.size
    R_rot = strobe.slot_radius / pitch
    reach = max([R_rot, float(np.max(track)) / pitch if n else 0.0]
                + [lk.reach / pitch for lk in looks])
    n_sub = int(np.clip(math.ceil(strobe.blur * reach / 0.25), 1, MAX_SUBPOSITIONS))
    offsets = (np.arange(n_sub) + 0.5) / n_sub - 0.5 if n_sub > 1 else np.zeros(1)
    offsets = offsets * strobe.blur            # rotor angle offsets across the slot [rad]
    track_px, ball_px = track / pitch, ball / pitch
    full = (1 << strobe.bit_depth) - 1
    zeros_v = (np.zeros_like(traj.t), np.zeros_like(traj.t))
    base_at, base = None, None
    for i in range(n_frames):
        tk = tf[i * stride:i * stride + K]
        # the flash centre and the sub-instants across the slot
        s0 = sample_trajectory(view, tk, velocities if velocities is not None else zeros_v)
        w = np.where(np.abs(s0.rotor_speed) > 0, s0.rotor_speed, np.inf)
        tsub = (tk[:, None] + offsets[None, :] / w[:, None]).ravel()
        tsub = np.clip(tsub, traj.t[0], traj.t[-1])
        ss = sample_trajectory(view, tsub, velocities if velocities is not None else zeros_v)
        phi_sub = ss.rotor_angle.reshape(K, n_sub)
        wa_sub = ss.weight_angle.reshape(K, n_sub, n)
        b0 = body_coordinates(traj, looks, tk, s0.rotor_angle)
        bsub = body_coordinates(traj, looks, tsub)
        if strobe.shaft_motion:
            cxs = cx0 + s0.x / pitch
            cys = cy0 - s0.y / pitch
        else:
            cxs = np.full(K, cx0)
            cys = np.full(K, cy0)
        acc = np.zeros((H, W))
        for k in range(K):
            cx, cy = cxs[k], cys[k]
            if base_at != (cx, cy):        # the rotor's disc and rim: drawn once per centre
                base = np.full((H, W), strobe.background)
                base += (LEVEL_INTERIOR - base) * _cov_disk(Xg, Yg, cx, cy, R_rot)
                base += (LEVEL_RIM - base) * _cov_ring(Xg, Yg, cx, cy, R_rot, 1.0)
                base_at = (cx, cy)
            img = base.copy()
            for lk in looks:               # liquids under the mark
                if lk.drawn == "crescent":
                    d = b0[lk.name]
                    _draw_liquid(img, canvas, cx, cy, lk, d["surface_x"][k], d["surface_y"][k],
                                 pitch)
            # reference mark: radial bar at the rotor angle of each sub-instant
            ang = phi_sub[k]
            r_a, r_b = MARK_SPAN[0] * R_rot, MARK_SPAN[1] * R_rot
            xs = np.concatenate([cx + r_a * np.cos(ang), cx + r_b * np.cos(ang)])
            ys = np.concatenate([cy - r_a * np.sin(ang), cy - r_b * np.sin(ang)])
            bx = canvas.box(xs, ys, 3.0)
            if bx is not None:
                sl, X, Y = bx
                cov = np.zeros_like(X)
                for a in ang:
                    cov += _cov_segment(X, Y, cx + r_a * math.cos(a), cy - r_a * math.sin(a),
                                        cx + r_b * math.cos(a), cy - r_b * math.sin(a), 1.5)
                cov /= n_sub
                img[sl] += (LEVEL_MARK - img[sl]) * cov
            for lk in looks:               # tilting weights and the damper over it
                if lk.drawn == "pendulum":
                    d = bsub[lk.name]
                    _draw_pendulum_body(img, canvas, cx, cy, lk,
                                        d["offset_x"].reshape(K, n_sub)[k],
                                        d["offset_y"].reshape(K, n_sub)[k], pitch, n_sub)
            for j in range(n):
                th = wa_sub[k, :, j]
                px = cx + track_px[j] * np.cos(th)
                py = cy - track_px[j] * np.sin(th)
                if kind == "pendulums":
                    _draw_rod(img, canvas, cx, cy, px, py, n_sub)
                _draw_bob(img, canvas, px, py, ball_px[j], n_sub)
            acc += img
        acc /= K
        if strobe.full_well > 0:
            acc = rng.poisson(np.clip(acc, 0, None) * strobe.full_well) / strobe.full_well
        if strobe.read_noise > 0:
            acc = acc + rng.normal(0.0, strobe.read_noise, acc.shape)
        image = np.rint(np.clip(acc, 0.0, 1.0) * full).astype(strobe.dtype)
        rel = wrap(s0.weight_angle - s0.rotor_angle[:, None])
        wpx = np.stack([cxs[:, None] + track_px[None, :] * np.cos(s0.weight_angle),
                        cys[:, None] - track_px[None, :] * np.sin(s0.weight_angle)], axis=-1)
        for lk in looks:
            d = b0[lk.name]
            ox, oy = (d["surface_x"], d["surface_y"]) if lk.drawn == "crescent" else \
                (d["offset_x"], d["offset_y"])
            d["px"] = np.column_stack([cxs + ox / pitch, cys - oy / pitch])
        yield StrobeFrame(index=i, image=image, t=tk, rotor_angle=s0.rotor_angle,
                          weight_angle=s0.weight_angle, relative_angle=rel,
                          centre_px=np.column_stack([cxs, cys]), weight_px=wpx, bodies=b0)
