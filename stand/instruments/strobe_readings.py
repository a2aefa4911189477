"""The light-slot stroboscope: settings, reading error (4.1) and what it shows at each flash.

Monograph section 4.3.1; digest ch5 section 6.1.  A lamp in the machine body
shines through a narrow slot; the rotor has a slot of its own, so light enters
the rotor once per revolution, when the rotor's slot passes the lamp
(:func:`flash_times`), and an observer sees the weights at one rotor angle
(:func:`strobe_angles`).  Reading error (4.1)::

    eta = delta_max / P_min,   P_min = 2 pi slot_radius,

the slot width over the rotor perimeter at the slot, independent of the
speed; while the slots overlap the rotor turns by ``slot_width /
slot_radius`` rad (:attr:`Stroboscope.blur`).  A weight group running at
Omega while the rotor runs at omega shows several images in an exposure over
several flashes (:func:`image_multiplicity`, :func:`multiplicity_for_ratio`).

Body weights (issue 16: two-axis pendulums, coupled pairs, the
autobalancer-damper, liquids) are seen as they look (:class:`BodyLook`,
:func:`body_looks`, :func:`body_coordinates`): a tilting weight or the
damper's weight as a bob at its centre of mass, whose horizontal offset from
the shaft point is ``arm sin(tilt) (-sin angle, cos angle)`` (tilting: the
tilt direction's azimuth is ``angle``, the bob lies 90 deg ahead of it) or
``arm (n_x, n_y)`` (damper); a liquid as the crescent between its chamber and
its free surface, whose centre is offset from the chamber centre by
``-liquid / kappa`` (``liquid``: the liquid's centre of mass from the chamber
centre, ``kappa = r^2/(R^2 - r^2)``).

The frames a camera films through the slot are drawn by
:mod:`stand.instruments.strobe_render`; the settings are scene data
(:mod:`stand.scene.strobe_settings`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from stand.errors import SceneError
from stand.integrate.result import Run, weight_names
from stand.instruments.timing import crossing_times, hermite, sample_trajectory, time_window, wrap
from stand.scene.strobe_settings import (  # noqa: F401 (settings read with the scene)
    Stroboscope, STROBE_KEYS, reading_error, default_ball_radius, TWO_PI, PATH)

__all__ = ["Stroboscope", "StrobeReading", "reading_error", "flash_times", "strobe_angles",
           "image_multiplicity", "multiplicity_for_ratio", "default_ball_radius", "STROBE_KEYS",
           "BodyLook", "body_looks", "body_coordinates", "point_weights", "HOUSING_FACTOR"]

#: drawn housing of a tilting weight or a damper: radius = HOUSING_FACTOR * arm (the scene
#: file's housing_radius is checked, not stored)
HOUSING_FACTOR = 1.25


# ---------------------------------------------------------------- readings
@dataclass
class StrobeReading:
    """What the stroboscope shows at each flash (ground truth, SI units).

    Attributes
    ----------
    t : (K,)                 flash times [s] (the slot's centre passes the lamp)
    rotor_angle : (K,)       rotor angle at the flashes, unwrapped [rad]
                             (= flash_angle + 2 pi k to ~1e-12 rad)
    weight_angle : (K, n)    absolute weight angles [rad]
    relative_angle : (K, n)  weight angles from the reference mark, wrapped to (-pi, pi] [rad]
    x, y : (K,)              shaft displacement [m]
    rotor_speed : (K,)       [rad/s]
    bodies : dict            body weight name -> its coordinates at the flashes
                             (:func:`body_coordinates`); empty without body weights

    ``weight_angle`` and ``relative_angle`` are those of the balls and
    pendulums only (n of them); body weights are in ``bodies``.
    """

    t: np.ndarray
    rotor_angle: np.ndarray
    weight_angle: np.ndarray
    relative_angle: np.ndarray
    x: np.ndarray
    y: np.ndarray
    rotor_speed: np.ndarray
    bodies: dict = field(default_factory=dict)


def flash_times(traj, strobe: Stroboscope, t_start: Optional[float] = None,
                t_end: Optional[float] = None) -> np.ndarray:
    """Times [s] at which the slot's centre passes the lamp.

    The rotor angle crosses ``flash_angle + 2 pi k`` (in either direction: the
    light enters whenever the slots align), found by cubic Hermite
    interpolation of (rotor_angle, rotor_speed) and Newton refinement
    (:func:`stand.instruments.timing.crossing_times`).  Flashes whose angular
    blur would reach outside the sampled run are dropped.

    Parameters
    ----------
    traj : Trajectory
    strobe : Stroboscope
    t_start, t_end : float, optional
        Window [s]; default the whole run.
    """
    t0, t1 = time_window(traj, t_start, t_end, "stroboscope")
    tf = crossing_times(traj.t, traj.rotor_angle, traj.rotor_speed, strobe.flash_angle,
                        direction=0)
    tf = tf[(tf >= t0) & (tf <= t1)]
    if tf.size:  # keep the blur window inside the samples
        i = np.clip(np.searchsorted(traj.t, tf), 0, traj.t.size - 1)
        w = np.maximum(np.abs(traj.rotor_speed[i]), 1e-300)
        half = 0.5 * strobe.blur / w
        tf = tf[(tf - half >= traj.t[0]) & (tf + half <= traj.t[-1])]
    return tf


def strobe_angles(traj, strobe: Stroboscope, t_start: Optional[float] = None,
                  t_end: Optional[float] = None) -> StrobeReading:
    """The weights' angles as the stroboscope shows them, one row per flash.

    Weight angles are Hermite-interpolated from (weight_angle, weight_speed),
    the shaft position from (x, y) and the shaft velocity; see
    :mod:`stand.instruments.timing` for the accuracy (~1e-5 rad with 20
    samples per revolution, much better for smooth weight motion).
    """
    tf = flash_times(traj, strobe, t_start, t_end)
    view = point_weights(traj)
    looks = body_looks(getattr(traj, "scene", None), strobe)
    n = int(np.shape(view.weight_angle)[1]) if np.ndim(view.weight_angle) == 2 else 0
    if tf.size == 0:
        z = np.zeros(0)
        return StrobeReading(z, z, np.zeros((0, n)), np.zeros((0, n)), z, z, z,
                             bodies=body_coordinates(traj, looks, z, z))
    s = sample_trajectory(view, tf)
    return StrobeReading(t=tf, rotor_angle=s.rotor_angle, weight_angle=s.weight_angle,
                         relative_angle=wrap(s.weight_angle - s.rotor_angle[:, None]),
                         x=s.x, y=s.y, rotor_speed=s.rotor_speed,
                         bodies=body_coordinates(traj, looks, tf, s.rotor_angle))


# ---------------------------------------------------------------- body weights
class _PointWeights:
    """A trajectory seen with its balls and pendulums only.

    A run's ``weight_angle`` stacks every weight with an ``angle`` coordinate,
    the tilting weights and the damper included; the stroboscope draws those
    as bodies (:func:`body_coordinates`), so their columns are left out here:
    ``weights`` holds the named ones, stacked by the Run's own properties.
    Every other attribute is the trajectory's.
    """

    _stack = Run._stack
    weight_angle = Run.weight_angle
    weight_speed = Run.weight_speed

    def __init__(self, traj, names):
        self._traj = traj
        self.weights = {nm: traj.weights[nm] for nm in names}

    def __getattr__(self, key):
        return getattr(self._traj, key)


def point_weights(traj):
    """``traj`` itself, or a view of it whose ``weight_angle`` / ``weight_speed`` hold the
    balls and pendulums only when its scene has body weights (:class:`_PointWeights`)."""
    scene = getattr(traj, "scene", None)
    if scene is None or not getattr(scene, "bodies", ()) or not isinstance(
            getattr(traj, "weights", None), dict):
        return traj
    names = [nm for nm in weight_names(scene.weights)[0] if nm in traj.weights]
    return _PointWeights(traj, names)


@dataclass(frozen=True)
class BodyLook:
    """How the stroboscope draws one body weight (SI units).

    Attributes
    ----------
    name : str
        The body's name in the run (``two_axis1``, ``coupled_pair1``, ``damper1``, ``liquid1``).
    type : str
        Its ``[[weights]]`` type (``two_axis_pendulum``, ``coupled_pair``, ``damper``,
        ``liquid_float``, ``liquid_chamber``).
    drawn : {"pendulum", "crescent"}
        A rod from the shaft point to a bob at the centre of mass (tilting weights,
        damper), or the liquid's crescent between the chamber wall and the free surface.
    mass : float
        [kg].
    arm : float
        Pivot to centre of mass [m] (0 for liquids).
    bob_radius : float
        Drawn bob radius [m]: ``ball_radius`` of the settings, else a steel ball of the
        body's mass (0 for liquids).
    housing_radius : float
        Drawn housing around the pivot, ``HOUSING_FACTOR * arm`` [m]; the chamber radius
        for liquids.
    chamber_radius, surface_radius : float
        Liquids: chamber radius R and free-surface (float) radius r [m]; 0 otherwise.
    kappa : float
        Liquids: r^2/(R^2 - r^2) [-], liquid centre-of-mass offset per unit free-surface
        offset; 0 otherwise.
    """

    name: str
    type: str
    drawn: str
    mass: float
    arm: float = 0.0
    bob_radius: float = 0.0
    housing_radius: float = 0.0
    chamber_radius: float = 0.0
    surface_radius: float = 0.0
    kappa: float = 0.0

    @property
    def reach(self) -> float:
        """Largest distance from the shaft point drawn for this body [m]."""
        if self.drawn == "crescent":
            return self.chamber_radius
        return max(self.arm + self.bob_radius, self.housing_radius)

    def to_dict(self, pixel_pitch: Optional[float] = None) -> dict:
        """Plain dict (JSON) with the SI lengths, and in px when ``pixel_pitch`` [m/px] is given."""
        d = {"name": self.name, "type": self.type, "drawn": self.drawn, "mass_kg": self.mass}
        keys = (("arm", self.arm), ("bob_radius", self.bob_radius),
                ("housing_radius", self.housing_radius)) if self.drawn == "pendulum" else \
            (("chamber_radius", self.chamber_radius), ("surface_radius", self.surface_radius))
        for k, v in keys:
            d[f"{k}_m"] = float(v)
            if pixel_pitch:
                d[f"{k}_px"] = float(v) / pixel_pitch
        if self.drawn == "crescent":
            d["kappa"] = float(self.kappa)
        return d


def body_looks(scene, strobe: Optional[Stroboscope] = None) -> tuple:
    """The :class:`BodyLook` of every body weight of ``scene`` (empty without).

    Parameters
    ----------
    scene : Scene or None
    strobe : Stroboscope, optional
        Its ``ball_radius`` [m] sizes the bobs; default a steel ball of each body's mass.
    """
    bodies = tuple(getattr(scene, "bodies", ()) or ()) if scene is not None else ()
    if not bodies:
        return ()
    from stand.model.rotors.bodies import LiquidWeight, body_names

    names, _ = body_names(bodies)
    looks = []
    for nm, pb in zip(names, bodies):
        b = pb.body
        if isinstance(b, LiquidWeight):
            looks.append(BodyLook(nm, b.kind, "crescent", float(b.mass),
                                  housing_radius=float(b.chamber_radius),
                                  chamber_radius=float(b.chamber_radius),
                                  surface_radius=float(b.surface_radius), kappa=float(b.kappa)))
            continue
        bob = strobe.ball_radius if (strobe is not None and strobe.ball_radius is not None) \
            else float(default_ball_radius(b.mass))
        looks.append(BodyLook(nm, b.kind, "pendulum", float(b.mass), arm=float(b.arm),
                              bob_radius=float(bob), housing_radius=HOUSING_FACTOR * float(b.arm)))
    return tuple(looks)


def _interp(t, y, dy, tq):
    """Cubic Hermite of ``y`` at ``tq``; slopes ``dy``, or second-order finite differences
    when the derivative is not recorded."""
    y = np.asarray(y, float)
    if dy is None:
        dy = np.gradient(y, t, edge_order=2) if y.size > 2 else np.gradient(y, t)
    return hermite(t, y, np.asarray(dy, float), tq)


def body_coordinates(traj, looks, tq, rotor_angle=None) -> dict:
    """Each body weight's coordinates at the times ``tq`` [s], as the stroboscope shows them.

    Interpolation: tilting weights from (angle, speed) and (tilt, tilt_rate),
    cubic Hermite with the recorded derivatives; the damper's direction
    (n_x, n_y, n_z) and the liquids' offsets cubic Hermite with finite-difference
    slopes (the damper's direction renormalised).

    Parameters
    ----------
    traj : Run
        With ``weights[name]`` for every body (:attr:`stand.integrate.result.Run.weights`).
    looks : sequence of BodyLook
    tq : array_like (M,)
        Times [s] inside the run.
    rotor_angle : array_like (M,), optional
        Rotor angle at ``tq`` [rad]; adds ``relative_azimuth``.

    Returns
    -------
    dict
        name -> dict of (M,) arrays: the body's own coordinates (``angle``, ``tilt`` [rad];
        ``n_x``, ``n_y``, ``n_z`` [-]; ``liquid_x``, ``liquid_y``, ``surface_x``,
        ``surface_y`` [m], fixed frame from the chamber centre) and what the picture shows:
        ``offset_x``, ``offset_y`` [m] the drawn centre of mass (the bob; the liquid's
        centre of mass) from the shaft point, fixed frame; ``radius`` [m] its length (the
        apparent radial offset ``arm |sin(tilt)|`` of a tilting weight); ``azimuth`` [rad]
        its absolute direction and ``relative_azimuth`` [rad] that direction from the
        reference mark, wrapped to (-pi, pi].

    Raises
    ------
    SceneError
        The run carries no coordinates for a body.
    """
    tq = np.atleast_1d(np.asarray(tq, float))
    out = {}
    if not looks:
        return out
    weights = getattr(traj, "weights", None) or {}
    t = np.asarray(traj.t, float)
    for lk in looks:
        w = weights.get(lk.name)
        if w is None:
            raise SceneError(f"{PATH}: the run carries no coordinates for the body weight "
                             f"{lk.name!r} (weights: {', '.join(weights) or 'none'})")
        if tq.size == 0:
            d = {}
        elif lk.drawn == "crescent":
            lx = _interp(t, w["liquid_x"], None, tq)
            ly = _interp(t, w["liquid_y"], None, tq)
            if "surface_x" in w:
                sx = _interp(t, w["surface_x"], None, tq)
                sy = _interp(t, w["surface_y"], None, tq)
            else:
                sx, sy = -lx / lk.kappa, -ly / lk.kappa
            d = {"liquid_x": lx, "liquid_y": ly, "surface_x": sx, "surface_y": sy,
                 "offset_x": lx, "offset_y": ly}
        elif "n_x" in w:
            n = np.column_stack([_interp(t, w[c], None, tq) for c in ("n_x", "n_y", "n_z")])
            n = n / np.linalg.norm(n, axis=1)[:, None]
            d = {"n_x": n[:, 0], "n_y": n[:, 1], "n_z": n[:, 2],
                 "tilt": np.arccos(np.clip(-n[:, 2], -1.0, 1.0)),
                 "offset_x": lk.arm * n[:, 0], "offset_y": lk.arm * n[:, 1]}
        else:
            al = _interp(t, w["angle"], w.get("speed"), tq)
            ph = _interp(t, w["tilt"], w.get("tilt_rate"), tq)
            r = lk.arm * np.sin(ph)
            d = {"angle": al, "tilt": ph, "offset_x": -r * np.sin(al), "offset_y": r * np.cos(al)}
        if tq.size == 0:
            z = np.zeros(0)
            d = {"offset_x": z, "offset_y": z}
        d["radius"] = np.hypot(d["offset_x"], d["offset_y"])
        d["azimuth"] = np.arctan2(d["offset_y"], d["offset_x"])
        if rotor_angle is not None:
            d["relative_azimuth"] = wrap(d["azimuth"] - np.asarray(rotor_angle, float))
        out[lk.name] = d
    return out


# ---------------------------------------------------------------- multiplicity
def image_multiplicity(angles, blur: float) -> int:
    """Number of distinct images of weights at ``angles`` (a multi-flash exposure).

    Angles on the circle closer than ``blur`` (single linkage: chains of
    neighbours each within ``blur``) merge into one image.  For a rendered
    frame the natural ``blur`` is the angular size of a weight image,
    ``2 ball_radius / track_radius + slot_width / slot_radius``.

    Parameters
    ----------
    angles : array_like
        Relative (or absolute) angles of all weight images in the exposure,
        any shape, e.g. ``StrobeFrame.relative_angle`` (K flashes x n weights) [rad].
    blur : float
        Merging distance [rad], >= 0.

    Returns
    -------
    int
        0 for no angles, else the number of clusters on the circle.
    """
    a = np.sort(np.mod(np.ravel(np.asarray(angles, float)), TWO_PI))
    if a.size == 0:
        return 0
    if not blur >= 0:
        raise ValueError(f"image_multiplicity: blur = {blur!r} rad must be >= 0")
    gaps = np.diff(np.concatenate([a, [a[0] + TWO_PI]]))
    return max(1, int(np.count_nonzero(gaps > blur)))


def multiplicity_for_ratio(ratio: float, flashes: int, blur: float) -> int:
    """Images of one weight group running at Omega = ratio * omega over ``flashes``.

    Successive flashes show it at relative angles ``-2 pi k (1 - ratio)``
    (digest ch5 section 5.3); :func:`image_multiplicity` of those.  For
    ``ratio ~ p/q`` (lowest terms) and enough flashes this is ``q``: doubling
    at 1/2, tripling at 1/3 -- when ``blur`` exceeds the slow drift
    ``2 pi |ratio - p/q| * q`` per cycle; otherwise more images.
    """
    k = np.arange(int(flashes))
    return image_multiplicity(-TWO_PI * k * (1.0 - ratio), blur)

