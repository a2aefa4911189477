"""The scene: one experiment on the virtual stand, in SI units, and its one TOML parser.

* :mod:`.model`             -- :class:`Scene` and its parts (rotor, supports, weights in planes,
  drives, perturbations, instruments), validated on construction; imports nothing of the
  model or the integrator, so that every layer above may share these data classes;
* :mod:`.limits`            -- the size limits every scene form is held to;
* :mod:`.parse`             -- scene files: TOML in, one :class:`Scene` out (:func:`load`), the
  planar tables and the ``[dimensionless]`` form, and the dispatch to the other forms;
* :mod:`.tables`            -- every table (``[scene]``, ``[run]``, ``[drive]``, ``[[weights]]``,
  ``[balancer]``, ...) read by one function, whatever the scene's form;
* :mod:`.instrument_tables` -- ``[instruments.<name>]`` tables (settings and placement);
* :mod:`.structure_tables`  -- the ``[structure]`` + ``[[weights]]`` form (any rotor of the family);
* :mod:`.body_tables`       -- ``[[weights]]`` tables of the body kinds (two-axis, pair, damper, liquid);
* :mod:`.book_tables`       -- the ``[weight_model]`` form (a book weight model with its own rotor);
* :mod:`.dimensionless`     -- the book's dimensionless parameters, both ways;
* :mod:`.experiments`       -- the experiment programmes of tables 4.1-4.7, built from a scene.
"""
