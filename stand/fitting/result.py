"""The answer of ``stand fit``: :class:`Fit`, a result like every other of the stand.

The document (``stand fit --json``)::

    parameters   {path: {value, std, unit, identifiable, start, lower, upper, note, ...}}
                 values in the scene file's own units (angles in degrees)
    correlation  {paths: [...], matrix: [[...]]}
    nuisance     the shaft's initial state, the probes' offset and runout, the rotor angle's
                 correction (what the record adds that is not the scene's)
    fit          chi2_dof, rms_residual, noise_std (the record's SI unit), samples, dof,
                 segments (chi2/dof per tenth of the record), stages, simulations, wall time
    comparison   theory against experiment: [{quantity, unit, measured, measured_std,
                 predicted, predicted_std, difference_sigma, note}]
    notes

Beside it: :attr:`Fit.scene` (the fitted :class:`stand.scene.model.Scene`),
:meth:`Fit.write_scene` (the fitted scene file, a new TOML with a comment block saying what
was fitted to what), :meth:`Fit.to_frame` (one row per fitted value; ``to_frame("series")``:
the record against the model, sample by sample) and :meth:`Fit.plot` (measured and fitted
whirl radius against time, or ``kind="residual"``, ``"1x"``).
"""
from __future__ import annotations

from datetime import datetime, timezone
from typing import Optional

import numpy as np

from stand.io.result import Result, axes_of

__all__ = ["Fit"]


class Fit(Result):
    """A scene fitted to a record (module docstring)."""

    _title = "fit"
    _summary_keys = ("scene", "data", "parameters", "fit")

    def __init__(self, doc, *, scene=None, document=None, template_text: str = "",
                 series: Optional[dict] = None, values: Optional[dict] = None):
        super().__init__(doc)
        self._scene = scene
        self._document = document
        self._template_text = template_text
        self._series = series or {}
        self._values = values or {}

    # ------------------------------------------------------------ the fitted scene
    @property
    def scene(self):
        """The fitted Scene (the template with the fitted values written in)."""
        return self._scene

    @property
    def values(self) -> dict:
        """{path: fitted value} in the scene file's units."""
        return dict(self._values)

    def scene_text(self) -> str:
        """The fitted scene file: the template's text with the fitted values written over its
        own (comments and layout kept), headed by a comment block saying what was fitted to
        what, with the ± and the fit's chi^2/dof."""
        from stand.fitting.paths import document_text

        from stand.io import __version__ as version

        body = document_text(self._document, self._values, self._template_text)
        if body is None:          # a key the text's layout hides: the document re-written
            body = _dump_toml(self._document)
        fit = self["fit"]
        head = [f"# Fitted by stand fit {version} on "
                f"{datetime.now(timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}",
                f"# template: {self['scene']}",
                f"# record:   {self['data']} ({fit['samples']} samples, {fit['quantity']}, "
                f"rotor angle from {fit['rotor_angle'] or 'the scene programme'})",
                f"# chi2/dof = {fit['chi2_dof']:.4g}, residual RMS {fit['rms_residual']:.4g} "
                f"{fit['rms_residual_unit']}, noise {fit['noise_std']:.3g} {fit['noise_std_unit']}",
                "# fitted values (1-sigma):"]
        for p, d in self["parameters"].items():
            std = "not identifiable" if not d["identifiable"] else f"± {d['std']:.3g}"
            head.append(f"#   {p} = {d['value']:.9g} {d['unit']}  ({std}; started at "
                        f"{d['start']:.6g})")
        head.append("# every other value is the template's")
        return "\n".join(head) + "\n\n" + body

    def write_scene(self, path, *, inputs=()) -> str:
        """Write :meth:`scene_text` to ``path`` atomically; an input file is never replaced."""
        from pathlib import Path

        from stand.io.atomic import write_text

        p = Path(path)
        for q in inputs:
            try:
                if q is not None and Path(q).exists() and p.exists() and p.samefile(q):
                    raise ValueError(f"{p}: is an input of the fit; write the fitted scene "
                                     "to a new file")
            except OSError:
                pass
        write_text(p, self.scene_text())
        return str(p)

    # ------------------------------------------------------------ tables and pictures
    def to_frame(self, table: Optional[str] = None):
        """One row per fitted value (``table=None``), the record against the model sample by
        sample (``"series"``), or a table of the document (``"comparison"``)."""
        import pandas as pd

        if table is None:
            rows = [dict(path=p, **{k: v for k, v in d.items()}) for p, d in
                    self["parameters"].items()]
            return pd.DataFrame(rows).set_index("path")
        if table == "series":
            s = self._series
            if not s:
                return pd.DataFrame()
            return pd.DataFrame({"time_s": s["t"], "measured_x": s["measured"].real,
                                 "measured_y": s["measured"].imag, "model_x": s["model"].real,
                                 "model_y": s["model"].imag, "residual_x": s["residual"].real,
                                 "residual_y": s["residual"].imag})
        return super().to_frame(table)

    def plot(self, ax=None, kind: str = "whirl"):
        """``kind="whirl"``: measured and fitted whirl radius against time; ``"residual"``:
        the residual's x and y against time; returns the Axes."""
        if kind not in ("whirl", "residual"):
            raise ValueError(f"Fit.plot: kind = {kind!r}: one of whirl, residual")
        ax = axes_of(ax)
        s = self._series
        if not s:
            return ax
        unit = self["fit"]["rms_residual_unit"]
        k = 1e6 if unit == "m" else 1.0
        lab = "µm" if unit == "m" else unit
        t = s["t"]
        if kind == "residual":
            ax.plot(t, s["residual"].real * k, lw=0.5, label="x")
            ax.plot(t, s["residual"].imag * k, lw=0.5, label="y")
            ax.set_ylabel(f"residual [{lab}]")
        else:
            off = complex(*self["nuisance"]["offset"]["value"])
            ax.plot(t, np.abs(s["measured"] - off) * k, lw=0.6, label="measured")
            ax.plot(t, np.abs(s["model"] - off) * k, lw=0.9, label="fitted model")
            ax.set_ylabel(f"whirl radius [{lab}]")
        ax.set_xlabel("time [s]")
        ax.legend(loc="upper right")
        return ax


def _dump_toml(doc, prefix: str = "") -> str:
    """A plain TOML writer for a scene document (tables, arrays of tables, numbers, strings,
    booleans, arrays): the fallback when the template's text cannot be edited in place."""
    import json

    def val(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, (int, float)):
            return repr(v) if not isinstance(v, float) else f"{v:.12g}" if "e" in f"{v:.12g}" \
                or "." in f"{v:.12g}" else f"{v:.12g}.0"
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, list):
            return "[" + ", ".join(val(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k} = {val(x)}" for k, x in v.items()) + "}"
        raise TypeError(type(v))

    lines, subs = [], []
    for k, v in doc.items():
        if isinstance(v, dict) and not prefix == "__inline__":
            subs.append((k, v))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            subs.append((k, v))
        else:
            lines.append(f"{k} = {val(v)}")
    out = "\n".join(lines) + ("\n" if lines else "")
    for k, v in subs:
        name = f"{prefix}.{k}" if prefix else k
        if isinstance(v, list):
            for item in v:
                out += f"\n[[{name}]]\n" + _dump_toml(item, name).split("\n[", 1)[0]
        else:
            out += f"\n[{name}]\n" + _dump_toml(v, name)
    return out
