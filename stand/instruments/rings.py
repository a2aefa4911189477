"""Calibration rings of the laser method ("taring", monograph section 4.3.2;
digest ch5 section 6.1 item 5).

The capacity S of the balancer is divided into 16 parts.  For each unbalance
i S / 16 (i = 0..20, up to 1.25 S) a circle is drawn on the screen with the
radius of the spot's steady circle at the test speed; a spot circle between
ring i and ring i + 1 lies in zone i and means an unbalance of about i S / 16
(sensitivity between S/16 and S/32).  The weights are locked to the rotor
during calibration (their mass is included, so M_Sigma and the natural
frequency are the scene's), and the rotor carries only the calibration
unbalance (it was balanced and the beam centred before).  The spot must be
smaller than zone 0 (:func:`check_spot_size`).

* :func:`ring_radii` -- closed form of the steady whirl radius;
* :func:`ring_radii_by_simulation` -- the calibration run itself, on the
  simulator;
* :func:`render_ring_image` -- the calibration image (rings as seen by the camera);
* :func:`zone_of` -- the zone of a spot circle.
"""
from __future__ import annotations

import math
from typing import Iterable, Optional

import numpy as np

from stand.scene.model import (Balancer, InitialState, Rotor, RunSettings, Scene, SceneError,
                     SpeedDrive)

__all__ = ["ring_radii", "family_ring_radii", "ring_radii_by_simulation",
           "calibration_scene", "render_ring_image", "zone_of", "check_spot_size", "ZONES", "PARTS"]

PARTS = 16                 #: the capacity is divided into 16 parts
ZONES = range(0, 21)       #: zones 0..20, up to 1.25 S


def _capacity(scene: Scene) -> float:
    """The main plane's capacity S [kg m] (:meth:`Scene.weights_capacity`); SceneError when 0."""
    S = scene.weights_capacity(scene.main_plane)
    if not S > 0:
        raise SceneError("calibration rings: the scene has no balancer (capacity S = 0); the "
                         "rings are drawn for unbalances i S / 16")
    return S


def _speed(scene: Scene, speed: Optional[float]) -> float:
    """Test speed [rad/s]: given, or the last speed of the scene's speed programme."""
    if speed is None:
        d = scene.drive
        speed = float(d.programme[-1, 1]) if d.kind == "speed" else float(d.target_speed)
    speed = float(speed)
    if not (math.isfinite(speed) and speed > 0):
        raise ValueError(f"speed = {speed!r}: must be > 0 (rad/s)")
    return speed


def _gain(cam) -> float:
    return 1.0 if cam is None else float(cam.gain)


def ring_radii(scene: Scene, speed: Optional[float] = None, zones: Iterable[int] = ZONES,
               cam=None, plane: Optional[str] = None) -> np.ndarray:
    """Radius on the screen [m] of the steady spot circle for unbalance i S / 16.

    Closed form for the weights locked to the rotor (rigid rotor of mass
    M_Sigma), unbalance U = i S / 16, constant speed omega:

        r_i = gain * (U / M_Sigma) * R^2 / sqrt((1 - R^2)^2 + (H R)^2),
        R = omega / omega_1,  H = damping_x / (omega_1 M_Sigma).

    With anisotropic supports the steady orbit is an ellipse; the radius
    returned is its semi-major axis |A| + |B| (z = A e^{i omega t} +
    B e^{-i omega t}), which reduces to the formula above when the supports
    are isotropic.

    Parameters
    ----------
    scene : Scene
        Supplies S (balancer capacity, body weights' included: :meth:`Scene.weights_capacity`),
        M_Sigma, supports.
    speed : float, optional
        Test speed [rad/s]; default the last speed of the scene's programme
        (torque drive: its target speed).
    zones : iterable of int
        i values; default 0..20.
    cam : ScreenCamera, optional
        Supplies the optical ``gain`` (default 1: shaft displacement).
    plane : str, optional
        Rotor-family scenes: the plane the screen films (default the main plane);
        see :func:`family_ring_radii`.

    Returns
    -------
    ndarray (len(zones),)
    """
    if getattr(scene, "kind", "planar") == "rotor":
        return family_ring_radii(scene, speed, zones, cam, plane)
    S = _capacity(scene)
    w = _speed(scene, speed)
    zones = np.asarray(list(zones), dtype=float)
    Ms = scene.total_mass
    s = scene.supports
    U = zones * S / PARTS
    # phasors of x = Re(X e^{i w t}), y = Re(Y e^{i w t}) for the force U w^2 (cos, sin)
    X = w * w / (s.stiffness_x - Ms * w * w + 1j * w * s.damping_x)
    Y = -1j * w * w / (s.stiffness_y - Ms * w * w + 1j * w * s.damping_y)
    A = 0.5 * (X + 1j * Y)
    B = 0.5 * (np.conj(X) + 1j * np.conj(Y))
    return _gain(cam) * U * (abs(A) + abs(B))


def family_ring_radii(scene: Scene, speed: Optional[float] = None,
                      zones: Iterable[int] = ZONES, cam=None,
                      plane: Optional[str] = None) -> np.ndarray:
    """Ring radii [m] of a rotor-family scene: the steady response of the locked-weights
    rotor (:func:`stand.integrate.coupled.with_locked_weights`, every weight's mass moving
    with its plane) to the unbalance i S / 16 in the main plane (where the balancer of
    capacity S sits), seen in ``plane`` (the screen's; an axis point ``axis@<d>m`` too).

    The steady orbit ``z = A e^{i w t} + B e^{-i w t}`` of the plane is a circle for an
    isotropic rotor and an ellipse otherwise; the radius is its semi-major axis
    ``|A| + |B|`` (as the planar closed form).  The phase of the unbalance does not change it.
    """
    from stand.integrate.coupled import with_locked_weights

    S = _capacity(scene)
    w = _speed(scene, speed)
    zones = np.asarray(list(zones), dtype=float)
    rotor = with_locked_weights(scene.linear_rotor(), scene.weights, scene.bodies)
    at = plane or scene.main_plane
    if at not in rotor.planes:
        raise SceneError(f"calibration rings: plane {at!r} is not a plane of the rotor "
                         f"({', '.join(rotor.planes)})")
    X, Y = rotor.unbalance_response(w, scene.main_plane, s=1.0, at=at)
    A = 0.5 * (X + 1j * Y)
    B = 0.5 * (np.conj(X) + 1j * np.conj(Y))
    return _gain(cam) * zones * S / PARTS * float(abs(A) + abs(B))


def calibration_scene(scene: Scene, unbalance: float, speed: float, duration: float,
                      sample_rate: float, rtol: float = 1e-11, atol: float = 1e-13) -> Scene:
    """The calibration run: the scene's rotor and supports, weights locked to the
    rotor (balancer removed, its mass added to the rotor: mass M_Sigma), the
    calibration ``unbalance`` [kg m] only, constant ``speed`` [rad/s] from t = 0,
    shaft at rest at t = 0."""
    Ms = scene.total_mass
    return Scene(rotor=Rotor(mass=Ms, eccentricity=unbalance / Ms),
                 supports=scene.supports, balancer=Balancer(),
                 drive=SpeedDrive(programme=np.array([[0.0, speed]])),
                 run=RunSettings(duration=duration, sample_rate=sample_rate, rtol=rtol, atol=atol,
                                 method="DOP853"),
                 initial=InitialState(), name="calibration run")


def settle_time(scene: Scene, speed: float, decay: float = 1e-9) -> float:
    """Time [s] after which the start transient of a calibration run has decayed to
    ``decay`` of the steady radius (slowest decay rate of the supports' modes;
    the start transient is at most ~R times the steady circle)."""
    Ms = scene.total_mass
    s = scene.supports
    rates = []
    for c, d in ((s.stiffness_x, s.damping_x), (s.stiffness_y, s.damping_y)):
        w0 = math.sqrt(c / Ms)
        zeta = d / (2.0 * Ms * w0)
        rates.append(zeta * w0 if zeta < 1 else w0 * (zeta - math.sqrt(zeta * zeta - 1.0)))
    rate = min(rates)
    if not rate > 0:
        raise ValueError("calibration run: the supports have no damping, so the start transient "
                         "never decays; use ring_radii (closed form)")
    R = speed / scene.natural_frequency
    return math.log(max(R, 1.0 / R, 1.0) * 10.0 / decay) / rate


def ring_radii_by_simulation(scene: Scene, speed: Optional[float] = None,
                             zones: Iterable[int] = ZONES, cam=None, *,
                             duration: Optional[float] = None, samples_per_rev: int = 64,
                             revolutions: int = 4, rtol: float = 1e-11,
                             atol: float = 1e-13) -> np.ndarray:
    """Ring radii [m on the screen] measured from calibration runs on the simulator.

    For each i, :func:`calibration_scene` with unbalance i S / 16 is simulated
    (:func:`stand.integrate.simulate.simulate`) at constant ``speed`` until the start
    transient has decayed (``duration``, default :func:`settle_time`), and the
    radius is measured over the last ``revolutions`` revolutions by a least-
    squares fit of z = x + i y = A e^{i phi} + B e^{-i phi} + C (phi the rotor
    angle): radius = |A| + |B| (the semi-major axis; |A| for isotropic supports).
    Multiplied by the camera's ``gain``.

    Returns
    -------
    ndarray (len(zones),)
    """
    from stand.integrate.simulate import simulate

    S = _capacity(scene)
    w = _speed(scene, speed)
    if duration is None:
        duration = settle_time(scene, w) + revolutions * 2.0 * math.pi / w
    rate = samples_per_rev * w / (2.0 * math.pi)
    out = []
    for i in zones:
        traj = simulate(calibration_scene(scene, i * S / PARTS, w, duration, rate, rtol, atol))
        if not traj.success:
            raise RuntimeError(f"calibration run for zone {i} failed: {traj.stats.message}")
        sel = traj.t >= traj.t[-1] - revolutions * 2.0 * math.pi / w * (1.0 - 1e-9)
        phi = traj.rotor_angle[sel]
        z = traj.x[sel] + 1j * traj.y[sel]
        M = np.stack([np.exp(1j * phi), np.exp(-1j * phi), np.ones_like(phi)], axis=1)
        coef = np.linalg.lstsq(M, z, rcond=None)[0]
        out.append(abs(coef[0]) + abs(coef[1]))
    return _gain(cam) * np.asarray(out)


def zone_of(radius_m, radii_m) -> np.ndarray:
    """Zone of a spot circle: i such that radii[i] <= radius < radii[i + 1].

    ``radii_m`` are the ring radii of zones 0, 1, ... (radii[0] = 0 for zone 0,
    as :func:`ring_radii` with the default zones returns); a radius beyond the
    last ring gets the last zone index (off scale: >= 1.25 S for zones 0..20).
    Reading to the nearest ring instead (resolution S/32) is
    ``np.argmin(abs(radii - r))``.
    """
    radii = np.asarray(radii_m, dtype=float)
    if radii.ndim != 1 or radii.size == 0 or np.any(np.diff(radii) <= 0):
        raise ValueError("radii_m: must be a non-empty increasing 1-D array (m)")
    idx = np.searchsorted(radii, np.asarray(radius_m, dtype=float), side="right") - 1
    return np.clip(idx, 0, radii.size - 1)


def check_spot_size(cam, radii_m) -> None:
    """The spot must be smaller than zone 0 (§4.3.2): spot diameter < 2 r_1.

    Raises
    ------
    SceneError
        Naming ``spot_diameter``.
    """
    radii = np.asarray(radii_m, dtype=float)
    r1 = radii[1] if radii.size > 1 and radii[0] == 0 else radii[0]
    if not cam.spot_diameter < 2.0 * r1:
        raise SceneError(f"{cam.table}.spot_diameter = {cam.spot_diameter!r}: not smaller than "
                         f"zone 0 (the first ring's diameter {2 * r1:.4g} m, unbalance S/16 at the "
                         f"test speed); use a smaller spot or a larger optical gain (m)")


# ---------------------------------------------------------------- the image
# 3x5 bitmap digits for the zone labels
_DIGITS = {
    "0": ("111", "101", "101", "101", "111"), "1": ("010", "110", "010", "010", "111"),
    "2": ("111", "001", "111", "100", "111"), "3": ("111", "001", "111", "001", "111"),
    "4": ("101", "101", "111", "001", "001"), "5": ("111", "100", "111", "001", "111"),
    "6": ("111", "100", "111", "101", "111"), "7": ("111", "001", "010", "010", "010"),
    "8": ("111", "101", "111", "101", "111"), "9": ("111", "101", "111", "001", "111"),
}


def _draw_text(img, text, u, v, scale, value):
    """Stamp ``text`` (digits) with its top-left corner at pixel (u, v)."""
    for n, ch in enumerate(text):
        glyph = _DIGITS[ch]
        for r, row in enumerate(glyph):
            for c, bit in enumerate(row):
                if bit == "1":
                    i0 = v + r * scale
                    j0 = u + (n * 4 + c) * scale
                    if 0 <= i0 and i0 + scale <= img.shape[0] and 0 <= j0 and j0 + scale <= img.shape[1]:
                        img[i0:i0 + scale, j0:j0 + scale] = value


def render_ring_image(radii_m, cam, *, centre=None, line_width: float = 1.0, labels: bool = False,
                      zones: Optional[Iterable[int]] = None, paper: int = 255, ink: int = 0,
                      label_every: int = 4) -> np.ndarray:
    """The calibration image: the rings as the camera sees them (uint8, H x W).

    Thin anti-aliased circles (box-filtered lines ``line_width`` px wide)
    of radii ``radii_m`` [m on the screen] centred at the undeflected beam
    (default ``(cam.offset_x, cam.offset_y)``), drawn through the camera's
    homography (ellipses when the camera is tilted), ink on paper; a zero
    radius draws nothing.  ``labels``: zone numbers (3x5 bitmap digits) to the
    right of every ``label_every``-th ring (``zones`` gives the numbers;
    default 0, 1, ...).
    """
    from stand.instruments.screen import pixels_to_screen, screen_to_pixels

    radii = np.asarray(radii_m, dtype=float).ravel()
    cx, cy = (cam.offset_x, cam.offset_y) if centre is None else centre
    H, W = cam.height, cam.width
    v, u = np.mgrid[0:H, 0:W].astype(float)
    X, Y = pixels_to_screen(u, v, cam)
    rho = np.hypot(X - cx, Y - cy)
    # |grad rho| in m per px, from the Jacobian of the inverse homography
    eps = 0.5
    Xu, Yu = pixels_to_screen(u + eps, v, cam)
    Xv, Yv = pixels_to_screen(u, v + eps, cam)
    dr_du = (np.hypot(Xu - cx, Yu - cy) - rho) / eps
    dr_dv = (np.hypot(Xv - cx, Yv - cy) - rho) / eps
    grad = np.maximum(np.hypot(dr_du, dr_dv), 1e-300)
    cover = np.zeros((H, W))
    for r in radii:
        if r <= 0:
            continue
        d = np.abs(rho - r) / grad                   # distance to the ring in px
        cover = np.maximum(cover, np.clip(0.5 * line_width + 0.5 - d, 0.0, 1.0))
    img = np.rint(paper + (ink - paper) * cover).astype(np.uint8)
    if labels:
        numbers = list(range(radii.size)) if zones is None else list(zones)
        scale = max(1, int(round(min(H, W) / 240)))
        for k, (r, z) in enumerate(zip(radii, numbers)):
            if r <= 0 or k % label_every:
                continue
            uu, vv = screen_to_pixels(cx + r, cy, cam)
            _draw_text(img, str(z), int(round(float(uu))) + 2 * scale,
                       int(round(float(vv))) - 6 * scale, scale, ink)
    return img
