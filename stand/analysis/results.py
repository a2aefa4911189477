"""The answers of the analysis as result objects (:class:`stand.io.result.Result`).

* :class:`Analysis`  -- ``stand.analyze``: the journal's numbers of one recording;
* :class:`TwoPlane`  -- two-plane balancing from two screens;
* :class:`Influence` -- influence-coefficient balancing from recordings;
* :class:`Track`     -- a spot track of a screen's frames (``stand track``, ``stand.track``).

Each holds the document ``--json`` prints (``to_dict()``), its tables
(``to_frame(...)``) and draws its picture on a given Axes (``plot(ax=)``).
"""
from __future__ import annotations

import math

from stand.io.result import Result

__all__ = ["Analysis", "TwoPlane", "Influence", "Track"]


class Analysis(Result):
    """What ``stand.analyze`` identified in one recording (docs/results.md).

    Attributes are the keys of ``stand analyze --json`` (units in the names):
    ``speed_hz``, ``natural_frequency_hz`` (``_std``), ``damping_ratio``,
    ``response_1x_m``, ``unbalance_gmm`` (``_std``), ``unbalance_angle_deg``,
    ``iso_grade``, ``programme``, ``runup`` (``bode``, ``resonance``, ``model_fit``),
    ``critical_speed_hz``, ``components`` (quasi-periodic lines), ``precession_hz`` and
    ``nutation_hz`` (stuck weights only), ``strongest_other_line_hz`` (the orbit's strongest
    line besides the 1X when it is no such precession), ``regime`` (:mod:`dsp.regime`'s
    names; shown by :data:`stand.io.labels.REGIME_NAMES`), ``critical_speeds_hz``,
    ``settling``, ``vibration_1x``,
    ``ring_reading``, ``initial_unbalance_gmm`` and ``reduction`` (simulated planar runs),
    ``truth_unbalance_gmm``, ``notes``; and ``regime_timeline`` (held, left out of the JSON
    as the CLI does).  :attr:`channels` holds the arrays analysed (what a report draws).

    Tables for :meth:`to_frame`: ``"components"``, ``"regime_timeline"``,
    ``"critical_speeds_hz"``, ``"runup.bode"``, ``"programme.stretches"``.
    The picture: the run-up's 1X amplitude against speed when there is one, else the
    orbit's lines (amplitude against frequency).
    """

    _title = "analysis"
    _json_exclude = ("regime_timeline",)
    _summary_keys = ("recording", "speed_hz", "natural_frequency_hz", "damping_ratio",
                    "unbalance_gmm", "regime")

    def __init__(self, doc, channels=None):
        super().__init__(doc)
        self._channels = channels

    @property
    def channels(self):
        """The arrays analysed (:func:`stand.analysis.sources.read_source`: ``t`` [s], ``x``,
        ``y`` [m or the channel's SI unit], ``phi`` [rad], ``weights`` [rad], ``scene``,
        ``rec_scene``, ``rings``, ...; None for a Bode table): what a report draws, not part
        of the document."""
        return self._channels

    def _draw(self, ax) -> None:
        bode = (self.get("runup") or {}).get("bode")
        if bode:
            ax.plot(bode["speed_hz"], [a * 1e6 for a in bode["amplitude_m"]], lw=0.9, label="1X")
            if self.get("critical_speed_hz") is not None:
                ax.axvline(self["critical_speed_hz"], color="C3", ls="--", lw=0.8,
                           label="critical speed")
            ax.set_xlabel("speed [rev/s]")
            ax.set_ylabel("1X amplitude [µm]")
            ax.legend(loc="upper right")
        else:
            comps = self.get("components") or []
            f = [c["frequency_hz"] for c in comps]
            a = [c["amplitude_m"] * 1e6 for c in comps]
            if f:
                ax.vlines(f, 0, a, lw=1.5)
                ax.plot(f, a, "o")
            for key, style in (("speed_hz", "C1"), ("natural_frequency_hz", "C2")):
                if self.get(key) is not None:
                    ax.axvline(self[key], color=style, ls=":", lw=0.8, label=key)
            ax.set_xlabel("frequency [Hz]")
            ax.set_ylabel("amplitude [µm]")
            if ax.get_legend_handles_labels()[0]:
                ax.legend(loc="upper right")
        ax.set_title(f"analysis of {self.get('recording', '')}", fontsize=9)


class TwoPlane(Result):
    """Two-plane balancing from two laser screens (:func:`stand.analysis.two_plane.two_plane`):
    ``planes`` (one record per correction plane: ``unbalance_gmm``, ``angle_deg``, their
    ``_std``, ``permissible_gmm``, ``passed``), ``screens``, ``speed_hz``, ``iso_21940_11``.
    ``to_frame()`` without a table name: the planes."""

    _title = "two-plane balancing"
    _summary_keys = ("recording", "speed_hz")

    def to_frame(self, table="planes"):
        return super().to_frame(table)

    def _draw(self, ax) -> None:
        rows = self["planes"]
        pos = list(range(len(rows)))
        ax.bar(pos, [r["unbalance_gmm"] for r in rows], yerr=[r["unbalance_gmm_std"] for r in rows],
               color="C0", label="unbalance")
        ax.scatter(pos, [r["permissible_gmm"] for r in rows], marker="_", s=600, color="C3",
                   label="permissible")
        ax.set_xticks(pos, [r["plane"] for r in rows])
        ax.set_ylabel("unbalance [g·mm]")
        ax.legend(loc="upper right")
        ax.set_title(f"two-plane balancing at {self['speed_hz']:.4g} rev/s", fontsize=9)


class Influence(Result):
    """Influence-coefficient balancing (:func:`stand.analysis.influence.influence_from_recordings`).

    The document is :meth:`dsp.influence.InfluenceBalance.to_dict` (``stand influence
    --json``); :attr:`balance` is the :class:`~dsp.influence.InfluenceBalance` itself, and
    its attributes are the result's (``planes``, ``sensors``, ``mass_g``, ``angle_deg``,
    ``correction_kg_m``, ... as tuples and arrays; the document's keys where it has none);
    ``to_frame()`` one row per correction plane (its ``to_frame()``)."""

    _title = "influence-coefficient balancing"

    def __init__(self, balance):
        super().__init__(balance.to_dict())
        self._balance = balance

    @property
    def balance(self):
        """The :class:`dsp.influence.InfluenceBalance`."""
        return self._balance

    def __getattr__(self, name):
        # the balance's own attributes first (planes, sensors, mass_g, ... as arrays and
        # tuples, as before), then the document's keys
        if not name.startswith("_") and hasattr(self._balance, name):
            return getattr(self._balance, name)
        return super().__getattr__(name)

    def to_frame(self, table=None):
        return self._balance.to_frame() if table is None else super().to_frame(table)

    def _summary(self) -> list:
        b = self._balance
        return [(p, f"{m:.4g} g at {a:.1f} deg") for p, m, a in zip(b.planes, b.mass_g, b.angle_deg)]

    def _draw(self, ax) -> None:
        b = self._balance
        for p, m, a in zip(b.planes, b.mass_g, b.angle_deg):
            th = math.radians(a)
            ax.annotate("", (m * math.cos(th), m * math.sin(th)), (0, 0),
                        arrowprops=dict(arrowstyle="->"))
            ax.text(m * math.cos(th), m * math.sin(th), f" {p}", fontsize=8)
        r = max([abs(m) for m in b.mass_g] + [1e-12]) * 1.2
        ax.set_xlim(-r, r)
        ax.set_ylim(-r, r)
        ax.set_aspect("equal")
        ax.set_xlabel("correction mass [g], 0 deg")
        ax.set_ylabel("correction mass [g], 90 deg")
        ax.set_title(self._title)


class Track(Result):
    """A spot track (``stand track``, :func:`stand.analysis.tracking.track_frames`) or the
    weights' angles in stroboscope frames (``stand strobe``): one row per frame in
    :attr:`frame` (the DataFrame the CSV holds), which ``to_frame()`` returns; the document
    is the summary (``source``, ``frames``, ``found``: frames read; a trace table also
    ``bounds``: frames read whose circle is unresolved, only an upper bound,
    :mod:`stand.analysis.trace_reading`).  The picture: the spot's path on the screen (or
    the weights' angles against the frame)."""

    _title = "track"

    def __init__(self, frame, source="", strobe: bool = False):
        ok = int(frame["ok"].sum()) if "ok" in frame else len(frame)
        doc = {"source": str(source), "frames": int(len(frame)), "found": ok}
        if "radius_px" in frame and "ok" in frame:
            from stand.analysis.trace_reading import unresolved

            doc["bounds"] = int((unresolved(frame) & frame["ok"].to_numpy(bool)).sum())
        super().__init__(doc)
        self._frame = frame
        self._strobe = bool(strobe)

    @property
    def frame(self):
        """The track, one row per frame (pandas DataFrame)."""
        return self._frame

    def to_frame(self, table=None):
        return self._frame if table is None else super().to_frame(table)

    def _draw(self, ax) -> None:
        df = self._frame
        if self._strobe:
            for c in (c for c in df.columns if c.endswith("_deg") and "std" not in c):
                ax.plot(df["frame"], df[c], ".", ms=3, label=c)
            ax.set_xlabel("frame")
            ax.set_ylabel("angle from the mark [deg]")
            ax.legend(loc="upper right", fontsize=7)
        else:
            xs, ys = ("x_m", "y_m") if "x_m" in df else ("u_px", "v_px")
            scale = 1e3 if xs == "x_m" else 1.0
            ax.plot(df[xs] * scale, df[ys] * scale, ".", ms=2)
            ax.set_aspect("equal", adjustable="datalim")
            unit = "mm" if xs == "x_m" else "px"
            ax.set_xlabel(f"x [{unit}]")
            ax.set_ylabel(f"y [{unit}]")
        ax.set_title(f"{'strobe angles' if self._strobe else 'track'} of {self['source']}",
                     fontsize=9)
