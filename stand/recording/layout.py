"""The one HDF5 layout of a recording: its dataset names, units and root attributes.

Layout (format_version 2; all arrays float64, SI units, one row per sample)::

    /time                          (N,)   s      sample times (an HDF5 dimension scale)
    /planes/<plane>/x, .../y       (N,)   m      fixed-frame translation of each plane
    /shaft/x, /shaft/y             (N,)   m      links to the main (instrumented or only) plane
    /rotor/angle, /rotor/speed     (N,)   rad, rad/s
    /weights/<weight>/<coord>      (N,)          each weight's coordinates (ball1/angle [rad], ...)
    /coordinates/...               (N,)          structure coordinates, a book model's state
    /truth/residual/<plane>        (N, 2) kg*m   a plane's own unbalance, rotor frame: the rotor's
                                                 unbalances listed in it + its weights and bodies
                                                 (rotors of the family; the static residual is
                                                 their sum, stand.integrate.residual)
    /truth/residual_unbalance      (N, 2) kg*m   static residual (sum over all planes), with
                                                 instruments (older files: the main plane's)
    /instruments/<name>/...                      what the instruments output (stand.instruments)
    /truth/<name>/...                            their ground truth

Every dataset carries ``units`` and ``description``; every (N, ...) dataset
has ``time`` attached as its first dimension's scale, so h5py, h5netcdf and
xarray users see the time axis.  Root attributes: ``format`` =
:data:`FORMAT`, ``format_version``, ``version`` (``stand.__version__``),
``created`` (ISO 8601, UTC), ``scene_name``, ``scene`` (the scene's TOML
text), ``scene_language`` (the scene-file language of that text,
:data:`stand.scene.model.SCENE_LANGUAGE`; files without it were written in language 1,
whose ``[structure]`` angles are in rad: :func:`scene_language`), ``structure``
(:attr:`stand.scene.model.Scene.structure_type`),
``main_plane``, ``weight_planes`` (JSON: weight -> plane), ``solver`` (JSON of
:class:`stand.integrate.result.SolverStats`), plus any ``extra_attrs``.

Written by :mod:`.write`, read by :mod:`.read`; :mod:`.hdf5` gathers the public names.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from stand.scene.model import SCENE_LANGUAGE

__all__ = ["FORMAT", "FORMAT_VERSION", "DATASETS", "REQUIRED", "RESERVED_ATTRS", "V1_WEIGHTS",
           "RecordingError", "decode_attr", "scene_language", "SCENE_LANGUAGE", "INSTRUMENTS",
           "TRUTH", "SCREEN", "STROBOSCOPE", "PHOTOGATE", "KEYPHASOR", "TACHOMETER", "PROBES",
           "instrument_key", "truth_key", "screen_group"]

FORMAT = "autobalancer-stand recording"
FORMAT_VERSION = 2
#: the fixed datasets: path -> (Recording field, units, description)
DATASETS = {
    "time": ("t", "s", "sample time"),
    "shaft/x": ("x", "m", "main plane's translation along the fixed X axis"),
    "shaft/y": ("y", "m", "main plane's translation along the fixed Y axis"),
    "rotor/angle": ("rotor_angle", "rad", "angle of the rotor's reference mark (keyphasor)"),
    "rotor/speed": ("rotor_speed", "rad/s", "rotor angular speed"),
}
REQUIRED = ("time", "shaft/x", "shaft/y")
RESERVED_ATTRS = ("scene", "scene_name", "scene_language", "solver", "version", "format",
                  "format_version", "created", "structure", "main_plane", "weight_planes",
                  "run_notes")
#: the groups of what the instruments output and of their ground truth
INSTRUMENTS, TRUTH = "instruments", "truth"
#: the instruments' groups (``instruments/<name>``, ``truth/<name>``); named screens
#: ``[instruments.screen.<n>]`` are ``screen.<n>`` (:func:`screen_group`)
SCREEN, STROBOSCOPE, PHOTOGATE = "screen", "stroboscope", "photogate"
KEYPHASOR, TACHOMETER, PROBES = "keyphasor", "tachometer", "probes"


def instrument_key(*parts: str) -> str:
    """``instrument_key("probes", "signal")`` -> ``"instruments/probes/signal"``."""
    return "/".join((INSTRUMENTS,) + parts)


def truth_key(*parts: str) -> str:
    """``truth_key("screen", "centre_m")`` -> ``"truth/screen/centre_m"``."""
    return "/".join((TRUTH,) + parts)


def screen_group(name=None) -> str:
    """The recording group of a screen: ``None`` / ``"screen"`` -> ``instruments/screen``;
    ``"front"`` or ``"screen.front"`` (``[instruments.screen.front]``) -> ``instruments/screen.front``."""
    if name is None or str(name) in ("", SCREEN):
        return instrument_key(SCREEN)
    name = str(name)
    return instrument_key(name if name.startswith(SCREEN + ".") else f"{SCREEN}.{name}")


#: format_version 1 weight matrices (N, n): path -> coordinate
V1_WEIGHTS = {"weights/angle": "angle", "weights/speed": "speed"}


class RecordingError(ValueError):
    """A file is not a readable recording.  The message names the file and the dataset."""


def decode_attr(value: Any) -> Any:
    """An HDF5 attribute value as a plain Python value."""
    if isinstance(value, bytes):
        return value.decode("utf-8", errors="replace")
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "OSU":
            return [decode_attr(v) for v in value.tolist()]
        return value
    if isinstance(value, np.generic):
        return value.item()
    return value


def scene_language(attrs: dict) -> int:
    """The scene-file language of a recording's stored scene text (root attribute
    ``scene_language``): 1 for the files written before it existed (their ``[structure]``
    angles are in rad), else the attribute's value."""
    v = attrs.get("scene_language")
    if isinstance(v, (int, np.integer)) and not isinstance(v, bool):
        return int(v)
    return 1
