"""The report of ``stand fit``: a view of a :class:`stand.fitting.result.Fit` (it computes nothing).

The page opens with the verdict -- does the fitted model explain the record (chi^2/dof, where
it does not), which values the record determines --, then the fitted values with their ±
(rounded to it), the theory-against-experiment table (each quantity measured in the record
and predicted by the fitted model, the difference in sigma), the correlations, and the
overlays: measured and fitted whirl radius against time, the residual against time, the 1X
amplitude against speed.
"""
from __future__ import annotations

import html
from typing import Optional

import numpy as np

from stand.reports.html import figure_png, write_report
from stand.io.numbers import plain, with_uncertainty

__all__ = ["fit_report", "fit_figures"]


def fit_figures(fit) -> dict:
    """``{caption: PNG data URI}`` of a Fit's overlays (its own plot method, no backend)."""
    from stand.io.figures import figure_and_axes

    out = {}
    s = fit._series
    if not s:
        return out
    for kind, cap in (("whirl", "whirl radius, measured and fitted model, against time"),
                      ("residual", "residual (record minus fitted model) against time")):
        fig, ax = figure_and_axes(None, figsize=(8, 3.2))
        fit.plot(ax=ax, kind=kind)
        out[cap] = figure_png(fig)
    if s.get("speed") is not None:
        fig, ax = figure_and_axes(None, figsize=(8, 3.2))
        _one_x(ax, s, fit)
        out["1X amplitude against speed, measured and fitted model"] = figure_png(fig)
    return out


def _one_x(ax, s, fit) -> None:
    """1X amplitude per revolution against speed (order tracking on the measured angle)."""
    t, w = s["t"], s["speed"]
    phi = np.cumsum(np.concatenate([[0.0], 0.5 * (w[1:] + w[:-1]) * np.diff(t)]))
    rev = np.floor(phi / (2 * np.pi)).astype(int)
    unit = fit["fit"]["rms_residual_unit"]
    k = 1e6 if unit == "m" else 1.0
    for key, lab in (("measured", "measured"), ("model", "fitted model")):
        z = s[key] * np.exp(-1j * phi)
        sums = np.bincount(rev, weights=z.real) + 1j * np.bincount(rev, weights=z.imag)
        cnt = np.bincount(rev)
        ok = cnt > 0
        sp = np.bincount(rev, weights=w)[ok] / cnt[ok] / (2 * np.pi)
        ax.plot(sp, np.abs(sums[ok] / cnt[ok]) * k, lw=0.8, label=lab)
    ax.set_xlabel("speed [rev/s]")
    ax.set_ylabel(f"1X amplitude [{'µm' if unit == 'm' else unit}]")
    ax.legend(loc="upper right")


def _value(d) -> str:
    if not d["identifiable"]:
        return f"{plain(d['value'], d['unit'], sig=6)} (not identifiable)"
    return with_uncertainty(d["value"], d["std"], d["unit"], resolution=False)


def _body(doc) -> str:
    e = html.escape
    f = doc["fit"]
    rows = "".join(f"<tr><td><code>{e(p)}</code></td><td class='num'>{e(_value(d))}</td>"
                   f"<td class='num'>{e(plain(d['start'], sig=6))}</td>"
                   f"<td>{'yes' if d['identifiable'] else 'no'}</td>"
                   f"<td>{e(d.get('note') or '')}</td></tr>" for p, d in doc["parameters"].items())
    parts = ["<h2 class='first'>Fitted values</h2><table><tr><th>scene value</th><th>fitted "
             "(1 sigma)</th><th>template</th><th>identifiable</th><th>note</th></tr>"
             + rows + "</table>"]
    cmp_rows = []
    for r in doc.get("comparison") or []:
        m = "n/a" if r.get("measured") is None else with_uncertainty(
            r["measured"], r.get("measured_std"), r["unit"], resolution=False)
        p = "n/a" if r.get("predicted") is None else with_uncertainty(
            r["predicted"], r.get("predicted_std"), r["unit"], resolution=False)
        ds = r.get("difference_sigma")
        cmp_rows.append(f"<tr><td>{e(r['quantity'])}</td><td class='num'>{e(m)}</td>"
                        f"<td class='num'>{e(p)}</td><td class='num'>"
                        f"{'' if ds is None else f'{ds:+.1f}'}</td><td>{e(r.get('note') or '')}"
                        "</td></tr>")
    if cmp_rows:
        parts.append("<h2>Theory against experiment</h2><table><tr><th>quantity</th><th>measured"
                     "</th><th>fitted model</th><th>difference [sigma]</th><th>how</th></tr>"
                     + "".join(cmp_rows) + "</table>")
    corr = doc.get("correlation") or {}
    if corr.get("paths") and len(corr["paths"]) > 1:
        head = "".join(f"<th><code>{e(p)}</code></th>" for p in corr["paths"])
        body = "".join(f"<tr><th><code>{e(p)}</code></th>" + "".join(
            f"<td class='num'>{v:+.3f}</td>" for v in row) + "</tr>"
            for p, row in zip(corr["paths"], corr["matrix"]))
        parts.append(f"<h2>Correlations</h2><table><tr><th></th>{head}</tr>{body}</table>")
    segs = "".join(f"<tr><td class='num'>{plain(s_['start_s'])} – {plain(s_['end_s'])}</td>"
                   f"<td class='num'>{plain(s_['chi2_dof'], sig=3)}</td></tr>"
                   for s_ in f.get("segments") or [])
    parts.append(f"<h2>The fit</h2><p>chi2/dof {plain(f['chi2_dof'])}; residual RMS "
                 f"{e(plain(f['rms_residual'], f['rms_residual_unit']))}, noise "
                 f"{e(plain(f['noise_std'], f['noise_std_unit'], sig=3))}; {f['samples']} samples, "
                 f"{f['simulations']} simulations in {plain(f['wall_time_s'], 's', sig=2)}; rotor angle from "
                 f"{e(str(f.get('rotor_angle')))}.</p><table><tr><th>time [s]</th>"
                 f"<th>chi2/dof</th></tr>{segs}</table>")
    notes = "".join(f"<li>{e(n)}</li>" for n in doc.get("notes") or [])
    if notes:
        parts.append(f"<h2>Notes</h2><ul>{notes}</ul>")
    return "\n".join(parts)


def _banner(doc) -> dict:
    f = doc["fit"]
    bad = [p for p, d in doc["parameters"].items() if not d["identifiable"]]
    ok = f.get("explained", False)
    lines = [f"record {doc['data']}, template {doc['scene']}",
             f"chi2/dof {plain(f['chi2_dof'], sig=3)}"
             + ("" if ok else f": the model does not explain the record "
                f"({f.get('unexplained_where', 'all along')})")]
    if bad:
        lines.append("not identifiable from this record: " + ", ".join(bad))
    return {"status": "pass" if ok and not bad else "fail" if not ok else "info",
            "headline": "the fitted model explains the record" if ok else
            "the fitted model does not explain the record", "lines": lines}


def fit_report(fit, *, html_path=None, json_path=None, figures: Optional[dict] = None) -> dict:
    """Write the HTML (and JSON) report of a Fit; return the plain JSON document."""
    figs = fit_figures(fit) if figures is None else figures
    doc = fit.to_dict()

    def body(plain):
        out = _body(plain)
        for cap, uri in figs.items():
            out += (f"<figure><img alt='{html.escape(cap)}' src='{uri}'>"
                    f"<figcaption>{html.escape(cap)}</figcaption></figure>")
        return out

    return write_report("stand fit: the model against the experiment", doc, html_path=html_path,
                        json_path=json_path, figures=figs, banner=_banner(doc), body=body)
