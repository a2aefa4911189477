"""The summary of a folder of balancing reports: one row per recording, failures first,
each linked to its own report (``stand report FOLDER -o DIR/ --summary S.csv``)."""
from __future__ import annotations

import html
from pathlib import Path

__all__ = ["order_failures_first", "write_summary_page"]


def _rank(row) -> int:
    """0: the file could not be reported, 1: ISO grade failed, 2: no verdict, 3: passed."""
    if row.get("status") != "ok":
        return 0
    passed = row.get("iso_passed")
    if passed is False or passed == 0:
        return 1
    return 3 if passed is True or passed == 1 else 2


def order_failures_first(df):
    """The summary table sorted: unreadable files, failed grades, no verdict, passed (then by
    file name)."""
    rank = [_rank(r) for r in df.to_dict("records")]
    return df.assign(_rank=rank).sort_values(["_rank", "file"]).drop(columns="_rank") \
        .reset_index(drop=True)


def write_summary_page(df, html_dir, grade: float) -> Path:
    """``html_dir/index.html``: the folder's verdicts, failures first, each row linked to the
    file's report; written atomically.  Returns its path."""
    from stand.io.atomic import write_text
    from stand.reports.html import render_html
    from stand.io.numbers import plain

    d = Path(html_dir)
    rows = []
    counts = {0: 0, 1: 0, 2: 0, 3: 0}
    for r in order_failures_first(df).to_dict("records"):
        k = _rank(r)
        counts[k] += 1
        verdict = {0: "could not be reported", 1: "FAIL", 2: "no verdict", 3: "PASS"}[k]
        cls = {0: "fail", 1: "fail", 2: "", 3: "pass"}[k]
        name = Path(str(r["file"])).name
        rep = str(r.get("report") or "")
        link = (f"<a href='{html.escape(Path(rep).name)}'>{html.escape(name)}</a>"
                if rep else html.escape(name))
        U = r.get("residual_unbalance_gmm")
        G = r.get("achieved_grade_mm_s")
        why = r.get("error") or ""
        rows.append(f"<tr><td>{link}</td><td class='{cls}'>{verdict}</td>"
                    f"<td class='num'>{html.escape(plain(U, 'g·mm') if U == U and U is not None else '—')}</td>"
                    f"<td class='num'>{html.escape(plain(G, 'mm/s') if G == G and G is not None else '—')}</td>"
                    f"<td class='num'>{int(r.get('warnings') or 0) if r.get('warnings') == r.get('warnings') else 0}</td>"
                    f"<td>{html.escape(str(why))}</td></tr>")
    n = sum(counts.values())
    bad = counts[0] + counts[1]
    banner = {"status": "fail" if bad else ("pass" if counts[3] == n else "info"),
              "headline": (f"{bad} of {n} recordings failed or could not be reported" if bad
                           else f"All {n} recordings pass G{plain(grade, sig=2)}" if counts[3] == n
                           else f"{counts[3]} of {n} recordings pass G{plain(grade, sig=2)}"),
              "lines": [f"failed grade: {counts[1]}; unreadable: {counts[0]}; no verdict: "
                        f"{counts[2]}; passed: {counts[3]}"]}
    body = ("<table><tr><th>Recording (its report)</th><th>Verdict</th><th>Residual unbalance</th>"
            "<th>Achieved grade</th><th>Warnings</th><th>Error</th></tr>" + "".join(rows) + "</table>")
    path = d / "index.html"
    write_text(path, render_html(f"Balancing reports: {d.name}", {}, banner=banner, body=body))
    return path
