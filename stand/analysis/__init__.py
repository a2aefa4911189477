"""From recordings to a lab's numbers (``stand analyze``), on top of the leaves ``dsp`` and ``vision``.

* :mod:`.identify`  -- the journal's numbers from one recording (natural frequency, damping,
  unbalance, components, regime), step by step;
* :mod:`.sources`   -- its first step: a Run, a Recording, a recording file or a lab table as arrays;
* :mod:`.unbalance` -- its unbalance steps: 1X line, unbalance from a model, rings, ISO grade;
* :mod:`.runup`     -- run-up / run-down: Bode data, sweep-corrected resonance, model fit;
* :mod:`.two_plane` -- two-plane balancing from two laser screens;
* :mod:`.signals`   -- signal helpers on one recorded run;
* :mod:`.regime`    -- the motion regime at the end of a simulated run;
* :mod:`.influence` -- influence-coefficient balancing from recordings;
* :mod:`.tracking`  -- images to numbers: spot tracks, ring calibration, strobe angles;
* :mod:`.batch`     -- many recordings in parallel, one summary table;
* :mod:`.results`   -- the answers as result objects (Analysis, TwoPlane, Influence, Track).
"""
