"""The field-balancing report's figures, from a :class:`~stand.analysis.field_balance.FieldBalance`.

* :func:`plane_drawing` -- a correction plane seen from its face: the holes (numbered, hole 0
  at the reference mark), the reference mark (0 deg), the sense in which the job's angles
  count, the trial masses' positions and the correction (and the holes it is split onto).
* :func:`sensor_polar` -- one sensor at one speed: the reference run's vibration, the trial
  runs', the predicted vibration after correction and the check run's, as vectors
  (the job's unit and amplitude convention, angles as the readings give them).

matplotlib ``Figure`` objects only (no pyplot, no backend chosen), returned as PNG data URIs
(:func:`stand.reports.html.figure_png`).
"""
from __future__ import annotations

import math

from stand.io.numbers import plain
from stand.reports.html import figure_png

__all__ = ["plane_drawing", "sensor_polar", "field_figures"]


def plane_drawing(res, plane: str) -> str:
    """PNG data URI of ``plane``'s drawing (module docstring)."""
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, FancyArrowPatch

    c, mu = res["corrections"][plane], res["mass_unit"]
    fig = Figure(figsize=(3.8, 3.8))
    ax = fig.add_subplot()
    ax.add_patch(Circle((0, 0), 1.0, fill=False, lw=2, color="#444"))
    ax.add_patch(Circle((0, 0), 0.12, fill=False, lw=1, color="#444"))
    xy = lambda deg, r: (r * math.cos(math.radians(deg)), r * math.sin(math.radians(deg)))  # noqa: E731
    n = c.get("holes")
    used = {h["hole"] for h in c.get("split", [])}
    for k in range(n or 0):
        x, y = xy(360.0 * k / n, 0.85)
        ax.add_patch(Circle((x, y), 0.045, color="#c60" if k in used else "#999",
                            fill=k in used))
        ax.annotate(str(k), xy(360.0 * k / n, 0.72), ha="center", va="center", fontsize=6)
    ax.plot(*zip(xy(-5, 1.12), xy(5, 1.12), xy(0, 1.02), xy(-5, 1.12)), color="k")
    ax.annotate("0° reference mark", xy(0, 1.16), fontsize=7, va="center")
    ax.add_patch(FancyArrowPatch(xy(25, 1.1), xy(65, 1.1), connectionstyle="arc3,rad=0.2",
                                 arrowstyle="-|>", mutation_scale=10, color="#06c"))
    ax.annotate("angles count this way", xy(45, 1.2), fontsize=7, color="#06c", ha="center")
    for run in res["runs"]:
        t = run["trial"].get(plane)
        if t and run["kind"] == "trial":
            ax.plot(*xy(t["angle_deg"], 0.95), "s", color="#888", ms=6)
            ax.annotate(f"trial {plain(t['mass'], mu)}", xy(t["angle_deg"] + 12, 0.5), fontsize=7,
                        color="#555", ha="center")
    ax.add_patch(FancyArrowPatch((0, 0), xy(c["angle_deg"], 0.9), arrowstyle="-|>",
                                 mutation_scale=14, lw=2, color="#b00"))
    ax.annotate(f"put {plain(c['mass'], mu)} at {plain(c['angle_deg'], '°')}",
                xy(c["angle_deg"], 0.35), fontsize=8, color="#b00", ha="center",
                fontweight="bold")
    ax.set_xlim(-1.35, 1.35)
    ax.set_ylim(-1.35, 1.35)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(f"plane {plane}" + (f", {n} holes" if n else ""), fontsize=9)
    return figure_png(fig)


def sensor_polar(res, r) -> str:
    """PNG data URI of the polar plot of residual row ``r`` (module docstring)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.6, 3.8))
    ax = fig.add_subplot(projection="polar")
    style = {"reference": ("o", "#b00"), "trial": ("^", "#888"), "check": ("D", "#06c")}
    for run in res["runs"]:
        rd = run["readings"].get(r["sensor"])
        same = (r["speed_rpm"] is None or run["speed_rpm"] is None
                or abs(run["speed_rpm"] - r["speed_rpm"]) <= 0.01 * r["speed_rpm"])
        if not (same and rd and run["kind"] in style and rd["angle_deg"] is not None):
            continue
        mk, col = style[run["kind"]]
        th = math.radians(rd["angle_deg"])
        ax.plot([0, th], [0, rd["amplitude"]], "-", color=col, lw=0.8)
        ax.plot([th], [rd["amplitude"]], mk, color=col, label=f"run {run['run']} ({run['kind']})")
    th = math.radians(r["after_deg"] or 0.0)                      # None: exactly zero
    ax.plot([0, th], [0, r["after"]], "s-", color="#070", label="predicted after"
            + (" (0, exactly determined)" if r["after_deg"] is None else ""))
    at = f" at {plain(r['speed_rpm'], 'rpm', sig=6)}" if r["speed_rpm"] is not None else ""
    ax.set_title(f"{r['sensor']}{at} [{res['vibration_unit']} {res['amplitude']}]", fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.08, 1.0))
    return figure_png(fig)


def field_figures(res) -> dict:
    """``{caption: PNG data URI}``: one drawing per plane, one polar plot per sensor and speed."""
    figs = {f"plane {p}: where to put the correction": plane_drawing(res, p)
            for p in res["corrections"]}
    for r in res["residuals"]:
        at = f" at {plain(r['speed_rpm'], 'rpm', sig=6)}" if r["speed_rpm"] is not None else ""
        figs[f"sensor {r['sensor']}{at}: reference, trial, check runs and predicted after"] = \
            sensor_polar(res, r)
    return figs
