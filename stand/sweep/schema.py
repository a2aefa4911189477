"""The columns of a sweep's result table and their dtypes (``docs/sweep.md``).

Every part file and the final table have the same columns and dtypes
(:func:`rows_to_frame`), whatever the points computed.
"""
from __future__ import annotations

import math
from typing import Iterable, Optional

import pandas as pd

from stand.sweep.spec import SweepSpec

__all__ = ["COMMON_COLUMNS", "THEORY_COLUMNS", "SIMULATE_COLUMNS", "RESULT_SCHEMA",
           "TIMING_COLUMNS", "rows_to_frame"]

#: output columns and their dtypes (inputs are float64 columns named by the axis keys)
COMMON_COLUMNS = {"point_index": "int64", "point_id": "string", "status": "string",
                  "error": "string", "wall_time_s": "float64",
                  "p.n": "Int64", "p.Rt": "float64", "p.h": "float64", "p.H": "float64",
                  "p.e0": "float64", "p.R": "float64", "p.f0_hz": "float64"}
THEORY_COLUMNS = {"theory.d": "float64", "theory.main_abscissa": "float64",
                  "theory.main_stable": "boolean", "theory.qp_stable": "boolean",
                  "theory.escape_speed_R": "float64", "theory.stable_motions": "string",
                  "theory.critical_speeds_R": "string", "theory.critical_kinds": "string",
                  "theory.n_critical": "Int64", "theory.critical_speeds_hz": "string",
                  "theory.natural_frequencies_hz": "string"}
SIMULATE_COLUMNS = {"sim.regime": "string", "sim.residual": "float64",
                    "sim.rotor_speed_R": "float64", "sim.spread_rad": "float64",
                    "sim.whirl_radius_m": "float64",
                    "sim.success": "boolean", "sim.message": "string", "sim.nfev": "Int64",
                    "sim.wall_s": "float64"}
RESULT_SCHEMA = {**COMMON_COLUMNS, **THEORY_COLUMNS, **SIMULATE_COLUMNS}
#: columns that depend on the machine, not on the inputs (dropped when comparing runs)
TIMING_COLUMNS = ("wall_time_s", "sim.wall_s")


def rows_to_frame(rows: list, spec_or_keys, compute: Optional[Iterable[str]] = None) -> pd.DataFrame:
    """Rows (dicts) -> DataFrame with the fixed schema (so that every part has the same dtypes).

    Parameters
    ----------
    rows : list of dict
        One row per point (:func:`stand.sweep.compute.compute_chunk`).
    spec_or_keys : SweepSpec or sequence of str
        The sweep (its axis keys and compute list), or the axis keys.
    compute : iterable of str, optional
        With axis keys: "theory" and/or "simulate".

    Returns
    -------
    pandas.DataFrame
        ``point_index``, ``point_id``, the inputs, then :data:`RESULT_SCHEMA`'s
        columns of what was computed.
    """
    if isinstance(spec_or_keys, SweepSpec):
        keys, compute = spec_or_keys.columns, spec_or_keys.compute
    else:
        keys = list(spec_or_keys)
    compute = compute or ()
    schema = dict(COMMON_COLUMNS)
    if "theory" in compute:
        schema.update(THEORY_COLUMNS)
    if "simulate" in compute:
        schema.update(SIMULATE_COLUMNS)
    cols = ["point_index", "point_id"] + list(keys) + [c for c in schema if c not in
                                                       ("point_index", "point_id")]
    data = {}
    for c in cols:
        vals = [r.get(c) for r in rows]
        dtype = schema.get(c, "float64")
        if dtype == "string":
            vals = ["" if v is None else str(v) for v in vals]
        elif dtype == "float64":
            vals = [math.nan if v is None else float(v) for v in vals]
        data[c] = pd.array(vals, dtype=dtype)
    return pd.DataFrame(data, columns=cols)
