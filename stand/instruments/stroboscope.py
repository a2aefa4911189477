"""The light-slot stroboscope of the universal stand (monograph section 4.3.1).

A lamp in the machine body shines through a narrow slot; the rotor has a slot
of its own, so light enters the rotor once per revolution, when the rotor's
slot passes the lamp, and an observer (a camera above the rotor) sees the
weights at one rotor angle (digest ch5 section 6.1).  Reading error (4.1)::

    eta = delta_max / P_min,   P_min = 2 pi slot_radius,

the slot width over the rotor perimeter at the slot, independent of the
speed.  While the slots overlap the rotor turns by ``slot_width /
slot_radius`` rad: this is the angular blur of every image (the light is taken
as uniform over that span: one slot much narrower than the other).

A weight group that runs at Omega while the rotor runs at omega (stuck balls,
digest ch5 section 5.3) moves by ``-2 pi (1 - Omega/omega)`` of relative angle
per flash; an exposure over several flashes then shows several images (the
book's "doubling, tripling" for Omega/omega ~ 1/2, 1/3).

This module gathers the instrument; the code lives in

* :mod:`stand.instruments.strobe_readings` -- the settings
  (:class:`Stroboscope`), the reading error (4.1), the flash times and the
  weights' angles at the flashes, the image multiplicity;
* :mod:`stand.instruments.strobe_render` -- the frames the camera films
  (image conventions, what is drawn, noise and quantisation).
"""
from __future__ import annotations

# every name the module had, the constants too (they are not in __all__)
from .strobe_readings import (  # noqa: F401
    DEG, PATH, STEEL_DENSITY, STROBE_KEYS, TWO_PI, StrobeReading, Stroboscope,
    default_ball_radius, flash_times, image_multiplicity, multiplicity_for_ratio, reading_error,
    strobe_angles,
)
from .strobe_render import (  # noqa: F401
    LEVEL_BALL, LEVEL_INTERIOR, LEVEL_MARK, LEVEL_RIM, LEVEL_ROD, MARK_SPAN, MAX_PIXELS,
    MAX_SUBPOSITIONS, StrobeFrame, render_strobe_frames,
)

__all__ = ["Stroboscope", "StrobeReading", "StrobeFrame", "reading_error", "flash_times",
           "strobe_angles", "render_strobe_frames", "image_multiplicity",
           "multiplicity_for_ratio", "default_ball_radius", "STROBE_KEYS"]
