"""What a run's instruments output, in memory: ``run.instruments`` (issue 29, item 5).

:func:`stand.run` on a scene with ``[instruments.*]`` tables returns a Run whose
``instruments`` maps each instrument's name to its output, computed when first asked for
and rendered frame by frame on demand; nothing is written until ``stand.save(run, path)``,
which stores these same outputs (:mod:`stand.recording.write_instruments`)::

    run = stand.run(stand.load("data_samples/scenes/stand_cameras.toml"))
    screen = run.instruments["screen"]
    screen.n_frames, screen.times        # frames, their exposure start times [s]
    img = screen.frame(10)               # (height, width) image [DN], rendered now
    run.instruments["tachometer"].to_frame()   # the readings, one row per reading

Every output has ``name``, ``settings``, ``plane`` (the plane the instrument looks at),
``n_frames``, ``times`` [s], ``frame(i)``, ``readings`` (dict of arrays, the recording's
dataset names), ``units`` (dataset name -> units), ``truth`` (what the instrument cannot see)
and ``to_frame()`` (a pandas DataFrame, units in the column names as :meth:`Run.to_frame`).
Cameras (screens, stroboscope) have frames; the reading instruments (photo-gate, keyphasor,
tachometer, probes) have ``n_frames == 0`` and their readings.

A screen frame ``i`` is the frame ``i`` of the recording (each frame's noise comes from its
own random stream, :func:`stand.instruments.render.frame_seed`).  The stroboscope's noise is
one stream over the whole sequence: its frames (at most :data:`MAX_STROBE_FRAMES`) are
rendered together when first asked for and kept.
"""
from __future__ import annotations

import dataclasses
import functools
import itertools
import math
from collections.abc import Mapping
from typing import Optional

import numpy as np

from stand.integrate.result import column_unit
from stand.scene.placement import instrument_plane, placement_of, screens, with_axis_planes

__all__ = ["InstrumentOutputs", "InstrumentOutput", "ScreenOutput", "StroboscopeOutput",
           "ReadingsOutput", "PhotogateOutput", "MAX_STROBE_FRAMES", "plane_view", "screen_plans"]

#: at most this many stroboscope frames per recording (one flash per revolution adds up)
MAX_STROBE_FRAMES = 200


def plane_view(traj, scene, settings):
    """``(view, plane, names)``: the run as the instrument ``settings`` sees it.

    Planar scenes: the run itself (one plane).  Rotor-family scenes: the run whose
    main plane is the instrument's plane (:func:`stand.scene.placement.instrument_plane`)
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


def _screen_plan(scene, name: str = "screen"):
    from stand.instruments.screen import exposure_times, frame_times

    cam = scene.instruments[name]
    starts = frame_times(scene.run.duration, cam)
    times = exposure_times(starts, cam, max_rotor_speed=scene.top_speed)
    return cam, starts, times


def screen_plans(scene):
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


class InstrumentOutput:
    """What one instrument outputs (module docstring); the base of the cameras and readers."""

    n_frames = 0

    def __init__(self, name: str, settings, plane: str):
        self.name = name
        self.settings = settings
        self.plane = plane
        self.readings: dict = {}
        self.units: dict = {}
        self.truth: dict = {}

    @property
    def times(self) -> np.ndarray:
        """Time of each frame or reading [s]."""
        return np.asarray(self.readings.get("time", np.zeros(0)))

    def frame(self, i: int) -> np.ndarray:
        """Image ``i`` (negative counts from the end).  Raises IndexError outside the frames."""
        raise IndexError(f"instrument {self.name!r} records readings, not frames")

    def _table_keys(self):
        """The readings that may be columns of :meth:`to_frame`."""
        return list(self.readings)

    def _index(self, i: int) -> int:
        n = self.n_frames
        if not -n <= i < n:
            raise IndexError(f"instrument {self.name!r}: frame {i} of {n}")
        return int(i) % n

    def _columns(self) -> dict:
        """``{column: array}`` of the table: every reading with one row per time."""
        cols = {}
        n = self.times.shape[0]
        for key in self._table_keys():
            a = np.asarray(self.readings[key])
            if a.dtype == object or a.ndim == 0 or a.shape[0] != n:
                continue
            u = column_unit(self.units.get(key, "1"))
            if a.ndim == 1:
                cols[f"{key}_{u}"] = a
            else:
                for j in range(int(np.prod(a.shape[1:]))):
                    cols[f"{key}{j + 1}_{u}"] = a.reshape(n, -1)[:, j]
        return cols

    def to_frame(self):
        """The readings as a pandas DataFrame, one row per time, units in the column names
        (``time_s``, ``speed_rad_s``; a reading per probe: ``signal1_m``, ``signal2_m``)."""
        import pandas as pd

        return pd.DataFrame(self._columns())

    def _describe(self) -> str:
        return f"readings={list(self.readings)}"

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, plane={self.plane!r}, {self._describe()})"


def _rolling_rows(ex, times, cam, v_px):
    """A rolling shutter's spot: a function of exposure sub-sample times (f, K) [s] giving px
    (f, H, K, 2) at each row's times (those plus row x ``cam.line_time``: called per chunk of
    frames, so no (F, H, K, 2) array is held), and ``(screen_m, px)`` (F, K, 2) at the times of
    each frame's spot row (from ``v_px``, iterated to the row the spot is in at those times;
    converges while the spot moves less than a row per line time), and those times (F, K)."""
    from scipy.interpolate import CubicSpline

    from stand.instruments.screen import spot_positions
    from stand.instruments.timing import sample_trajectory, shaft_velocity

    try:                      # cubic Hermite with the state's velocities (as the probes)
        vel = shaft_velocity(ex)

        def at(T):            # the last frame's late rows: held at the run's end
            s = sample_trajectory(ex, np.clip(T, ex.t[0], ex.t[-1]).ravel(), vel)
            return spot_positions(*(a.reshape(T.shape) for a in (s.x, s.y, s.rotor_angle)), cam)
    except ValueError:        # a view without the state: a cubic spline through the samples
        splines = [CubicSpline(ex.t, a) for a in (ex.x, ex.y, np.unwrap(ex.rotor_angle))]
        at = lambda T: spot_positions(*(s(T) for s in splines), cam)  # noqa: E731
    rows = lambda T: at(T[:, None, :] + cam.line_time * np.arange(cam.height)[None, :, None])[1]  # noqa: E731
    for _ in range(8):        # the fixed point v = v(t + v line_time): the spot's own row
        T = times + cam.line_time * np.clip(v_px, 0, cam.height - 1)[:, None]
        spot = at(T)
        v_px = spot[1][..., 1].mean(axis=1)
    return rows, spot, T


class ScreenOutput(InstrumentOutput):
    """A screen camera's frames (the laser spot) and their truth (spot centre).

    Attributes
    ----------
    readings : dict
        ``frame_time`` (F,) exposure starts [s], ``frame_rotor_angle`` (F,) rotor angle at
        the first exposure sub-sample [rad].
    truth : dict
        ``centre_px`` (F, 2) [px], ``centre_m`` (F, 2) [m], ``in_frame`` (F,), the spot's
        exposure-averaged centre; ``exposure_time`` (F, K) [s]; ``brightness`` (F,) the
        flicker's gain times the auto-exposure's; ``frame_index`` (F,) each frame's place
        before the drops.
    px : ndarray (F, K, 2)
        Spot centre at each exposure sub-sample [px] (what the frames are drawn from).
    """

    def __init__(self, name: str, scene, traj, plan):
        from stand.instruments.screen import frame_truth, spot_positions
        from vision.camera_artefacts import auto_gain, flicker_gain

        cam, starts, times, index = plan
        ex, plane, _ = plane_view(traj.extra, scene, cam)
        super().__init__(name, cam, plane)
        K = times.shape[1]
        # a run that stopped early renders the frames it has
        n_ok = int(np.count_nonzero(np.all(index < ex.t.size, axis=1)))
        shape = (n_ok, K)
        sl = index[:n_ok].ravel()
        screen_m, self.px = spot_positions(ex.x[sl].reshape(shape), ex.y[sl].reshape(shape),
                                           ex.rotor_angle[sl].reshape(shape), cam)
        truth = frame_truth(screen_m, self.px, cam)
        self.readings = {"frame_time": starts[:n_ok],
                         "frame_rotor_angle": ex.rotor_angle[sl].reshape(shape)[:, 0]}
        self.units = {"frame_time": "s", "frame_rotor_angle": "rad", "centre_px": "px",
                      "centre_m": "m", "in_frame": "1", "exposure_time": "s"}
        self.truth = {key: np.asarray(truth[key])[:n_ok] for key in ("centre_px", "centre_m",
                                                                     "in_frame")}
        self.truth["exposure_time"] = times[:n_ok]
        self._rows, self._row_times = None, times[:n_ok]
        if cam.line_time > 0:        # rolling shutter: the truth is the spot at its own row's times
            self._rows, spot, self.truth["exposure_time"] = _rolling_rows(
                ex, times[:n_ok], cam, self.truth["centre_px"][:, 1])
            self.truth.update({k: np.asarray(v) for k, v in frame_truth(*spot, cam).items()
                               if k in ("centre_px", "centre_m", "in_frame")})
        # the lamps' flicker at each mid-exposure; the frames the camera lost (the kept ones
        # keep their timestamps; the truth keeps each kept frame's index in the full sequence)
        light = flicker_gain(starts[:n_ok] + 0.5 * cam.exposure, cam.mains_frequency,
                             cam.flicker_depth)         # times the auto-exposure's gain
        self.truth["brightness"] = light * auto_gain(light, cam.frame_period, cam.auto_gain_time,
                                                     cam.auto_gain_target and cam.auto_gain_target / cam.background)
        self.truth["frame_index"] = np.arange(n_ok)
        if cam.drop_rate > 0:
            keep = np.random.default_rng([cam.seed, 0xD809]).random(n_ok) >= cam.drop_rate
            self.px = self.px[keep]
            self._row_times = self._row_times[keep]
            for d in (self.readings, self.truth):
                d.update({k: np.asarray(a)[keep] for k, a in d.items()})
        self.units.update(brightness="1", frame_index="1")
        self._scene = scene

    @property
    def n_frames(self) -> int:
        return int(self.px.shape[0])

    def _describe(self) -> str:
        return f"frames={self.n_frames}"

    @property
    def times(self) -> np.ndarray:
        """Start of each frame's exposure [s]."""
        return self.readings["frame_time"]

    def frame(self, i: int) -> np.ndarray:
        """Frame ``i`` (height, width) [DN], rendered now (after H.264: the sequence up to it)."""
        from stand.instruments.render import render_frames

        i = self._index(i)
        if self.settings.h264_qp is not None:
            return next(itertools.islice(self.frames(), i, None))
        return next(render_frames(self.px[i:i + 1], self.settings, first_index=i,
                                  gains=self.truth["brightness"][i:i + 1], rows=self.rows(i, i + 1)))

    def rows(self, i0: int, i1: int):
        """Frames i0..i1-1's spot px (., H, K, 2) at each row's times (None: global shutter)."""
        return None if self._rows is None else self._rows(self._row_times[i0:i1])

    def frames(self, chunk: int = 32):
        """Every frame in order, rendered one at a time (a generator; a rolling shutter's rows
        computed ``chunk`` frames at a time, so memory stays bounded; then H.264 if set)."""
        from stand.instruments.render import h264_frames, render_frames

        out = (f for i in range(0, self.n_frames, chunk)
               for f in render_frames(self.px[i:i + chunk], self.settings, first_index=i,
                                      gains=self.truth["brightness"][i:i + chunk], rows=self.rows(i, i + chunk)))
        return out if self.settings.h264_qp is None else h264_frames(out, self.settings)

    @functools.cached_property
    def rings(self) -> Optional[dict]:
        """Calibration rings at the test (operating) speed, zones i S/16, i = 0..20:
        ``{"test_speed": rad/s, "radius": (21,) m, "warning": str or None}``; None when the
        scene has no balancing capacity or no speed."""
        from stand.instruments.rings import check_spot_size, ring_radii

        test_speed = self._scene.top_speed
        if not (self._scene.weights_capacity(self._scene.main_plane) > 0 and test_speed > 0):
            return None
        radii = ring_radii(self._scene, speed=test_speed, cam=self.settings, plane=self.plane)
        try:
            check_spot_size(self.settings, radii)
            warning = None
        except ValueError as exc:  # a warning for the user, kept with the data
            warning = str(exc)
        return {"test_speed": test_speed, "radius": radii, "warning": warning}

    def calibration_image(self, radii=None) -> np.ndarray:
        """The rings drawn as the camera sees them (height, width) [DN]."""
        from stand.instruments.rings import render_ring_image

        return render_ring_image(self.rings["radius"] if radii is None else radii, self.settings)

    def _columns(self) -> dict:
        cols = {"time_s": self.times, "rotor_angle_rad": self.readings["frame_rotor_angle"]}
        c_px, c_m = self.truth["centre_px"], self.truth["centre_m"]
        cols.update({"centre_u_px": c_px[:, 0], "centre_v_px": c_px[:, 1],
                     "centre_x_m": c_m[:, 0], "centre_y_m": c_m[:, 1],
                     "in_frame": self.truth["in_frame"]})
        return cols


class StroboscopeOutput(InstrumentOutput):
    """The stroboscope's frames (lit once per revolution) and, per frame, its flashes.

    ``t_start`` [s]: the first sample with the rotor above 10 % of its largest speed;
    ``note``: why there are no frames (the rotor does not complete a revolution), else None.
    ``weights``: what the frames show of each weight (JSON-able list).  ``readings``:
    ``flash_time`` and ``flash_rotor_angle`` (frame, flash); ``truth``: ``relative_angle``
    (frame, flash, weight), ``centre_px`` (frame, flash, 2) and per body weight its
    coordinates (``truth["bodies"]``).
    """

    def __init__(self, scene, traj):
        from stand.instruments.strobe_render import drawn_weights

        strobe = scene.instruments["stroboscope"]
        view, plane, self.names = plane_view(traj, scene, strobe)
        super().__init__("stroboscope", strobe, plane)
        self.view = view
        self.scene = getattr(view, "scene", None) or scene
        speed = np.abs(view.rotor_speed)
        moving = np.nonzero(speed > 0.1 * max(float(np.max(speed)), 1e-12))[0]
        self.t_start = float(view.t[moving[0]]) if moving.size else None
        self.weights = drawn_weights(self.scene, strobe)
        self.note = None
        if self.t_start is None or float(np.max(speed)) * (view.t[-1] - self.t_start) < 2 * math.pi:
            self.note = "the rotor does not complete a revolution: no flashes, no frames"
        self._frames: Optional[list] = None
        self.units = {"flash_time": "s", "flash_rotor_angle": "rad", "relative_angle": "rad",
                      "centre_px": "px"}

    def rendered(self):
        """The frames (:class:`stand.instruments.strobe_render.StrobeFrame`), one at a time:
        the kept ones, or rendered now (a generator; kept by :meth:`frame` and friends)."""
        if self._frames is not None:
            return iter(self._frames)
        if self.note is not None:
            return iter(())
        from stand.instruments.strobe_render import render_strobe_frames

        return render_strobe_frames(self.view, self.settings, t_start=self.t_start,
                                    max_frames=MAX_STROBE_FRAMES)

    def _all(self) -> list:
        if self._frames is None:
            self._frames = list(self.rendered())
            self._readings, self._truth = flash_tables(self._frames)
        return self._frames

    @property
    def readings(self) -> dict:
        """``flash_time`` [s] and ``flash_rotor_angle`` [rad] (frame, flash) (renders the frames)."""
        self._all()
        return self._readings

    @readings.setter
    def readings(self, value: dict) -> None:
        self._readings = value

    @property
    def truth(self) -> dict:
        """``relative_angle``, ``centre_px``, ``bodies`` (class docstring; renders the frames)."""
        self._all()
        return self._truth

    @truth.setter
    def truth(self, value: dict) -> None:
        self._truth = value

    @property
    def n_frames(self) -> int:
        return len(self._all())

    def _describe(self) -> str:
        return (f"frames={len(self._frames)}" if self._frames is not None
                else "frames not rendered yet" if self.note is None else "no frames")

    @property
    def times(self) -> np.ndarray:
        """Time of each frame: its first flash [s]."""
        return np.array([fr.time for fr in self._all()])

    def frame(self, i: int) -> np.ndarray:
        """Frame ``i`` (height, width) [DN] (all frames are rendered on the first call)."""
        frames = self._all()
        return frames[self._index(i)].image

    def _columns(self) -> dict:
        self._all()
        cols = {"time_s": self.times}
        if self.n_frames:
            cols["rotor_angle_rad"] = self.readings["flash_rotor_angle"][:, 0]
            rel = self.truth.get("relative_angle")
            for j in range(0 if rel is None else rel.shape[2]):
                cols[f"relative_angle{j + 1}_rad"] = rel[:, 0, j]
        return cols


def flash_tables(frames) -> tuple:
    """``(readings, truth)`` of stroboscope frames, stacked (frame, flash, ...): the flash
    times and rotor angles; the weights' relative angles, the drawn centre, the bodies."""
    times, rel, rot, centre = [], [], [], []
    bodies: dict = {}
    for fr in frames:
        times.append(fr.t)
        rel.append(fr.relative_angle)
        rot.append(fr.rotor_angle)
        centre.append(fr.centre_px)
        for name, coords in fr.bodies.items():
            for key, a in coords.items():
                bodies.setdefault(name, {}).setdefault(key, []).append(a)
    if not times:
        return {}, {}
    readings = {"flash_time": np.array(times).reshape(len(times), -1),
                "flash_rotor_angle": np.array(rot).reshape(len(rot), -1)}
    truth: dict = {}
    n = int(np.shape(rel[0])[-1]) if rel else 0
    if n:
        truth["relative_angle"] = np.array(rel).reshape(len(rel), -1, n)
    if centre:
        truth["centre_px"] = np.array(centre).reshape(len(centre), -1, 2)
    truth["bodies"] = {name: {key: np.array(a) for key, a in coords.items()}
                       for name, coords in bodies.items()}
    return readings, truth


class ReadingsOutput(InstrumentOutput):
    """A reading instrument's output: ``readings`` (arrays by their recording names) and
    ``units``; ``attrs`` holds what it says of itself (the photo-gate's period).

    ``time_key`` names the reading that gives :attr:`times`; ``columns`` the readings with one
    row per time (the table of :meth:`to_frame`; default all of them).
    """

    def __init__(self, name: str, settings, plane: str, readings: dict, units: dict,
                 attrs: Optional[dict] = None, time_key: str = "time", columns=None):
        super().__init__(name, settings, plane)
        self.readings = readings
        self.units = units
        self.attrs = dict(attrs or {})
        self.time_key = time_key
        self.columns = tuple(readings if columns is None else columns)

    @property
    def times(self) -> np.ndarray:
        """Time of each reading [s] (``readings[time_key]``)."""
        return np.asarray(self.readings.get(self.time_key, np.zeros(0)))

    def _table_keys(self):
        return [k for k in self.columns if k in self.readings]


class PhotogateOutput(ReadingsOutput):
    """The photo-gate: the spot's passes (``enter_time``, ``leave_time``, ``centre_time``
    [s]); ``times``: the pulses the counter receives; ``attrs["period_s"]``: the counter's
    period.  :meth:`to_frame`: one row per event (``time_s``, ``event``), in time order."""

    def _columns(self) -> dict:
        ev = [(float(t), key[:-len("_time")]) for key in ("enter_time", "leave_time", "centre_time")
              if key in self.readings for t in self.readings[key]]
        ev.sort()
        return {"time_s": np.array([e[0] for e in ev]), "event": [e[1] for e in ev]}


def _keyphasor(scene, traj) -> ReadingsOutput:
    from stand.instruments.probes import keyphasor_pulses

    kp = scene.instruments["keyphasor"]
    return ReadingsOutput("keyphasor", kp, instrument_plane(scene, kp),
                          {"pulse_time": keyphasor_pulses(traj, kp)}, {"pulse_time": "s"},
                          time_key="pulse_time")


def _tachometer(scene, traj) -> ReadingsOutput:
    from stand.instruments.probes import tachometer_readings

    tach = scene.instruments["tachometer"]
    return ReadingsOutput("tachometer", tach, instrument_plane(scene, tach),
                          tachometer_readings(traj, tach),
                          {"time": "s", "speed": "rad/s", "counts": "1", "true_speed": "rad/s",
                           "true_speed_at_time": "rad/s"})


def _probes(scene, traj) -> ReadingsOutput:
    from stand.instruments.probes import probe_signals

    probes = scene.instruments["probes"]
    view, plane, _ = plane_view(traj, scene, probes)
    return ReadingsOutput("probes", probes, plane, probe_signals(view, probes),
                          {"time": "s", "signal": "m", "displacement": "m", "runout": "m",
                           "noise": "m", "rotor_angle": "rad", "angles": "rad"},
                          columns=("time", "signal", "displacement", "runout", "noise",
                                   "rotor_angle"))


def _photogate(scene, traj) -> ReadingsOutput:
    from stand.instruments.photogate import gate_passes, pulse_counter_period, screen_coordinate
    from stand.instruments.timing import shaft_velocity

    gate = scene.instruments["photogate"]
    screen = scene.instruments.get("screen") or next(iter(screens(scene.instruments).values()), None)
    view, plane, _ = plane_view(traj, scene, gate)
    gain = getattr(screen, "gain", 1.0)  # the gate sits on the screen: the camera's optical gain
    vx, vy = shaft_velocity(view)
    X, dX = screen_coordinate(gain * view.x, gain * view.y, gain * vx, gain * vy, gate)
    passes = gate_passes(view.t, X, dX, gate)
    readings = {f"{key}_time": np.asarray(getattr(passes, key))
                for key in ("enter", "leave", "centre") if hasattr(passes, key)}
    attrs: dict = {"gain": float(gain)}
    if screen is None:
        attrs["gain_note"] = "no [instruments.screen]: spot displacement = shaft displacement (gain 1)"
    try:
        trig = np.asarray(getattr(passes, "enter" if getattr(gate, "trigger", "enter") == "enter"
                                  else "centre"))
        attrs["period_s"] = float(pulse_counter_period(trig, getattr(gate, "start_pass", 1),
                                                       getattr(gate, "stop_pass", 3)))
    except ValueError as exc:
        attrs["period_s"] = float("nan")
        attrs["note"] = str(exc)
    trigger = "enter_time" if getattr(gate, "trigger", "enter") == "enter" else "centre_time"
    return PhotogateOutput("photogate", gate, plane, readings, dict.fromkeys(readings, "s"), attrs,
                           time_key=trigger)


#: the reading instruments, in the order they are stored
READERS = {"photogate": _photogate, "keyphasor": _keyphasor, "tachometer": _tachometer,
           "probes": _probes}


class InstrumentOutputs(Mapping):
    """``run.instruments``: instrument name -> its output (module docstring), each computed
    when first asked for; :func:`stand.recording.write.write_recording` stores them all."""

    def __init__(self, scene, traj, plans: Optional[dict] = None):
        if scene.kind == "rotor" and any(placement_of(s).axial_position is not None
                                         for s in scene.instruments.values()):
            scene = with_axis_planes(scene)   # (idempotent: the run's scene already has them)
        self.scene = scene
        self.traj = traj
        self.plans = screen_plans(scene)[0] if plans is None else plans
        inst = scene.instruments
        self._names = list(self.plans) + [n for n in ("stroboscope", *READERS) if n in inst]
        self._cache: dict = {}

    def __getitem__(self, name: str) -> InstrumentOutput:
        if name not in self._cache:
            if name in self.plans:
                out = ScreenOutput(name, self.scene, self.traj, self.plans[name])
            elif name == "stroboscope" and name in self._names:
                out = StroboscopeOutput(self.scene, self.traj)
            elif name in READERS and name in self._names:
                out = READERS[name](self.scene, self.traj)
            else:
                raise KeyError(f"{name!r}: the scene's instruments are {', '.join(self._names)}")
            self._cache[name] = out
        return self._cache[name]

    def __iter__(self):
        return iter(self._names)

    def __len__(self) -> int:
        return len(self._names)

    def __repr__(self) -> str:
        return f"InstrumentOutputs({', '.join(self._names)})"
