"""Maps of a sweep's table: regime map and critical-speed map (PNG, matplotlib Agg).

Both take the table returned by :func:`stand.sweep.run_sweep` (or read back with
:func:`stand.sweep.read_results`) and two input columns for the axes.  The
horizontal axis defaults to the speed ratio ``p.R`` (= omega / omega_1) and the
vertical one to the other swept input.
"""
from __future__ import annotations

import json
import math
from typing import Optional

import numpy as np
import pandas as pd

__all__ = ["regime_map", "critical_speed_map", "default_axes"]


def default_axes(table: pd.DataFrame, spec=None):
    """(x, y) columns: ``p.R`` and the first swept input that is not a speed."""
    inputs = list(spec.columns) if spec is not None else [
        c for c in table.columns if c not in ("point_index", "point_id", "status", "error",
                                              "wall_time_s") and "." not in c[:2]
        and not c.startswith(("p.", "theory.", "sim."))]
    speedish = ("R_omega", "dimensionless.R_omega", "speed", "drive.speed")
    others = [c for c in inputs if c not in speedish]
    x = "p.R"
    y = others[0] if others else (inputs[0] if inputs else "p.e0")
    return x, y


def _figure():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def regime_map(table: pd.DataFrame, path, *, x: Optional[str] = None, y: Optional[str] = None,
               column: Optional[str] = None, spec=None, title: Optional[str] = None) -> None:
    """Draw the regime of each point over two inputs.

    Parameters
    ----------
    table : DataFrame
        A sweep's results.
    path : path
        PNG file.
    x, y : str, optional
        Columns of the axes (default :func:`default_axes`: ``p.R``, the speed
        ratio omega/omega_1, and the other swept input).
    column : str, optional
        Category shown: default ``sim.regime`` if simulated, else
        ``theory.stable_motions``.
    spec : SweepSpec, optional
        Used to pick the default axes.
    """
    plt = _figure()
    dx, dy = default_axes(table, spec)
    x, y = x or dx, y or dy
    if column is None:
        column = "sim.regime" if "sim.regime" in table.columns else "theory.stable_motions"
    cat = table[column].astype(str).where(table["status"] == "ok", "error")
    cat = cat.replace("", "none")
    labels = sorted(cat.unique())
    cmap = plt.get_cmap("tab10" if len(labels) <= 10 else "tab20")
    fig, ax = plt.subplots(figsize=(7.5, 5.0), dpi=110)
    n = len(table)
    size = max(2.0, min(60.0, 24000.0 / max(n, 1)))
    for k, lab in enumerate(labels):
        sel = cat == lab
        ax.scatter(table.loc[sel, x], table.loc[sel, y], s=size, marker="s", linewidths=0,
                   color=("0.3" if lab == "error" else cmap(k % cmap.N)), label=lab)
    ax.set_xlabel("speed ratio R = omega / omega_1" if x == "p.R" else x)
    ax.set_ylabel("unbalance e0 (capacity units)" if y in ("p.e0", "e0", "dimensionless.e0") else y)
    ax.set_title(title or f"{column}  ({n} points)")
    ax.legend(fontsize=7, loc="best", markerscale=max(1.0, 6.0 / math.sqrt(size)), framealpha=0.85)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def critical_speed_map(table: pd.DataFrame, path, *, x: Optional[str] = None,
                       y: Optional[str] = None, spec=None, title: Optional[str] = None) -> None:
    """Main-motion stability over two inputs with the critical speeds drawn on it.

    Points where the main (balancing) motion is stable are shaded; each
    critical speed of a row (``theory.critical_speeds_R``, in units of omega_1)
    is marked at that row's ``y`` (triangles up: the motion gains stability
    above it; down: loses it).  The horizontal axis must be the speed ratio
    ``p.R`` for the marks to be meaningful (the default).

    Parameters
    ----------
    table : DataFrame
        Results of a sweep with compute = "theory".
    path : path
        PNG file.
    x, y : str, optional
        Axis columns (default ``p.R`` and the other swept input).
    """
    if "theory.main_stable" not in table.columns:
        raise ValueError("critical_speed_map: the table has no theory columns "
                         "(compute = [\"theory\"] in the sweep file)")
    plt = _figure()
    dx, dy = default_axes(table, spec)
    x, y = x or dx, y or dy
    ok = table["status"] == "ok"
    stable = table["theory.main_stable"].fillna(False).astype(bool) & ok
    fig, ax = plt.subplots(figsize=(7.5, 5.0), dpi=110)
    n = len(table)
    size = max(2.0, min(60.0, 24000.0 / max(n, 1)))
    ax.scatter(table.loc[stable, x], table.loc[stable, y], s=size, marker="s", linewidths=0,
               color="#9fd49f", label="main motion stable")
    ax.scatter(table.loc[~stable & ok, x], table.loc[~stable & ok, y], s=size, marker="s",
               linewidths=0, color="#f2c0c0", label="main motion unstable / none")
    if (~ok).any():
        ax.scatter(table.loc[~ok, x], table.loc[~ok, y], s=size, marker="s", linewidths=0,
                   color="0.4", label="error")
    if x == "p.R":
        xmin, xmax = float(table[x].min()), float(table[x].max())
        seen = {}
        for yv, cs, kinds in zip(table[y], table["theory.critical_speeds_R"].fillna(""),
                                 table["theory.critical_kinds"].fillna("")):
            if not cs or yv in seen:
                continue
            seen[yv] = (json.loads(cs), json.loads(kinds))
        for kind, marker, color in (("gains", "^", "tab:green"), ("loses", "v", "tab:red")):
            pts = [(r, yv) for yv, (rs, ks) in seen.items() for r, k in zip(rs, ks)
                   if k == kind and xmin <= r <= xmax]
            if pts:
                a = np.array(pts)
                ax.plot(a[:, 0], a[:, 1], marker, color=color, ms=4,
                        label=f"critical speed ({kind} stability)")
        if "theory.escape_speed_R" in table.columns:
            esc = table.groupby(y)["theory.escape_speed_R"].first()
            esc = esc[(esc >= xmin) & (esc <= xmax)]
            if len(esc):
                ax.plot(esc.values, esc.index, ".", color="tab:purple", ms=3,
                        label="QP escape speed R*")
    ax.set_xlabel("speed ratio R = omega / omega_1" if x == "p.R" else x)
    ax.set_ylabel("unbalance e0 (capacity units)" if y in ("p.e0", "e0", "dimensionless.e0") else y)
    ax.set_title(title or f"main-motion stability and critical speeds ({n} points)")
    ax.legend(fontsize=7, loc="best", framealpha=0.85)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
