"""Parameter sweeps: many scenes, theory and/or simulation, on a process pool or a
Dask cluster, with checkpoint/resume.

* :mod:`.spec`  -- the ``SWEEP.toml`` format (:func:`load_sweep`), with
  :mod:`.axes` (the ``[[axis]]`` tables), :mod:`.keys` (what an axis key means
  for each scene kind) and :mod:`.checks` (messages);
* :mod:`.run`   -- execution and checkpoints (:func:`run_sweep`), with
  :mod:`.compute` and :mod:`.theory_points` (the work of a point),
  :mod:`.schema` (the table's columns) and :mod:`.store` (the files);
* :mod:`.maps`  -- regime and critical-speed maps (PNG).

See ``docs/sweep.md``.
"""
__all__ = ["Axis", "SweepSpec", "SweepSpecError", "load_sweep", "parse_sweep", "point_scene_dict",
           "RESULT_SCHEMA", "TIMING_COLUMNS", "compute_chunk", "parts_dir",
           "read_results", "run_sweep", "critical_speed_map", "regime_map"]

#: where each public name lives (imported on first use: ``stand --help`` needs no pandas)
_HOME = {**dict.fromkeys(("Axis", "SweepSpec", "SweepSpecError", "load_sweep", "parse_sweep",
                          "point_scene_dict"), "spec"),
         **dict.fromkeys(("RESULT_SCHEMA", "TIMING_COLUMNS", "compute_chunk", "parts_dir",
                          "read_results", "run_sweep"), "run"),
         "critical_speed_map": "maps", "regime_map": "maps"}


def __getattr__(name):
    if name in _HOME:
        import importlib

        value = getattr(importlib.import_module(f".{_HOME[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
