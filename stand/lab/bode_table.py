"""Bode / polar tables: the steady 1X vector against the speed, as rotor kits' software
and portable analysers export it (``rpm, amp_1x_um, phase_1x_deg``).

Roles ``speed``, ``amplitude`` (any vibration unit: displacement, velocity,
acceleration, with ``pk``, ``pk-pk`` or ``rms``; volts with a sensitivity) and ``phase``
(deg, rad); no time column.  The phase convention (lag or lead) is read from the table
itself: through a resonance the response lags more and more behind the unbalance, so
a phase column that grows is a lag.  :func:`read_bode_table` returns the speeds [rad/s]
and the 1X displacement vectors [m, peak] (velocity / acceleration divided by (i w)^k).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from stand.lab.recording_map import MapError, RecordingMap
from stand.lab.units import AMPLITUDE, VIBRATION, UnitError

__all__ = ["BodeTable", "read_bode_table", "is_bode_map"]

MAX_VALUE = 1e12   #: a speed, amplitude or phase beyond this in its column's unit is no reading


@dataclass
class BodeTable:
    """A Bode table in SI.

    Attributes
    ----------
    path : str
    speed_rad_s : ndarray
    vector_m : ndarray (complex)
        1X displacement, peak, phase with the response lagging as the angle decreases.
    quantity : str
        What the amplitude column measures (``length``, ``velocity``, ``acceleration``).
    phase_convention : str
        ``lag`` or ``lead`` (as detected).
    columns : dict
    rows : int
    recording_map : RecordingMap
    """

    path: str
    speed_rad_s: np.ndarray
    vector_m: np.ndarray
    quantity: str
    phase_convention: str
    columns: dict
    rows: int
    recording_map: RecordingMap = field(default_factory=RecordingMap)

    def input_summary(self) -> dict:
        return {"kind": "bode table", "columns": {r: {"column": c.column, "unit": c.unit}
                                                  for r, c in self.columns.items()},
                "vibration_quantity": self.quantity, "phase_convention": self.phase_convention,
                "rows_used": self.rows, "map": self.recording_map.source}


def is_bode_map(rmap) -> bool:
    """A recording map of a Bode table: it maps ``amplitude``."""
    return rmap is not None and "amplitude" in rmap.columns


def read_bode_table(path, rmap: RecordingMap) -> BodeTable:
    """Read a Bode table (module docstring); :class:`stand.lab.table.TableError` naming the
    column otherwise."""
    import pandas as pd

    from stand.lab.formats import resolve_column
    from stand.lab.table import TableError, read_frame

    label = str(path)
    df, _ = read_frame(path, rmap)
    names = list(df.columns)
    cols, sig = {}, {}
    for role in ("speed", "amplitude", "phase"):
        if role not in rmap.columns:
            raise TableError(f"{label}: a Bode table needs the roles speed, amplitude and phase; "
                             f"the map {rmap.source} names no {role} (columns: {', '.join(names)})")
        spec = rmap.columns[role]
        full = resolve_column(spec.column, names, grouped=bool(df.attrs.get("grouped")))
        if full is None:
            raise TableError(f"{label}: {role} = column {spec.column!r} is not in the table; its "
                             f"columns: {', '.join(names)}")
        if spec.unit is None:
            raise TableError(f"{label}: {role} = column {spec.column!r}: no unit; give it, e.g. "
                             f"--columns {role}={spec.column}[{ {'speed': 'rpm', 'amplitude': 'um', 'phase': 'deg'}[role]}]")
        try:
            k = spec.si_factor(f"{role} = column {spec.column!r}")
        except (UnitError, MapError) as exc:
            raise TableError(f"{label}: {exc}") from None
        raw = df[full]
        num = pd.to_numeric(raw, errors="coerce").to_numpy(float)
        text = np.isnan(num) & raw.notna().to_numpy() & (raw.astype(str).str.strip() != "").to_numpy()
        if (text | (np.abs(num) > MAX_VALUE)).any():
            i = int(np.argmax(text | (np.abs(num) > MAX_VALUE)))
            raise TableError(f"{label}: {role} = column {spec.column!r} ({spec.unit}), data row "
                             f"{i + 1}: {str(raw.iloc[i])[:40]!r} is " + (
                                 "not a number" if text[i] else f"above {MAX_VALUE:.0e}: not a reading"))
        cols[role], sig[role] = spec, num * k
    ok = np.isfinite(sig["speed"]) & np.isfinite(sig["amplitude"]) & np.isfinite(sig["phase"])
    if ok.sum() < 6:
        raise TableError(f"{label}: {int(ok.sum())} complete rows of speed, amplitude and phase; "
                         "the modal fit needs at least 6")
    w, a, ph = (sig[r][ok] for r in ("speed", "amplitude", "phase"))
    o = np.argsort(w)
    w, a, ph = w[o], a[o], np.unwrap(ph[o])
    conv = cols["amplitude"].convention()
    a = a * (AMPLITUDE[conv] if conv else 1.0)            # to peak
    q = cols["amplitude"].quantity()
    k = VIBRATION[q]
    lag = ph[-1] > ph[0]
    z = a * np.exp(-1j * ph if lag else 1j * ph) / (1j * w) ** k
    return BodeTable(path=label, speed_rad_s=w, vector_m=z, quantity=q,
                     phase_convention="lag" if lag else "lead", columns=cols, rows=int(ok.sum()),
                     recording_map=rmap)
