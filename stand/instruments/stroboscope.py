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

Body weights (two-axis pendulums, coupled pairs, the damper, liquids) are
drawn as they look: a bob at the centre of mass on a rod from the pivot, a
liquid's crescent (:class:`BodyLook`); their coordinates at the flashes are
the ground truth (:func:`body_coordinates`).
"""
from __future__ import annotations

# every name the module had, the constants too (they are not in __all__)
from stand.instruments.strobe_readings import (  # noqa: F401
    HOUSING_FACTOR, PATH, STROBE_KEYS, TWO_PI, BodyLook, StrobeReading,
    Stroboscope, body_coordinates, body_looks, default_ball_radius, flash_times,
    image_multiplicity, multiplicity_for_ratio, point_weights, reading_error, strobe_angles,
)
from stand.scene.strobe_settings import DEG, STEEL_DENSITY  # noqa: F401
from stand.instruments.strobe_render import (  # noqa: F401
    LEVEL_BALL, LEVEL_FLOAT, LEVEL_HOUSING, LEVEL_INTERIOR, LEVEL_LIQUID, LEVEL_MARK, LEVEL_RIM,
    LEVEL_ROD, MARK_SPAN, MAX_PIXELS, MAX_SUBPOSITIONS, StrobeFrame, drawn_weights,
    render_strobe_frames,
)

__all__ = ["Stroboscope", "StrobeReading", "StrobeFrame", "reading_error", "flash_times",
           "strobe_angles", "render_strobe_frames", "image_multiplicity",
           "multiplicity_for_ratio", "default_ball_radius", "STROBE_KEYS", "BodyLook",
           "body_looks", "body_coordinates", "drawn_weights"]
