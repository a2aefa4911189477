"""The scene: one experiment on the virtual stand, in SI units, and its one TOML parser.

* :mod:`.model`            -- :class:`Scene` and its parts (rotor, supports, weights, drive,
  perturbations, instruments), validated on construction;
* :mod:`.parse`            -- scene files: TOML in, one :class:`Scene` out (:func:`load`);
* :mod:`.structure_tables` -- the ``[structure]`` + ``[[weights]]`` form (any rotor of the family);
* :mod:`.body_tables`      -- ``[[weights]]`` tables of the body kinds (two-axis, pair, damper, liquid);
* :mod:`.book_tables`      -- the ``[weight_model]`` form (a book weight model with its own rotor);
* :mod:`.dimensionless`    -- the book's dimensionless parameters, both ways;
* :mod:`.experiments`      -- the experiment programmes of tables 4.1-4.7, built from a scene.
"""
