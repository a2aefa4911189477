"""Parameter sweeps: many scenes, theory and/or simulation, on a process pool or a
Dask cluster, with checkpoint/resume.

* :mod:`.spec`  -- the ``SWEEP.toml`` format (:func:`load_sweep`), with
  :mod:`.axes` (the ``[[axis]]`` tables), :mod:`.keys` (what an axis key means
  for each scene kind) and :mod:`.checks` (messages);
* :mod:`.run`   -- execution and checkpoints (:func:`run_sweep`), with
  :mod:`.compute` and :mod:`.theory_points` (the work of a point),
  :mod:`.schema` (the table's columns) and :mod:`.store` (the files);
* :mod:`.command` -- ``stand sweep`` (:func:`sweep_main`);
* :mod:`.maps`  -- regime and critical-speed maps (PNG).

See ``docs/sweep.md``.
"""
from .spec import Axis, SweepSpec, SweepSpecError, load_sweep, parse_sweep, point_scene_dict
from .run import (RESULT_SCHEMA, TIMING_COLUMNS, add_sweep_arguments, compute_chunk, parts_dir,
                  read_results, run_sweep, sweep_main)
from .maps import critical_speed_map, regime_map

__all__ = ["Axis", "SweepSpec", "SweepSpecError", "load_sweep", "parse_sweep", "point_scene_dict",
           "RESULT_SCHEMA", "TIMING_COLUMNS", "add_sweep_arguments", "compute_chunk", "parts_dir",
           "read_results", "run_sweep", "sweep_main", "critical_speed_map", "regime_map"]
