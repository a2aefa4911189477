"""Run a scene with its instruments and store what they record beside the ground truth.

Only what the scene asks for is computed: a scene without ``[instruments.*]``
tables renders nothing and samples nothing extra.  The screen camera's
exposure sub-samples are requested from the simulator in the same run
(``simulate(extra_times=...)``); the stroboscope, photo-gate, keyphasor,
tachometer and probes interpolate the recorded samples (cubic Hermite with the
recorded speeds, :mod:`stand.instruments.timing`).  Frames are rendered and
written one at a time, so a long video never sits in memory.

Recording layout (HDF5, beside the core datasets of :mod:`stand.recording.hdf5`)::

    instruments/<name>/...        what the instrument outputs (frames, times, readings)
    instruments/<name>.attrs      its settings as JSON (SI units)
    truth/<name>/...              the ground truth for scoring identification

Scenes with body weights (two-axis pendulums, coupled pairs, the damper,
liquids; they run on the generic kernel) are seen too: the screen films the
shaft's spot whatever the weights; the stroboscope draws each body as it looks
and records, per body, ``truth/stroboscope/<name>/<coordinate>`` (frame, flash)
at the flashes, and what it draws of each weight in the attrs ``weights``
(JSON) of ``instruments/stroboscope``; ``truth/capacity`` and the calibration
rings count the bodies' capacities (:func:`stand.instruments.rings.scene_capacity`).
"""
from __future__ import annotations

import dataclasses
import json
import math

import numpy as np

from stand.scene.model import Scene, SceneError
from stand.integrate.simulate import Trajectory, simulate
from stand.instruments.placement import instrument_plane, placement_of, screens, with_axis_planes
from stand.instruments.rings import scene_capacity

FRAME_COMPRESSION = {"compression": "gzip", "compression_opts": 1, "shuffle": True}
#: at most this many stroboscope frames per recording (one flash per revolution adds up)
MAX_STROBE_FRAMES = 200


def _settings_json(settings) -> str:
    def plain(v):
        if isinstance(v, np.ndarray):
            return v.tolist()
        if isinstance(v, (np.floating, np.integer)):
            return v.item()
        if isinstance(v, float) and not math.isfinite(v):
            return str(v)
        return v
    d = dataclasses.asdict(settings) if dataclasses.is_dataclass(settings) else dict(settings)
    return json.dumps({k: plain(v) for k, v in d.items()}, default=str)


def plane_view(traj, scene: Scene, settings):
    """``(view, plane, names)``: the run as the instrument ``settings`` sees it.

    Planar scenes: the run itself (one plane).  Rotor-family scenes: the run whose
    main plane is the instrument's plane (:func:`stand.instruments.placement.instrument_plane`)
    -- ``x``, ``y`` and the shaft velocity are that plane's -- and whose scene and weights
    are those of that plane only (the stroboscope draws the weights of the plane it looks
    at); the weights are renamed as a scene with that plane's weights only numbers them
    (``names``: view name -> name in the run).
    """
    plane = instrument_plane(scene, settings)
    if scene.kind != "rotor" or traj is None:
        return traj, plane, {}
    from stand.integrate.result import weight_names
    from stand.scene.model import Balancer
    from stand.instruments.timing import shaft_velocity

    full = dataclasses.replace(traj, main_plane=plane, extra=None)
    pw = tuple(w for w in scene.plane_weights if w.plane == plane)
    balls = [w for w in pw if hasattr(w, "balancer")]
    vscene = dataclasses.replace(scene, plane_weights=pw,
                                 balancer=balls[0].balancer if len(balls) == 1 else Balancer())

    def named(sc):
        n, p = weight_names(sc.weights)
        if sc.bodies:
            from stand.model.rotors.bodies import body_names

            bn, bp = body_names(sc.bodies)
            n, p = n + bn, p + bp
        return [nm for nm, pl in zip(n, p) if pl == plane]

    names = dict(zip(named(vscene), named(scene)))
    view = dataclasses.replace(full, scene=vscene,
                               weights={new: traj.weights[old] for new, old in names.items()
                                        if old in traj.weights},
                               weight_planes={new: plane for new in names})
    try:
        view.vx, view.vy = shaft_velocity(full)
    except ValueError:
        pass
    return view, plane, names


def _place_attrs(g, plane: str, settings, names=None) -> None:
    """Where the instrument looks, stored with its output."""
    g.attrs["plane"] = plane
    p = placement_of(settings)
    if p.axial_position is not None:
        g.attrs["axial_position_m"] = float(p.axial_position)
    if names and any(k != v for k, v in names.items()):
        g.attrs["weight_names_in_run"] = json.dumps(names)


def _max_speed(scene: Scene) -> float:
    return scene.top_speed


def _screen_plan(scene: Scene, name: str = "screen"):
    from stand.instruments.screen import exposure_times, frame_times

    cam = scene.instruments[name]
    starts = frame_times(scene.run.duration, cam)
    times = exposure_times(starts, cam, max_rotor_speed=_max_speed(scene))
    return cam, starts, times


def _screen_plans(scene: Scene):
    """``(plans, extra)``: per screen name ``(cam, starts, times, index)`` -- ``index`` (F x K)
    of each exposure sub-sample in the run's extra samples -- and the extra sample times
    (the screens' exposure sub-samples merged; one screen: its own, unchanged)."""
    plans = {name: _screen_plan(scene, name) for name in screens(scene.instruments)}
    if not plans:
        return {}, None
    if len(plans) == 1:
        (name, (cam, starts, times)), = plans.items()
        return {name: (cam, starts, times, np.arange(times.size).reshape(times.shape))}, \
            times.ravel()
    extra = np.unique(np.concatenate([p[2].ravel() for p in plans.values()]))
    return {name: (cam, starts, times, np.searchsorted(extra, times))
            for name, (cam, starts, times) in plans.items()}, extra


def run_with_instruments(scene: Scene, method: str | None = None, progress: bool = False,
                         checkpoint=None, rtol: float | None = None, atol: float | None = None):
    """Simulate ``scene`` and prepare its instruments.

    Returns
    -------
    traj : Trajectory
        The recording-grid trajectory (``traj.extra`` holds the camera's
        exposure samples when there is a screen camera).
    writer : callable or None
        ``writer(h5file)`` stores every instrument's output and truth; pass it
        to :func:`stand.recording.hdf5.write_recording`.  None without instruments.
    """
    if not scene.instruments:
        return simulate(scene, method=method, progress=progress, checkpoint=checkpoint,
                        rtol=rtol, atol=atol), None
    if scene.kind == "book":
        raise SceneError(f"[instruments]: not available on a book weight model (the scene's "
                         f"structure is {scene.structure_type}); write it with [structure] + "
                         "[[weights]] to attach instruments")
    if scene.kind == "rotor":   # the instruments' axis points become planes of the run
        scene = with_axis_planes(scene)
    plans, extra = _screen_plans(scene)
    traj = simulate(scene, method=method, progress=progress, extra_times=extra, checkpoint=checkpoint,
                    rtol=rtol, atol=atol)

    def writer(f):
        write_instruments(f, scene, traj, plans)

    # an upper bound of what the instruments store (16-bit frames, uncompressed), so the
    # recording writer knows whether it may assemble the file in memory (stand.recording.hdf5)
    frame_bytes = sum((len(p[1]) + 1) * 2 * p[0].width * p[0].height for p in plans.values())
    writer.estimated_bytes = frame_bytes + \
        (MAX_STROBE_FRAMES * 2 * 1024 * 1024 if "stroboscope" in scene.instruments else 0) + \
        64 * traj.t.size * 8
    return traj, writer


def write_instruments(f, scene: Scene, traj: Trajectory, plans=None) -> None:
    """Store the output and truth of every instrument of ``scene`` into the open file ``f``.

    Each screen ``name`` (``"screen"``, or ``"screen.<n>"`` for the named screens
    ``[instruments.screen.<n>]``) writes ``instruments/<name>`` and ``truth/<name>``.
    """
    inst = scene.instruments
    if scene.kind == "rotor" and any(placement_of(s).axial_position is not None
                                     for s in inst.values()):
        scene = with_axis_planes(scene)     # (idempotent: the run's scene already has them)
    if plans is None:
        plans = _screen_plans(scene)[0]
    for name, plan in plans.items():
        _write_screen(f, scene, traj, plan, name)
    if "stroboscope" in inst:
        _write_strobe(f, scene, traj)
    if "photogate" in inst:
        _write_photogate(f, scene, traj)
    if "keyphasor" in inst:
        from stand.instruments.probes import keyphasor_pulses

        g = f.require_group("instruments/keyphasor")
        g.attrs["settings"] = _settings_json(inst["keyphasor"])
        ds = g.create_dataset("pulse_time", data=keyphasor_pulses(traj, inst["keyphasor"]))
        ds.attrs["units"] = "s"
    if "tachometer" in inst:
        from stand.instruments.probes import tachometer_readings

        g = f.require_group("instruments/tachometer")
        g.attrs["settings"] = _settings_json(inst["tachometer"])
        _write_dict(g, tachometer_readings(traj, inst["tachometer"]),
                    {"time": "s", "speed": "rad/s", "counts": "1", "true_speed": "rad/s",
                     "true_speed_at_time": "rad/s"})
    if "probes" in inst:
        from stand.instruments.probes import probe_signals

        g = f.require_group("instruments/probes")
        g.attrs["settings"] = _settings_json(inst["probes"])
        view, plane, _ = plane_view(traj, scene, inst["probes"])
        if scene.kind == "rotor":
            _place_attrs(g, plane, inst["probes"])
        _write_dict(g, probe_signals(view, inst["probes"]),
                    {"time": "s", "signal": "m", "displacement": "m", "runout": "m", "noise": "m",
                     "rotor_angle": "rad", "angles": "rad"})
    _write_truth(f, scene, traj)


def _write_dict(g, d: dict, units: dict) -> None:
    for k, v in d.items():
        a = np.asarray(v)
        if a.dtype == object:
            continue
        ds = g.create_dataset(k, data=a)
        if k in units:
            ds.attrs["units"] = units[k]


def _write_screen(f, scene: Scene, traj: Trajectory, plan, name: str = "screen") -> None:
    from stand.instruments.render import render_frames
    from stand.instruments.rings import check_spot_size, render_ring_image, ring_radii
    from stand.instruments.screen import frame_truth, spot_positions

    cam, starts, times, index = plan
    ex, plane, _ = plane_view(traj.extra, scene, cam)
    F, K = times.shape
    # a run that stopped early renders the frames it has
    n_ok = int(np.count_nonzero(np.all(index < ex.t.size, axis=1)))
    shape = (n_ok, K)
    sl = index[:n_ok].ravel()
    screen_m, px = spot_positions(ex.x[sl].reshape(shape), ex.y[sl].reshape(shape),
                                  ex.rotor_angle[sl].reshape(shape), cam)
    truth = frame_truth(screen_m, px, cam)
    g = f.require_group(f"instruments/{name}")
    g.attrs["settings"] = _settings_json(cam.to_attrs() if hasattr(cam, "to_attrs") else cam)
    g.attrs["description"] = ("camera filming the laser spot on the screen: frames (row = image "
                              "row, column = image column), exposure start times")
    ds = g.create_dataset("frame_time", data=starts[:n_ok])
    ds.attrs["units"] = "s"
    ds.attrs["description"] = "start of each frame's exposure"
    ds = g.create_dataset("frame_rotor_angle", data=ex.rotor_angle[sl].reshape(shape)[:, 0])
    ds.attrs["units"] = "rad"
    ds.attrs["description"] = "rotor angle (reference mark) at the first exposure sub-sample"
    g.attrs["exposure_s"] = float(cam.exposure)
    if scene.kind == "rotor":
        _place_attrs(g, plane, cam)
        g.attrs["plane_description"] = ("the spot shows this plane's fixed-frame translation "
                                        "(planes/<plane> of the run; axis@<d>m: the point of "
                                        "the shaft axis at axial distance d) times the gain")
    frames = g.create_dataset("frames", shape=(n_ok, cam.height, cam.width), dtype=cam.dtype,
                              chunks=(1, cam.height, cam.width), **FRAME_COMPRESSION)
    frames.attrs["units"] = "DN"
    for i, img in enumerate(render_frames(px, cam)):
        frames[i] = img
    # calibration rings at the test (operating) speed: zones i S/16, i = 0..20
    test_speed = _max_speed(scene)
    if scene_capacity(scene) > 0 and test_speed > 0:
        radii = ring_radii(scene, speed=test_speed, cam=cam, plane=plane)
        g.attrs["ring_test_speed_rad_s"] = test_speed
        ds = g.create_dataset("ring_radius", data=radii)
        ds.attrs["units"] = "m"
        ds.attrs["description"] = "zone i boundary: steady spot radius for unbalance i*S/16 at the test speed"
        g.create_dataset("calibration_image", data=render_ring_image(radii, cam),
                         **FRAME_COMPRESSION)
        try:
            check_spot_size(cam, radii)
        except ValueError as exc:  # a warning for the user, kept with the data
            g.attrs["warning"] = str(exc)
    t = f.require_group(f"truth/{name}")
    for key, unit in (("centre_px", "px"), ("centre_m", "m"), ("in_frame", "1")):
        ds = t.create_dataset(key, data=np.asarray(truth[key])[:n_ok])
        ds.attrs["units"] = unit
    ds = t.create_dataset("exposure_time", data=times[:n_ok])
    ds.attrs["units"] = "s"


#: units of the body coordinates stored as stroboscope truth
_BODY_UNITS = {"angle": "rad", "tilt": "rad", "n_x": "1", "n_y": "1", "n_z": "1",
               "liquid_x": "m", "liquid_y": "m", "surface_x": "m", "surface_y": "m",
               "offset_x": "m", "offset_y": "m", "radius": "m", "azimuth": "rad",
               "relative_azimuth": "rad", "px": "px"}
_BODY_DESCRIPTIONS = {
    "offset_x": "drawn centre of mass (bob; liquid's centre of mass) from the shaft point, fixed X",
    "offset_y": "drawn centre of mass (bob; liquid's centre of mass) from the shaft point, fixed Y",
    "radius": "apparent radial offset of the centre of mass from the shaft point",
    "azimuth": "absolute direction of the centre of mass from the shaft point",
    "relative_azimuth": "direction of the centre of mass from the reference mark, wrapped to (-pi, pi]",
    "px": "drawn bob centre, liquids: free-surface centre (column, row)",
    "surface_x": "free-surface centre from the chamber centre, fixed X",
    "surface_y": "free-surface centre from the chamber centre, fixed Y",
}


def _write_strobe(f, scene: Scene, traj: Trajectory) -> None:
    from stand.instruments.stroboscope import drawn_weights, render_strobe_frames

    strobe = scene.instruments["stroboscope"]
    traj, plane, names = plane_view(traj, scene, strobe)
    scene = getattr(traj, "scene", None) or scene
    speed = np.abs(traj.rotor_speed)
    moving = np.nonzero(speed > 0.1 * max(float(np.max(speed)), 1e-12))[0]
    t_start = float(traj.t[moving[0]]) if moving.size else None
    g = f.require_group("instruments/stroboscope")
    g.attrs["settings"] = _settings_json(strobe)
    g.attrs["description"] = "frames lit by the slot once per revolution; flash times per frame"
    g.attrs["weights"] = json.dumps(drawn_weights(scene, strobe))
    if scene.kind == "rotor":
        _place_attrs(g, plane, strobe, names)
    g.attrs["weights_description"] = ("what the frames show of each weight (JSON list): balls "
                                      "and pendulums on their track; body weights as a bob on a "
                                      "rod from the pivot (drawn = pendulum) or a liquid's "
                                      "crescent (drawn = crescent); lengths in m and px")
    if t_start is None or float(np.max(speed)) * (traj.t[-1] - t_start) < 2 * math.pi:
        g.attrs["note"] = "the rotor does not complete a revolution: no flashes, no frames"
        return
    g.attrs["t_start_s"] = t_start
    g.attrs["t_start_rule"] = "first sample with the rotor above 10 % of its largest speed"
    frames = None
    times, rel, rot, centre = [], [], [], []
    bodies: dict = {}
    for i, fr in enumerate(render_strobe_frames(traj, strobe, t_start=t_start,
                                                max_frames=MAX_STROBE_FRAMES)):
        if frames is None:
            frames = g.create_dataset("frames", shape=(0,) + fr.image.shape,
                                      maxshape=(None,) + fr.image.shape, dtype=fr.image.dtype,
                                      chunks=(1,) + fr.image.shape, **FRAME_COMPRESSION)
        frames.resize(i + 1, axis=0)
        frames[i] = fr.image
        frames.attrs["units"] = "DN"
        times.append(fr.t)
        rel.append(fr.relative_angle)
        rot.append(fr.rotor_angle)
        centre.append(fr.centre_px)
        for name, coords in fr.bodies.items():
            for key, a in coords.items():
                bodies.setdefault(name, {}).setdefault(key, []).append(a)
    g.attrs["frames_limit"] = MAX_STROBE_FRAMES
    g.attrs["truncated"] = bool(len(times) >= MAX_STROBE_FRAMES)
    ds = g.create_dataset("flash_time", data=np.array(times).reshape(len(times), -1))
    ds.attrs["units"] = "s"
    ds = g.create_dataset("flash_rotor_angle", data=np.array(rot).reshape(len(rot), -1))
    ds.attrs["units"] = "rad"
    t = f.require_group("truth/stroboscope")
    n = int(np.shape(rel[0])[-1]) if rel else 0
    if n:
        ds = t.create_dataset("relative_angle", data=np.array(rel).reshape(len(rel), -1, n))
        ds.attrs["units"] = "rad"
        ds.attrs["description"] = ("balls / pendulums: angle from the reference mark at each "
                                   "flash (frame, flash, weight)")
    if centre:
        ds = t.create_dataset("centre_px", data=np.array(centre).reshape(len(centre), -1, 2))
        ds.attrs["units"] = "px"
        ds.attrs["description"] = "drawn rotor centre (shaft point) at each flash (column, row)"
    for name, coords in bodies.items():
        b = t.require_group(name)
        b.attrs["description"] = (f"body weight {name} at each flash (frame, flash[, 2]): its "
                                  "coordinates and what the frame shows of it")
        for key, a in coords.items():
            ds = b.create_dataset(key, data=np.array(a))
            ds.attrs["units"] = _BODY_UNITS.get(key, "1")
            if key in _BODY_DESCRIPTIONS:
                ds.attrs["description"] = _BODY_DESCRIPTIONS[key]


def _write_photogate(f, scene: Scene, traj: Trajectory) -> None:
    from stand.instruments.photogate import gate_passes, pulse_counter_period, screen_coordinate
    from stand.instruments.timing import shaft_velocity

    gate = scene.instruments["photogate"]
    screen = scene.instruments.get("screen") or next(iter(screens(scene.instruments).values()), None)
    traj, plane, _ = plane_view(traj, scene, gate)
    gain = getattr(screen, "gain", 1.0)  # the gate sits on the screen: the camera's optical gain
    vx, vy = shaft_velocity(traj)
    X, dX = screen_coordinate(gain * traj.x, gain * traj.y, gain * vx, gain * vy, gate)
    passes = gate_passes(traj.t, X, dX, gate)
    g = f.require_group("instruments/photogate")
    g.attrs["settings"] = _settings_json(gate)
    g.attrs["gain"] = float(gain)
    if scene.kind == "rotor":
        _place_attrs(g, plane, gate)
    if screen is None:
        g.attrs["gain_note"] = "no [instruments.screen]: spot displacement = shaft displacement (gain 1)"
    for key in ("enter", "leave", "centre"):
        if hasattr(passes, key):
            ds = g.create_dataset(f"{key}_time", data=np.asarray(getattr(passes, key)))
            ds.attrs["units"] = "s"
    try:
        trig = np.asarray(getattr(passes, "enter" if getattr(gate, "trigger", "enter") == "enter"
                                  else "centre"))
        g.attrs["period_s"] = float(pulse_counter_period(trig, getattr(gate, "start_pass", 1),
                                                         getattr(gate, "stop_pass", 3)))
    except ValueError as exc:
        g.attrs["period_s"] = float("nan")
        g.attrs["note"] = str(exc)


def _write_truth(f, scene: Scene, traj: Trajectory) -> None:
    t = f.require_group("truth")
    psi = traj.residual_unbalance()
    ds = t.create_dataset("residual_unbalance", data=np.column_stack([psi.real, psi.imag]))
    ds.attrs["units"] = "kg*m"
    ds.attrs["description"] = ("total unbalance rotor + weights in the rotor frame (x along the "
                               "reference mark), on the recording's time grid")
    ds = t.create_dataset("capacity", data=scene_capacity(scene))
    ds.attrs["units"] = "kg*m"
    ds.attrs["description"] = ("balancing capacity of the main plane: sum m l of the balls / "
                               "pendulums plus the body weights' capacities")
