"""Virtual instruments of the stand (monograph chapter 4, digest ch5 sections 6 and 8.1.4).

Each instrument turns the ground-truth motion (a :class:`stand.integrate.simulate.Trajectory`
or plain arrays) into what the real instrument would record -- with its
imperfections -- and keeps the truth beside it:

* :mod:`.screen`      -- laser beam along the shaft axis onto a screen, a camera
  filming it (frames with exposure, noise, quantisation), calibration rings;
* :mod:`.strobe_readings`, :mod:`.strobe_render` -- the light slot flashing once per
  revolution: what it shows, and its frames;
* :mod:`.photogate`   -- the photo-element and pulse counter (period from the
  1st to the 3rd crossing);
* :mod:`.probes`      -- keyphasor, tachometer, displacement probes.

Their settings are scene data (``stand/scene/*_settings.py``, ``screen_camera.py``): dataclasses
with a ``from_table`` constructor that validates a ``[instruments.<name>]`` TOML table with
messages naming key, value and unit.
"""
