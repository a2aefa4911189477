"""Figures of the balancing report (matplotlib's object API, no backend chosen), drawn from
the analysis (:class:`stand.analysis.results.Analysis`: its Bode data) and the channels it
analysed; the cameras' last frames from the recording."""
from __future__ import annotations

import math

import numpy as np

from stand.reports.html import figure_png

__all__ = ["figures", "polar_figures"]

TWO_PI = 2.0 * math.pi
#: the unit a channel of each quantity is drawn in: (name, SI factor to it)
_UNITS = {"length": ("mm", 1e3), "velocity": ("mm/s", 1e3), "acceleration": ("m/s²", 1.0)}


def figures(a, source=None) -> dict:
    """The report's figures.

    Parameters
    ----------
    a : stand.analysis.results.Analysis
        The analysis (its ``channels``: times [s], x, y, rotor and weight angles [rad]).
    source : path, Recording or Run, optional
        Where the cameras' last frames are read from.

    Returns
    -------
    dict
        ``{caption: PNG data URI}``: orbit (the channel's unit), 1X amplitude and phase
        (deg) against speed (rev/s) and the polar plot of the 1X vectors when the speed
        varies (or the Bode table's), spectrogram (Hz), weights' angles (deg), last camera
        frames.
    """
    from matplotlib.figure import Figure

    ch = a.channels or {}
    figs = {}
    q = ch.get("quantity", "length")
    unit, sc = _UNITS.get(q, ("SI", 1.0))
    t, x, y = ch.get("t"), ch.get("x"), ch.get("y")
    if t is not None and t.size >= 2:
        rings = ch.get("rings")
        st = a.get("stationary_stretch") or {}
        fig = Figure(figsize=(9, 4.2))
        axs = fig.subplots(1, 2)
        if rings is not None:
            g, (ox, oy) = rings["gain"], rings["offset_m"]
            X, Y, where = g * x + ox, g * y + oy, "screen"
        else:
            X, Y, where = x, y, "shaft" if q == "length" else q
        tail = t >= st["t_start_s"] if st else t >= t[0] + 0.7 * (t[-1] - t[0])
        for ax, sel, title in ((axs[0], slice(None), "whole record"),
                               (axs[1], tail, "stationary stretch")):
            ax.plot(X[sel] * sc, Y[sel] * sc, lw=0.6)
            if rings is not None:
                th = np.linspace(0, TWO_PI, 200)
                for rr in rings["radius_m"]:
                    if rr > 0:
                        ax.plot(rr * sc * np.cos(th), rr * sc * np.sin(th), color="0.75", lw=0.5)
                if title != "whole record":
                    rr = rings["radius_m"]
                    lim = max(float(np.max(np.hypot(X[sel], Y[sel]))) * sc * 1.2,
                              float(rr[min(2, rr.size - 1)]) * sc)
                    ax.set_xlim(-lim, lim)
                    ax.set_ylim(-lim, lim)
            ax.set_aspect("equal", adjustable="box")
            ax.set_xlabel(f"X ({where}, {unit})")
            ax.set_ylabel(f"Y ({where}, {unit})")
            ax.set_title(title)
        figs["orbit / laser trace (rings: zones i S/16 when recorded)"] = figure_png(fig)
    bode = a.get("bode") or (a.get("runup") or {}).get("bode")
    if bode and len(bode["speed_hz"]) > 1:
        figs.update(_bode_figures(bode, unit if a.get("bode") is None else "mm",
                                  sc if a.get("bode") is None else 1e3, a.get("critical_speed_hz")))
    if t is not None and t.size >= 16:
        figs.update(_spectrogram(t, x, y, ch.get("phi")))
    w, phi = ch.get("weights"), ch.get("phi")
    if w is not None and phi is not None and np.size(w):
        rel = np.asarray(w).reshape(t.size, -1) - np.unwrap(phi)[:, None]
        fig = Figure(figsize=(8, 3.5))
        ax = fig.subplots()
        ax.plot(t, np.degrees(np.angle(np.exp(1j * rel))), ".", ms=1)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("angle from the mark (deg)")
        ax.set_ylim(-180, 180)
        figs["weights' angles relative to the reference mark"] = figure_png(fig)
    for cap, frame in _last_frames(source):
        fig = Figure(figsize=(4, 4))
        ax = fig.subplots()
        ax.imshow(frame, cmap="gray", origin="upper")
        ax.set_axis_off()
        figs[cap] = figure_png(fig)
    return figs


def _bode_figures(bode, unit, sc, critical_hz) -> dict:
    """The 1X amplitude and phase against speed, and its polar plot (one point per
    revolution of a run, one per row of a Bode table)."""
    from matplotlib.figure import Figure

    f = np.asarray(bode["speed_hz"], float)
    amp = np.asarray(bode["amplitude_m"], float) * sc
    ph = bode.get("phase_deg")
    fig = Figure(figsize=(8, 5 if ph is not None else 3))
    axs = fig.subplots(2 if ph is not None else 1, 1, sharex=True, squeeze=False)[:, 0]
    axs[0].semilogy(f, np.maximum(amp, 1e-30), ".", ms=2)
    axs[0].set_ylabel(f"1X amplitude ({unit})")
    if ph is not None:
        axs[1].plot(f, ph, ".", ms=2)
        axs[1].set_ylabel("1X phase (deg)")
    for ax in axs:
        if critical_hz is not None:
            ax.axvline(critical_hz, color="C3", ls="--", lw=0.8)
    axs[-1].set_xlabel("rotor speed (rev/s; dashed: the identified critical speed)")
    out = {("1X amplitude and phase vs speed (Bode plot)" if ph is not None else
            "1X amplitude vs speed (no reference mark: no phase)"): figure_png(fig)}
    if ph is not None:
        z = amp * np.exp(1j * np.radians(np.asarray(ph, float)))
        fig = Figure(figsize=(5, 5))
        ax = fig.subplots()
        ax.plot(z.real, z.imag, ".-", ms=2, lw=0.5)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(f"1X real part ({unit})")
        ax.set_ylabel(f"1X imaginary part ({unit})")
        out["1X polar plot (the vector's tip as the speed rises)"] = figure_png(fig)
    return out


def _spectrogram(t, x, y, phi) -> dict:
    """The spectrogram of the complex orbit x + i y, with the rotor speed."""
    from matplotlib.figure import Figure
    from scipy import signal as sg

    fs = (t.size - 1) / (t[-1] - t[0])
    nper = int(min(max(16, 2 ** round(math.log2(max(fs, 1.0)))), max(16, t.size // 4)))
    nper = min(nper, t.size)
    f, tt, Sxx = sg.spectrogram(x + 1j * y, fs=fs, nperseg=nper, noverlap=nper // 2,
                                return_onesided=False, detrend=False)
    f = np.fft.fftshift(f)
    Sxx = np.fft.fftshift(Sxx, axes=0)
    fig = Figure(figsize=(8, 4))
    ax = fig.subplots()
    ax.pcolormesh(tt + t[0], f, 10 * np.log10(Sxx + 1e-30 + Sxx.max() * 1e-12),
                  shading="auto", cmap="viridis")
    if phi is not None:
        ax.plot(t, np.gradient(np.unwrap(phi), t) / TWO_PI, "w--", lw=0.7)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("frequency (Hz, + forward whirl)")
    return {"spectrogram of the orbit x + i y (dashed: rotor speed)": figure_png(fig)}


def _last_frames(source) -> list:
    """``[(caption, image)]``: the stroboscope's and the screen camera's last frames of a
    recording file or of a run in memory."""
    out = []
    caps = (("stroboscope", "stroboscope frame (last recorded)"),
            ("screen", "screen camera frame (last recorded)"))
    outputs = getattr(source, "instruments", None)
    if outputs is not None and not hasattr(source, "shape"):          # a run in memory
        for name, cap in caps:
            if name in outputs and outputs[name].n_frames > 0:
                out.append((cap, np.asarray(outputs[name].frame(outputs[name].n_frames - 1))))
        return out
    path = getattr(source, "path", source)
    if not path:
        return out
    from pathlib import Path

    from stand.lab.table import is_table

    if not Path(path).is_file() or is_table(Path(path)):
        return out
    from stand.recording.hdf5 import read_recording

    rec = source if hasattr(source, "shape") else read_recording(path)
    for name, cap in caps:
        shape = rec.shape(f"instruments/{name}/frames")
        if shape is not None and len(shape) == 3 and shape[0] > 0:
            out.append((cap, np.asarray(rec.dataset(f"instruments/{name}/frames", shape[0] - 1))))
    return out


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
