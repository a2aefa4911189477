"""Figures of the balancing report (matplotlib's object API, no backend chosen), drawn only
from the recording's data."""
from __future__ import annotations

import math

import numpy as np

from stand.reports.html import figure_png
from stand.analysis.signals import per_revolution

__all__ = ["figures", "polar_figures"]

TWO_PI = 2.0 * math.pi


def figures(rec) -> dict:
    """The report's figures, from the recording's data only.

    Parameters
    ----------
    rec : Record
        The recording (:func:`stand.reports.balancing_input.load_record`).

    Returns
    -------
    dict
        ``{caption: PNG data URI}``: orbit (mm), 1X amplitude (mm) and phase
        (deg) against speed (rev/s) when the speed varies, spectrogram (Hz),
        weights' angles (deg), last camera frames.
    """
    from matplotlib.figure import Figure

    d, t, x, y, phi, speed, rotating = rec.data, rec.t, rec.x, rec.y, rec.phi, rec.speed, rec.rotating
    i_st = rec.steady
    figs = {}
    inst = d["inst"]
    # orbit / laser trace
    fig = Figure(figsize=(9, 4.2))
    axs = fig.subplots(1, 2)
    if "ring_radius" in inst:
        st = inst.get("screen_settings", {})
        g = float(st.get("gain", 1.0))
        ox, oy = float(st.get("offset_x", 0.0)), float(st.get("offset_y", 0.0))
        X, Y, unit, sc = g * x + ox, g * y + oy, "screen, mm", 1e3
    else:
        X, Y, unit, sc = x, y, "shaft, mm", 1e3
    sel = slice(i_st, None) if rotating and t.size - i_st > 8 else slice(int(0.7 * t.size), None)
    for ax, s_, title in ((axs[0], slice(None), "whole record"),
                          (axs[1], sel, "final stretch")):
        ax.plot(X[s_] * sc, Y[s_] * sc, lw=0.6)
        if "ring_radius" in inst:
            th = np.linspace(0, TWO_PI, 200)
            for rr in inst["ring_radius"]:
                if rr > 0:
                    ax.plot(rr * sc * np.cos(th), rr * sc * np.sin(th), color="0.75", lw=0.5)
            if title == "final stretch":
                lim = max(float(np.max(np.hypot(X[s_], Y[s_]))) * sc * 1.2,
                          float(inst["ring_radius"][min(2, inst["ring_radius"].size - 1)]) * sc)
                ax.set_xlim(-lim, lim)
                ax.set_ylim(-lim, lim)
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel(f"X ({unit})")
        ax.set_ylabel(f"Y ({unit})")
        ax.set_title(title)
    figs["orbit / laser trace (rings: zones i S/16 when recorded)"] = figure_png(fig)

    # 1X amplitude / phase vs speed for varying speed
    if rotating:
        try:
            pr = per_revolution(t, x, y, phi)
        except Exception:  # noqa: BLE001
            pr = None
        if pr is not None and np.ptp(pr[1]) > 0.05 * np.max(pr[1]):
            tm, wr, vec = pr
            phase = d.get("phase_referenced", True)    # no mark: a phase means nothing
            fig = Figure(figsize=(8, 5 if phase else 3))
            axs_b = fig.subplots(2 if phase else 1, 1, sharex=True, squeeze=False)[:, 0]
            axs_b[0].semilogy(wr / TWO_PI, np.maximum(np.abs(vec), 1e-30) * 1e3, ".", ms=2)
            axs_b[0].set_ylabel("1X amplitude (mm)")
            if phase:
                axs_b[1].plot(wr / TWO_PI, np.degrees(np.angle(vec)), ".", ms=2)
                axs_b[1].set_ylabel("1X phase (deg)")
            axs_b[-1].set_xlabel("rotor speed (rev/s)")
            figs["1X amplitude and phase vs speed (one point per revolution)" if phase else
                 "1X amplitude vs speed (one point per revolution; no reference mark: no phase)"] \
                = figure_png(fig)

    # spectrogram of the complex orbit
    from scipy import signal as sg

    fs = (t.size - 1) / (t[-1] - t[0])
    nper = int(min(max(16, 2 ** round(math.log2(max(fs, 1.0)))), max(16, t.size // 4)))
    nper = min(nper, t.size)
    if t.size >= 16:
        f, tt, Sxx = sg.spectrogram(x + 1j * y, fs=fs, nperseg=nper, noverlap=nper // 2,
                                    return_onesided=False, detrend=False)
        f = np.fft.fftshift(f)
        Sxx = np.fft.fftshift(Sxx, axes=0)
        fig = Figure(figsize=(8, 4))
        ax = fig.subplots()
        ax.pcolormesh(tt + t[0], f, 10 * np.log10(Sxx + 1e-30 + Sxx.max() * 1e-12),
                      shading="auto", cmap="viridis")
        if rotating:
            ax.plot(t, speed / TWO_PI, "w--", lw=0.7)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("frequency (Hz, + forward whirl)")
        figs["spectrogram of the orbit x + i y (dashed: rotor speed)"] = figure_png(fig)

    # weights' relative angles
    rel = d.get("rel")
    if rel is not None and rel.size:
        fig = Figure(figsize=(8, 3.5))
        ax = fig.subplots()
        ax.plot(t, np.degrees(np.angle(np.exp(1j * rel))), ".", ms=1)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("angle from the mark (deg)")
        ax.set_ylim(-180, 180)
        figs["weights' angles relative to the reference mark"] = figure_png(fig)

    for key, cap in (("strobe_frame", "stroboscope frame (last recorded)"),
                     ("screen_frame", "screen camera frame (last recorded)")):
        if key in inst:
            fig = Figure(figsize=(4, 4))
            ax = fig.subplots()
            ax.imshow(inst[key], cmap="gray", origin="upper")
            ax.set_axis_off()
            figs[cap] = figure_png(fig)
    return figs


def _polar(points, permissible_gmm, title):
    """A polar plot of unbalance vectors [g mm] (angle from the reference mark, counter-
    clockwise = the rotation direction) with the permissible circle."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(4.6, 4.6))
    ax = fig.add_subplot(projection="polar")
    rmax = max([p[1] for p in points] + [permissible_gmm or 0.0]) * 1.15 or 1.0
    if permissible_gmm:
        th = np.linspace(0, TWO_PI, 200)
        ax.fill(th, np.full(th.size, permissible_gmm), color="#2a2", alpha=0.15, lw=0)
        ax.plot(th, np.full(th.size, permissible_gmm), color="#2a2", lw=1.2,
                label=f"permissible {permissible_gmm:.3g} g·mm")
    for name, U, ang, style in points:
        a = math.radians(ang if ang is not None else 0.0)
        ax.annotate("", xy=(a, U), xytext=(0, 0),
                    arrowprops=dict(arrowstyle="->", color=style, lw=2))
        ax.plot([a], [U], "o", color=style, label=f"{name}: {U:.3g} g·mm"
                + (f" at {ang % 360:.0f}°" if ang is not None else " (no angle)"))
    ax.set_rmax(rmax)
    ax.set_title(title, fontsize=10)
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, -0.32), fontsize=8, frameon=False)
    return fig


def polar_figures(doc, scene=None) -> dict:
    """``{caption: PNG data URI}``: the unbalance before and after against the permissible
    circle (ISO 21940-11), one plot per correction plane for two-plane work.

    ``doc`` is the report's JSON; ``scene`` (optional) gives the angle of the rotor's own
    unbalance (the "before" point).
    """
    from stand.reports.html import figure_png

    out = {}
    bq = doc.get("balancing_quality") or {}
    Up = (bq.get("iso_21940_11") or {}).get("permissible_residual_gmm")
    pts = []
    if bq.get("initial_unbalance_gmm"):
        ang = None
        if scene is not None:
            ang = math.degrees(float(getattr(scene.rotor, "unbalance_angle", 0.0)))
        pts.append(("before", float(bq["initial_unbalance_gmm"]), ang, "#b33"))
    if bq.get("residual_unbalance_gmm") is not None:
        pts.append(("after", float(bq["residual_unbalance_gmm"]),
                    bq.get("residual_unbalance_angle_deg"), "#137"))
    if pts:
        out["polar plot: unbalance before and after, permissible circle (ISO 21940-11)"] = \
            figure_png(_polar(pts, Up, "unbalance (g·mm)"))
    two = doc.get("two_plane") or {}
    for p in two.get("planes", []):
        pp = [("residual", float(p["unbalance_gmm"]), p.get("angle_deg"), "#137")]
        if p.get("truth_gmm") is not None:
            pp.append(("truth", float(p["truth_gmm"]), p.get("truth_angle_deg"), "#999"))
        out[f"polar plot: plane {p.get('plane')}, unbalance and its permissible share"] = \
            figure_png(_polar(pp, p.get("permissible_gmm"), f"plane {p.get('plane')} (g·mm)"))
    return out
