"""What the instruments output (``run.instruments``) stored into the recording being written
(:func:`stand.recording.write.write_recording`): ``instruments/<name>/...`` (frames, times,
readings; the settings as JSON attrs, SI units) and ``truth/<name>/...`` (the ground truth
for scoring identification; per body weight ``truth/stroboscope/<name>/<coordinate>``), the
names of :mod:`stand.recording.layout`.  Frames are rendered and written one at a time."""
from __future__ import annotations

import dataclasses
import json

import numpy as np

from stand.instruments.outputs import (MAX_STROBE_FRAMES, InstrumentOutputs, ReadingsOutput,
                                       ScreenOutput, StroboscopeOutput, flash_tables)
from stand.instruments.pipeline import settings_dict
from stand.scene.placement import placement_of
from stand.recording.layout import PHOTOGATE, STROBOSCOPE, instrument_key, truth_key

__all__ = ["write_outputs", "estimated_bytes"]

FRAME_COMPRESSION = {"compression": "gzip", "compression_opts": 1, "shuffle": True}


def estimated_bytes(outputs) -> float:
    """An upper bound of what ``outputs`` store (16-bit frames, uncompressed) [bytes], so that
    the recording writer knows whether it may assemble the file in memory."""
    if not isinstance(outputs, InstrumentOutputs):
        return 0
    frames = sum((len(p[1]) + 1) * 2 * p[0].width * p[0].height for p in outputs.plans.values())
    strobe = MAX_STROBE_FRAMES * 2 * 1024 * 1024 if STROBOSCOPE in outputs.scene.instruments else 0
    return frames + strobe + 64 * np.size(outputs.traj.t) * 8


def _settings_json(settings) -> str:
    return json.dumps(settings_dict(settings))


def _place_attrs(g, plane: str, settings, names=None) -> None:
    """Where the instrument looks, stored with its output."""
    g.attrs["plane"] = plane
    p = placement_of(settings)
    if p.axial_position is not None:
        g.attrs["axial_position_m"] = float(p.axial_position)
    if names and any(k != v for k, v in names.items()):
        g.attrs["weight_names_in_run"] = json.dumps(names)


def write_outputs(f, outputs: InstrumentOutputs) -> None:
    """Store ``outputs`` (``run.instruments``) and the run's truth into the open file ``f``."""
    scene = outputs.scene
    for name in outputs:
        out = outputs[name]
        if isinstance(out, ScreenOutput):
            _write_screen(f, scene, out)
        elif isinstance(out, StroboscopeOutput):
            _write_strobe(f, scene, out)
        elif name == PHOTOGATE:
            _write_photogate(f, scene, out)
        else:
            _write_readings(f, scene, out)
    _write_truth(f, scene, outputs.traj)


def _write_dict(g, d: dict, units: dict) -> None:
    for k, v in d.items():
        a = np.asarray(v)
        if a.dtype == object:
            continue
        ds = g.create_dataset(k, data=a)
        if k in units:
            ds.attrs["units"] = units[k]


def _write_readings(f, scene, out: ReadingsOutput) -> None:
    """Keyphasor, tachometer, probes: their readings and settings (probes: their plane)."""
    g = f.require_group(instrument_key(out.name))
    g.attrs["settings"] = _settings_json(out.settings)
    if out.name == "probes" and scene.kind == "rotor":
        _place_attrs(g, out.plane, out.settings)
    _write_dict(g, out.readings, out.units)


def _write_screen(f, scene, out: ScreenOutput) -> None:
    cam, name = out.settings, out.name
    g = f.require_group(instrument_key(name))
    g.attrs["settings"] = _settings_json(cam.to_attrs() if hasattr(cam, "to_attrs") else cam)
    g.attrs["description"] = ("camera filming the laser spot on the screen: frames (row = image "
                              "row, column = image column), exposure start times")
    ds = g.create_dataset("frame_time", data=out.readings["frame_time"])
    ds.attrs["units"] = "s"
    ds.attrs["description"] = "start of each frame's exposure"
    ds = g.create_dataset("frame_rotor_angle", data=out.readings["frame_rotor_angle"])
    ds.attrs["units"] = "rad"
    ds.attrs["description"] = "rotor angle (reference mark) at the first exposure sub-sample"
    g.attrs["exposure_s"] = float(cam.exposure)
    if scene.kind == "rotor":
        _place_attrs(g, out.plane, cam)
        g.attrs["plane_description"] = ("the spot shows this plane's fixed-frame translation "
                                        "(planes/<plane> of the run; axis@<d>m: the point of "
                                        "the shaft axis at axial distance d) times the gain")
    frames = g.create_dataset("frames", shape=(out.n_frames, cam.height, cam.width), dtype=cam.dtype,
                              chunks=(1, cam.height, cam.width), **FRAME_COMPRESSION)
    frames.attrs["units"] = "DN"
    for i, img in enumerate(out.frames()):
        frames[i] = img
    rings = out.rings   # calibration rings at the test (operating) speed: zones i S/16, i = 0..20
    if rings is not None:
        g.attrs["ring_test_speed_rad_s"] = rings["test_speed"]
        ds = g.create_dataset("ring_radius", data=rings["radius"])
        ds.attrs["units"] = "m"
        ds.attrs["description"] = "zone i boundary: steady spot radius for unbalance i*S/16 at the test speed"
        g.create_dataset("calibration_image", data=out.calibration_image(rings["radius"]),
                         **FRAME_COMPRESSION)
        if rings["warning"] is not None:
            g.attrs["warning"] = rings["warning"]
    t = f.require_group(truth_key(name))
    for key in ("centre_px", "centre_m", "in_frame", "exposure_time", "brightness", "frame_index"):
        ds = t.create_dataset(key, data=out.truth[key])
        ds.attrs["units"] = out.units[key]


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


def _write_strobe(f, scene, out: StroboscopeOutput) -> None:
    strobe = out.settings
    g = f.require_group(instrument_key(STROBOSCOPE))
    g.attrs["settings"] = _settings_json(strobe)
    g.attrs["description"] = "frames lit by the slot once per revolution; flash times per frame"
    g.attrs["weights"] = json.dumps(out.weights)
    if out.scene.kind == "rotor":
        _place_attrs(g, out.plane, strobe, out.names)
    g.attrs["weights_description"] = ("what the frames show of each weight (JSON list): balls "
                                      "and pendulums on their track; body weights as a bob on a "
                                      "rod from the pivot (drawn = pendulum) or a liquid's "
                                      "crescent (drawn = crescent); lengths in m and px")
    if out.note is not None:
        g.attrs["note"] = out.note
        return
    g.attrs["t_start_s"] = out.t_start
    g.attrs["t_start_rule"] = "first sample with the rotor above 10 % of its largest speed"
    frames = None
    kept = []
    for i, fr in enumerate(out.rendered()):
        if frames is None:
            frames = g.create_dataset("frames", shape=(0,) + fr.image.shape,
                                      maxshape=(None,) + fr.image.shape, dtype=fr.image.dtype,
                                      chunks=(1,) + fr.image.shape, **FRAME_COMPRESSION)
        frames.resize(i + 1, axis=0)
        frames[i] = fr.image
        frames.attrs["units"] = "DN"
        kept.append(dataclasses.replace(fr, image=None))   # the truth, not the image
    readings, truth = flash_tables(kept)
    g.attrs["frames_limit"] = MAX_STROBE_FRAMES
    g.attrs["truncated"] = bool(len(kept) >= MAX_STROBE_FRAMES)
    for key in ("flash_time", "flash_rotor_angle"):
        if key in readings:
            ds = g.create_dataset(key, data=readings[key])
            ds.attrs["units"] = out.units[key]
    t = f.require_group(truth_key(STROBOSCOPE))
    if "relative_angle" in truth:
        ds = t.create_dataset("relative_angle", data=truth["relative_angle"])
        ds.attrs["units"] = "rad"
        ds.attrs["description"] = ("balls / pendulums: angle from the reference mark at each "
                                   "flash (frame, flash, weight)")
    if "centre_px" in truth:
        ds = t.create_dataset("centre_px", data=truth["centre_px"])
        ds.attrs["units"] = "px"
        ds.attrs["description"] = "drawn rotor centre (shaft point) at each flash (column, row)"
    for name, coords in truth.get("bodies", {}).items():
        b = t.require_group(name)
        b.attrs["description"] = (f"body weight {name} at each flash (frame, flash[, 2]): its "
                                  "coordinates and what the frame shows of it")
        for key, a in coords.items():
            ds = b.create_dataset(key, data=a)
            ds.attrs["units"] = _BODY_UNITS.get(key, "1")
            if key in _BODY_DESCRIPTIONS:
                ds.attrs["description"] = _BODY_DESCRIPTIONS[key]


def _write_photogate(f, scene, out: ReadingsOutput) -> None:
    g = f.require_group(instrument_key(PHOTOGATE))
    g.attrs["settings"] = _settings_json(out.settings)
    g.attrs["gain"] = out.attrs["gain"]
    if scene.kind == "rotor":
        _place_attrs(g, out.plane, out.settings)
    if "gain_note" in out.attrs:
        g.attrs["gain_note"] = out.attrs["gain_note"]
    for key, a in out.readings.items():
        ds = g.create_dataset(key, data=a)
        ds.attrs["units"] = "s"
    g.attrs["period_s"] = out.attrs["period_s"]
    if "note" in out.attrs:
        g.attrs["note"] = out.attrs["note"]


def _write_truth(f, scene, traj) -> None:
    t = f.require_group(truth_key())
    psi = traj.residual_unbalance()
    ds = t.create_dataset("residual_unbalance", data=np.column_stack([psi.real, psi.imag]))
    ds.attrs["units"] = "kg*m"
    ds.attrs["description"] = ("static residual unbalance: the vector sum over all planes of the "
                               "rotor's unbalances and the weights' static moments, in the rotor "
                               "frame (x along the reference mark), on the recording's time grid")
    ds = t.create_dataset("capacity", data=scene.weights_capacity(scene.main_plane))
    ds.attrs["units"] = "kg*m"
    ds.attrs["description"] = ("balancing capacity of the main plane: sum m l of the balls / "
                               "pendulums plus the body weights' capacities")
