"""The laser-spot screen and the camera filming it (monograph section 4.3; digest
ch5 sections 5.3 and 6.1).

A laser screwed into the shaft end, coaxial with the shaft, shines onto a screen;
the spot draws the shaft's motion: a point for a balanced rotor, a circle for a
steady whirl, an epitrochoid with (k - 1) petals for the quasi-periodic "stuck
balls" motion (5.237)-(5.240).  A camera films the screen.

Chain of this module (the pipeline calls them in this order):

1. :func:`frame_times` -- frame start times;  :func:`exposure_times` -- the K
   sub-sample times of each exposure (midpoints of K equal slices); the
   simulator samples the motion there (``simulate(scene, extra_times=...)``).
2. :func:`spot_on_screen` -- shaft motion -> spot on the screen [m]:
   ``gain * (x, y)`` + beam-misalignment circle turning with the rotor + offset
   (+ the intersection of a tilting axis with the screen plane, for the
   tilting models of later issues).
3. :func:`screen_to_pixels` -- screen [m] -> image [px] through the camera's
   homography (pinhole camera, optionally tilted); inverse :func:`pixels_to_screen`.
4. :func:`stand.instruments.render.render_frames` -- frames, one by one.
5. :func:`frame_truth` -- per frame, the exposure-averaged spot centre in px
   (what an intensity centroid estimates) and in m.

Coordinates
-----------
Screen: X, Y [m] in the fixed frame of the shaft displacement (x, y); the
origin is where the camera's optical axis meets the screen, which is the image
centre.  The undeflected beam (x = y = 0, no misalignment) hits
(offset_x, offset_y) -- the image centre by default.
Image: u = column (to the right), v = row (downwards); pixel centres at
integers, (0, 0) the centre of the top-left pixel (OpenCV convention); image
centre ((W - 1)/2, (H - 1)/2).  The screen is seen with +X to the right and +Y
up (v = c_v - Y / pitch for an untilted camera).
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from vision.camera_artefacts import Lens, distort_points, undistort_points
from stand.scene.screen_camera import (  # noqa: F401 (settings read with the scene)
    ScreenCamera, SCREEN_KEYS, frame_times, exposure_times, TILT_LIMIT, DEFAULT_SUBSAMPLES)

__all__ = ["ScreenCamera", "lens_of", "spot_on_screen", "screen_to_pixels",
           "pixels_to_screen", "frame_times", "exposure_times", "spot_positions", "frame_truth",
           "SCREEN_KEYS",
           "TILT_LIMIT", "DEFAULT_SUBSAMPLES"]


# ---------------------------------------------------------------- geometry
def spot_on_screen(x, y, rotor_angle, cam: ScreenCamera, tilt_x=None, tilt_y=None,
                   screen_distance=None):
    """Spot position on the screen [m].

    Plane-parallel models: ``gain * (x, y)`` + the misalignment circle
    ``misalignment * (cos, sin)(rotor_angle + misalignment_phase)`` + offset.
    Tilting models (later issues): if ``tilt_x``, ``tilt_y`` (angles [rad] of
    the axis from the screen normal, in the X-Z and Y-Z planes, positive toward
    +X, +Y) and ``screen_distance`` [m] (from the point (x, y) of the axis to
    the screen plane) are given, the intersection of the axis line with the
    screen, ``screen_distance * tan(tilt)``, is added.

    Parameters
    ----------
    x, y : array_like
        Shaft (axis point) displacement [m].
    rotor_angle : array_like
        Angle of the rotor's reference mark [rad].

    Returns
    -------
    X, Y : ndarray
    """
    x, y, phi = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (x, y, rotor_angle)))
    a = phi + cam.misalignment_phase
    X = cam.gain * x + cam.misalignment * np.cos(a) + cam.offset_x
    Y = cam.gain * y + cam.misalignment * np.sin(a) + cam.offset_y
    given = [v is not None for v in (tilt_x, tilt_y, screen_distance)]
    if any(given):
        if not all(given):
            raise ValueError("tilt_x, tilt_y and screen_distance must be given together")
        X = X + screen_distance * np.tan(np.asarray(tilt_x, dtype=float))
        Y = Y + screen_distance * np.tan(np.asarray(tilt_y, dtype=float))
    return X, Y


def _project(H: np.ndarray, a, b):
    """Apply the 3x3 homography ``H`` to the points (a, b): ``[a' w, b' w, w] = H [a, b, 1]``."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    w = H[2, 0] * a + H[2, 1] * b + H[2, 2]
    return (H[0, 0] * a + H[0, 1] * b + H[0, 2]) / w, (H[1, 0] * a + H[1, 1] * b + H[1, 2]) / w


def lens_of(cam: ScreenCamera):
    """The camera's lens distortion (:class:`vision.camera_artefacts.Lens`: ``lens_k1``,
    ``lens_k2``, focal length camera_distance / pixel_pitch [px], the image centre), None
    for a pinhole."""
    if cam.lens_k1 == 0 and cam.lens_k2 == 0:
        return None
    return Lens(cam.lens_k1, cam.lens_k2, cam.camera_distance / cam.pixel_pitch,
                ((cam.width - 1) / 2.0, (cam.height - 1) / 2.0))


def screen_to_pixels(X, Y, cam: ScreenCamera):
    """Screen [m] -> image [px] (u = column, v = row) through ``cam.homography``, then the
    lens distortion (:func:`lens_of`)."""
    u, v = _project(cam.homography, X, Y)
    lens = lens_of(cam)
    return (u, v) if lens is None else distort_points(u, v, lens)


def pixels_to_screen(u, v, cam: ScreenCamera):
    """Image [px] -> screen [m]; inverse of :func:`screen_to_pixels`."""
    lens = lens_of(cam)
    if lens is not None:
        u, v = undistort_points(u, v, lens)
    return _project(cam.homography_inverse, u, v)


def spot_positions(x, y, rotor_angle, cam: ScreenCamera, **tilting):
    """Spot positions on the screen [m] and in the image [px], last axis (X, Y) / (u, v).

    ``x``, ``y``, ``rotor_angle`` of any common shape (e.g. (F, K) at
    :func:`exposure_times`); ``tilting``: ``tilt_x``, ``tilt_y``,
    ``screen_distance`` of :func:`spot_on_screen`.

    Returns
    -------
    screen_m, px : ndarray (..., 2)
    """
    X, Y = spot_on_screen(x, y, rotor_angle, cam, **tilting)
    u, v = screen_to_pixels(X, Y, cam)
    return np.stack([X, Y], axis=-1), np.stack([u, v], axis=-1)


# ---------------------------------------------------------------- timing


# ---------------------------------------------------------------- truth
def frame_truth(screen_m, px, cam: ScreenCamera, window: Optional[float] = None) -> dict:
    """Ground truth per frame from the sub-sample positions (F, K, 2).

    Returns
    -------
    dict of ndarray
        ``centre_px`` (F, 2): exposure-averaged spot centre in the image [px] --
        exactly what the intensity centroid of a noiseless, unsaturated,
        fully visible frame estimates (each sub-sample carries the same flux);
        ``centre_m`` (F, 2): exposure-averaged spot centre on the screen [m]
        (equal to ``pixels_to_screen(centre_px)`` without tilt; with a tilt they
        differ at second order in the blur length);
        ``in_frame`` (F,) bool: every sub-sample's drawing window (+-4 sigma) lies
        inside the image, so the centroid is not cut by the image border.
    """
    from stand.instruments.render import WINDOW_SIGMAS

    window = WINDOW_SIGMAS if window is None else window
    screen_m = np.asarray(screen_m, dtype=float)
    px = np.asarray(px, dtype=float)
    su, sv = cam.sigma_px
    u, v = px[..., 0], px[..., 1]
    inside = ((u - window * su >= -0.5) & (u + window * su <= cam.width - 0.5)
              & (v - window * sv >= -0.5) & (v + window * sv <= cam.height - 0.5))
    return {"centre_px": px.mean(axis=-2), "centre_m": screen_m.mean(axis=-2),
            "in_frame": np.all(inside, axis=-1)}
