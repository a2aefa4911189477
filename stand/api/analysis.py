"""The API of the commands that read recordings and answer (``stand analyze``, ``report``,
``influence``, ``balance``, ``daq``, ``fit --report``): folders of recordings, two-plane balancing,
influence coefficients, DAQ exports.  Below :mod:`stand.cli`, above everything else."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

__all__ = ["is_batch", "analyze_many", "report_row", "report_many", "two_plane", "influence",
           "save_influence", "daq", "fit_report"]


def is_batch(source) -> bool:
    """Whether ``source`` names several recordings (a folder or a glob pattern)."""
    from stand.analysis.batch import is_batch_source

    return is_batch_source(str(source))


def _files_and_map(source, recording_map, columns):
    from stand.analysis.batch import expand_sources
    from stand.api import _recording_map

    return expand_sources(str(source)), _recording_map(recording_map, columns)


def analyze_many(source, output, *, grade: float = 6.3, service_speed_rpm: Optional[float] = None,
                 recording_map=None, columns: Optional[str] = None, workers: Optional[int] = None,
                 scheduler: Optional[str] = None, progress: bool = False):
    """:func:`stand.analyze` of every recording of a folder or glob, one row each, written to
    ``output`` (CSV, or Parquet for ``*.parquet``); a file that fails is a row with its error.
    ``grade`` [mm/s], ``service_speed_rpm`` [rpm], ``recording_map`` / ``columns`` as for
    :func:`stand.analyze`.  Returns the table (pandas, ``status`` "ok" or "error")."""
    from stand.analysis.batch import analyze_row, run_batch, write_table

    files, rmap = _files_and_map(source, recording_map, columns)
    df = run_batch(files, analyze_row, workers=workers, scheduler=scheduler, progress=progress,
                   grade=grade, service_speed_rpm=service_speed_rpm, recording_map=rmap)
    write_table(df, output)
    return df


def report_row(path, grade, service_speed_rpm, html_dir, recording_map=None) -> dict:
    """One row of a batch report (never raises): writes ``<stem>.html`` into ``html_dir``."""
    from stand.api import report

    row = {"file": path, "status": "ok", "error": "", "report": ""}
    try:
        out = str(Path(html_dir) / (Path(path).stem + ".html")) if html_dir else None
        doc = report(path, grade=grade, service_speed_rpm=service_speed_rpm, html_path=out,
                     recording_map=recording_map)
        row["report"] = out or ""
        q = doc.get("balancing_quality", {})
        for k, v in q.items():
            if isinstance(v, (int, float, str, bool)) or v is None:
                row[k] = v
        iso = q.get("iso_21940_11") or {}
        row["iso_passed"] = iso.get("passed")
        row["achieved_grade_mm_s"] = iso.get("achieved_grade_mm_s")
        row["warnings"] = len(doc.get("warnings", []))
    except Exception as exc:   # reported in the row: one bad file must not stop the batch
        row.update(status="error", error=f"{type(exc).__name__}: {exc}")
    return row


def report_many(source, summary, *, html_dir=None, grade: float = 6.3,
                service_speed_rpm: Optional[float] = None, recording_map=None,
                columns: Optional[str] = None, workers: Optional[int] = None,
                scheduler: Optional[str] = None, progress: bool = False):
    """The balancing report of every recording of a folder or glob: one HTML each in
    ``html_dir`` (when given) and one summary table ``summary`` (CSV or Parquet), failures
    first.  Returns ``(table, summary_page)``: the summary page (HTML, in ``html_dir``) or None."""
    from stand.analysis.batch import run_batch, write_table
    from stand.reports.batch_summary import order_failures_first, write_summary_page

    files, rmap = _files_and_map(source, recording_map, columns)
    df = run_batch(files, report_row, workers=workers, scheduler=scheduler, progress=progress,
                   grade=grade, service_speed_rpm=service_speed_rpm, html_dir=html_dir,
                   recording_map=rmap)
    df = order_failures_first(df)
    write_table(df, summary)
    page = write_summary_page(df, html_dir, grade) if html_dir else None
    return df, page


def two_plane(recording, tracks, *, grade: float = 6.3, service_speed_rpm: Optional[float] = None):
    """Two-plane balancing from a recording's two screens (their ``stand track --screen`` CSVs):
    :func:`stand.analysis.two_plane.two_plane`; a dict with one entry per plane in ``planes``."""
    from stand.analysis.two_plane import two_plane as _two_plane

    return _two_plane(recording, tracks, grade=grade, service_speed_rpm=service_speed_rpm)


def influence(reference, trials, trial_weights, sensors):
    """Influence-coefficient balancing from a reference recording and one trial recording per
    plane (:func:`stand.analysis.influence.influence_from_recordings`).

    ``trial_weights``: ``"PLANE:MASS_G:ANGLE_DEG:RADIUS_MM"`` per trial; ``sensors``: the
    measurement planes (names, or one comma-separated string)."""
    from stand.analysis.influence import influence_from_recordings

    if isinstance(sensors, str):
        sensors = [s.strip() for s in sensors.split(",") if s.strip()]
    return influence_from_recordings(reference, list(trials), list(trial_weights), list(sensors))


def save_influence(balance, path) -> None:
    """Write a field balancing's influence matrix (TOML) for the next machine of the type
    (``stand balance --influence``)."""
    from stand.analysis.field_influence_file import influence_toml
    from stand.io.atomic import write_text
    from stand.io.tomlfile import read_toml

    try:                          # the measuring job's runs as written (see influence_toml)
        runs = read_toml(balance["job"], what="job file", error=ValueError)[0].get("run")
    except (ValueError, OSError, TypeError):
        runs = None
    write_text(path, influence_toml(balance, runs))


def daq(recording, output, *, truth=None, offset_um=(35.0, -20.0), quantity: str = "displacement",
        bode: bool = False) -> dict:
    """A recording's probes, keyphasor and tachometer written as a lab DAQ export (CSV), or with
    ``bode`` the order-tracked 1X Bode table of a slow run-up, with its truth (JSON beside it,
    or ``truth``).  ``offset_um``: the x, y probes' DC offsets [µm]; ``quantity``:
    ``"displacement"``, ``"velocity"`` or ``"acceleration"``.  Returns the truth (dict).

    Raises :class:`stand.errors.NotApplicable` for a recording without the instruments."""
    from stand.lab.daq_export import daq_bode, daq_export

    if bode:
        return daq_bode(recording, output, truth_path=truth)
    return daq_export(recording, output, truth_path=truth, offset_um=offset_um, quantity=quantity)


def fit_report(fit, html_path) -> None:
    """Write the HTML report of a :func:`stand.fit` (values, theory against experiment,
    overlays)."""
    from stand.reports.fit_report import fit_report as _fit_report

    _fit_report(fit, html_path=html_path)
