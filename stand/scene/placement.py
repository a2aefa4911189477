"""Where an instrument looks: a named plane of the rotor, or a point of a tilting rotor's axis.

Every ``[instruments.<name>]`` table may say where the instrument is attached::

    [instruments.screen]
    plane = "body"            # a plane of the rotor (default: the scene's main plane)
    # or
    axial_position = 0.45     # m: the point of the shaft axis at this axial distance

* ``plane`` names one of the scene's planes (:attr:`stand.scene.model.Scene.planes`): the
  screen films the spot of that plane's fixed-frame translation
  (:attr:`stand.integrate.result.Run.planes`), the probes measure it, the stroboscope draws
  the weights that sit in that plane (balls at their angles; body weights as on
  planar scenes).  Default: :attr:`stand.scene.model.Scene.main_plane`.
* ``axial_position = d`` [m] (rotors with tilt coordinates only): the laser beam
  along the shaft axis hits a screen at axial distance ``d`` where the axis line
  is ((4.2) of the book: ``x + d beta, y - d alpha`` for the rigid rotor (2.131)).
  The point's plane map is built with the rotor type's own map of an axis point
  (:data:`AXIS_MAPS`) and added to the rotor as the plane ``axis@<d>m`` for the run
  (a plane map only: the dynamics are unchanged).  The distance is measured as the
  rotor type measures its plane positions: from the centre of mass (``spatial``),
  from the fixed point O (``spherical_hinge``, ``cylindrical_hinge``,
  ``fixed_point_stand``), from the left support (``flexible``, 0 < d < length),
  along the spin axis from the platform frame (``platform``, default parameters).
  Types without tilt coordinates (``planar``, ``two_mass``, ``grinding``) say
  "not applicable".

The placement travels with the settings object (attribute ``placement``, set by
the scene parser); settings built in Python without it sit in the main plane.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from stand.errors import SceneError

__all__ = ["Placement", "PLACEMENT_KEYS", "AXIS_MAPS", "NO_TILT", "split_placement",
           "attach", "placement_of", "instrument_plane", "axis_plane_name", "axis_map",
           "with_axis_planes", "check_placement", "is_screen", "screens"]

#: keys of an ``[instruments.<name>]`` table that place the instrument (not its settings)
PLACEMENT_KEYS = ("plane", "axial_position")

#: rotor types without tilt coordinates: ``axial_position`` is not applicable
NO_TILT = {
    "planar": "the planar rotor (2.5.1) translates without tilting: every point of its axis "
              "moves alike; use plane = \"balancer\"",
    "two_mass": "the two-mass system (2.5.2) has translations only (planes \"body\" and "
                "\"balancer\"); use plane = ...",
    "grinding": "the grinding rotor (2.5.3) has one translation only; use plane = \"balancer\"",
}


@dataclass(frozen=True)
class Placement:
    """Where an instrument is attached.

    Attributes
    ----------
    plane : str or None
        A plane of the rotor; None: the scene's main plane (or the axis point).
    axial_position : float or None
        Axial distance [m] of the axis point filmed (tilting rotors).
    table : str
        The table's dotted path, for messages.
    """

    plane: Optional[str] = None
    axial_position: Optional[float] = None
    table: str = "instruments"

    def to_attrs(self) -> dict:
        d = {}
        if self.plane is not None:
            d["plane"] = self.plane
        if self.axial_position is not None:
            d["axial_position_m"] = float(self.axial_position)
        return d


def split_placement(data, path: str):
    """``(settings table without the placement keys, Placement)`` of one instrument table."""
    if not isinstance(data, dict):
        return data, Placement(table=path)
    data = dict(data)
    plane = data.pop("plane", None)
    ax = data.pop("axial_position", None)
    if plane is not None and not isinstance(plane, str):
        raise SceneError(f"{path}.plane = {plane!r}: must be a string, the name of a plane of "
                         "the rotor")
    if ax is not None:
        if isinstance(ax, bool) or not isinstance(ax, (int, float)) or not math.isfinite(ax):
            raise SceneError(f"{path}.axial_position = {ax!r}: must be a finite number (m)")
        ax = float(ax)
    if plane is not None and ax is not None:
        raise SceneError(f"{path}: give plane or axial_position, not both (axial_position = "
                         f"{ax:g} m films the axis point at that distance; plane = \"{plane}\" "
                         "a named plane)")
    return data, Placement(plane, ax, path)


def attach(settings, placement: Placement):
    """Store ``placement`` on a (frozen) settings object; returns it."""
    try:
        object.__setattr__(settings, "placement", placement)
    except (AttributeError, TypeError):   # pragma: no cover - settings with __slots__
        pass
    return settings


def placement_of(settings) -> Placement:
    """The instrument's placement (default: the main plane)."""
    p = getattr(settings, "placement", None)
    return p if isinstance(p, Placement) else Placement()


# ---------------------------------------------------------------- axis points
def _spatial(params, rotor, d):
    from stand.model.rotors.spatial_supports import plane_map

    return plane_map(d)


def _tilt(params, rotor, d):      # (2.70) on (alpha, beta): x = d beta, y = -d alpha
    return np.array([[0.0, d], [-d, 0.0]])


def _hinge(params, rotor, d):     # (2.104) on (beta,): x = d beta, y = 0
    return np.array([[d], [0.0]])


def _flexible(params, rotor, d):
    length = float(params["length"])
    if not 0.0 < d < length:
        raise SceneError(f"axial_position = {d:g} m: must lie strictly between the supports, "
                         f"0 < d < length = {length:g} m")
    J = rotor.n // 2
    j = np.arange(1, J + 1)
    return np.kron(np.eye(2), np.sin(math.pi * j * d / length)[None, :])


def _platform(params, rotor, d):
    if params:
        raise SceneError("axial_position on a platform with parameters given in [structure]: not "
                         "applicable in this version (the axis map needs the platform's "
                         "parameter set); use plane = \"rotor\" or \"balancer\"")
    from stand.model.rotors.platform import default_params, plane_map

    return plane_map(default_params(), d)


#: rotor type -> ``f(structure params, LinearRotor, d [m]) -> T (2 x n)``: the map of the
#: axis point at axial distance d (the builder's own plane map)
AXIS_MAPS = {
    "spatial": _spatial,
    "spherical_hinge": _tilt,
    "cylindrical_hinge": _hinge,
    "fixed_point_stand": _hinge,
    "flexible": _flexible,
    "platform": _platform,
}


def axis_plane_name(d: float) -> str:
    """Name of the plane added for the axis point at ``d`` [m]."""
    return f"axis@{d:g}m"


def axis_map(scene, d: float, where: str = "axial_position") -> np.ndarray:
    """The plane map (2 x n) of the axis point at axial distance ``d`` of the scene's rotor."""
    kind = scene.structure_type
    if kind in NO_TILT or kind not in AXIS_MAPS:
        why = NO_TILT.get(kind, f"rotor type {kind!r} has no map of its axis points")
        raise SceneError(f"{where} = {d:g}: not applicable: {why}")
    rotor = scene.linear_rotor()
    params = dict(getattr(scene.structure, "params", {}) or {})
    try:
        T = np.asarray(AXIS_MAPS[kind](params, rotor, float(d)), float)
    except SceneError as exc:
        raise SceneError(f"{where}: {exc}") from None
    except ValueError as exc:
        raise SceneError(f"{where} = {d:g}: {exc}") from None
    if T.shape != (2, rotor.n):  # pragma: no cover - a builder's map of another size
        raise SceneError(f"{where}: the axis map of rotor type {kind!r} has shape {T.shape}, "
                         f"not (2, {rotor.n})")
    return T


def check_placement(settings, planes, kind: str, scene=None) -> None:
    """Check one instrument's placement against the scene's planes and rotor type."""
    p = placement_of(settings)
    if p.plane is not None and p.plane not in planes:
        raise SceneError(f"{p.table}.plane = \"{p.plane}\": not a plane of rotor type "
                         f"\"{kind}\"; planes: {', '.join(planes)}")
    if p.axial_position is not None:
        if kind in NO_TILT or kind not in AXIS_MAPS:
            why = NO_TILT.get(kind, f"rotor type {kind!r} has no map of its axis points")
            raise SceneError(f"{p.table}.axial_position = {p.axial_position:g}: not applicable: "
                             f"{why}")
        if scene is not None:
            axis_map(scene, p.axial_position, f"{p.table}.axial_position")


def instrument_plane(scene, settings) -> str:
    """The plane an instrument looks at (the axis point's plane name for ``axial_position``)."""
    p = placement_of(settings)
    if p.axial_position is not None:
        return axis_plane_name(p.axial_position)
    return p.plane or scene.main_plane


def with_axis_planes(scene):
    """``scene`` whose rotor also has the planes of the instruments' axis points (plane maps
    only: the dynamics are unchanged); ``scene`` itself when no instrument asks for one."""
    import dataclasses

    extra = {}
    for s in scene.instruments.values():
        p = placement_of(s)
        if p.axial_position is not None:
            extra[axis_plane_name(p.axial_position)] = axis_map(
                scene, p.axial_position, f"{p.table}.axial_position")
    if not extra:
        return scene
    st = scene.structure
    rotor = st.rotor
    planes = dict(rotor.planes)
    planes.update(extra)
    rotor = dataclasses.replace(rotor, planes=planes)
    return dataclasses.replace(scene, structure=dataclasses.replace(st, rotor=rotor))


def is_screen(name: str) -> bool:
    """``[instruments.screen]`` (name ``"screen"``) or a named one ``[instruments.screen.<n>]``."""
    return name == "screen" or name.startswith("screen.")


def screens(instruments) -> dict:
    """The screen cameras of a scene's instruments, name -> settings, in the scene's order."""
    return {k: v for k, v in instruments.items() if is_screen(k)}


def check_instruments(scene) -> None:
    """The checks :func:`stand.scene.parse.check_derived` makes of the instruments of a
    planar scene, for a rotor-family scene: placements (axis maps built), then
    :func:`check_instrument_budget`."""
    if scene.kind == "book":
        raise SceneError("[instruments]: not available on a book weight model ([weight_model]); "
                         "write the scene with [structure] + [[weights]]")
    planes, kind = tuple(scene.planes), scene.structure_type
    for inst in scene.instruments.values():
        check_placement(inst, planes, kind, scene)
    width = 2 * (scene.linear_rotor().n + scene.n_weights) + 8 * len(scene.bodies)
    check_instrument_budget(scene, width)


def check_instrument_budget(scene, width: int) -> None:
    """Every scene's instruments: image sizes, the memory of all screens' exposure
    sub-samples (simulated state rows of ``width`` numbers), each instrument against the
    run settings.  Errors name the table, the value and the limit."""
    from stand.scene.limits import MAX_IMAGE_PIXELS, MAX_STATE_BYTES

    for inst in scene.instruments.values():
        w, h = getattr(inst, "width", 0), getattr(inst, "height", 0)
        if w * h > MAX_IMAGE_PIXELS:
            raise SceneError(f"{getattr(inst, 'table', 'instruments')}: width x height = {w} x "
                             f"{h} px: more than {MAX_IMAGE_PIXELS / 1e6:.0f} Mpx per image")
    run = scene.run
    nbytes, what = 0, []
    for name, cam in screens(scene.instruments).items():
        from stand.scene.screen_camera import exposure_times, frame_times

        n_frames = frame_times(run.duration, cam).size
        k = exposure_times(np.zeros(1), cam, max_rotor_speed=scene.top_speed).shape[1]
        nbytes += n_frames * k * width * 8 * 3
        what.append(f"{n_frames} frames x {k} exposure sub-samples ({name})")
        if nbytes > MAX_STATE_BYTES / 4:
            raise SceneError(
                f"instruments.screen: {' + '.join(what)} need about "
                f"{nbytes / 1e9:.3g} GB of simulated samples (limit {MAX_STATE_BYTES / 4e9:.0f} GB): "
                "lower frame_rate or subsamples, or film a part of the run with start_time")
    for inst in scene.instruments.values():
        check = getattr(inst, "check_against_run", None)
        if check is not None:
            check(run)
