"""The rotor's angle from what a lab table has: encoder angle, keyphasor pulses, tachometer.

Order of preference: an ``angle`` channel (encoder), a ``keyphasor`` (pulses
-> angle by a spline, :func:`dsp.speed.angle_from_pulses`), a ``speed``
channel (tachometer: speed only, the angle has no mark).  None of them: the
identification estimates the speed from the 1X line itself (flagged).
"""
from __future__ import annotations

import numpy as np

__all__ = ["rotor_angle_of"]


def _binary_pulses(t, v):
    """A 0/1 flag column (1 on the sample of each pulse): the first sample of each run of 1s."""
    on = v > 0.5
    start = np.flatnonzero(on & ~np.concatenate(([False], on[:-1])))
    return t[start]


def rotor_angle_of(table, notes: list):
    """``(RotorAngle or None, description)`` of a :class:`stand.lab.table.LabTable`.

    Raises
    ------
    stand.lab.table.TableError
        A pulse channel without usable pulses (names the column).
    """
    from dsp.errors import SignalError
    from dsp.pulse_timing import pulse_timing_std, retime_pulses
    from dsp.pulses import debounced
    from dsp.speed import angle_from_pulses, angle_from_speed, pulse_times, repair_pulses
    from dsp.speed_channels import angle_from_encoder

    from stand.lab.table import TableError

    t, sig, cols = table.t, table.signals, table.columns
    if "angle" in sig:
        try:
            ra = angle_from_encoder(t, sig["angle"])
        except SignalError as exc:
            raise TableError(f"{table.path}: angle column {cols['angle'].column!r}: {exc}") from None
        return ra, f"rotor angle from column {cols['angle'].column!r}"
    if "keyphasor" in sig:
        v, spec = sig["keyphasor"], cols["keyphasor"]
        try:
            if np.all(np.isin(v[np.isfinite(v)], (0.0, 1.0))):
                p = _binary_pulses(t, v)
                how = "0/1 flags"
            else:
                p = pulse_times(t, v, threshold=spec.threshold, name=f"column {spec.column!r}")
                how = "leading edges"
            p, merged = debounced(p)
            if merged:
                notes.append(f"keyphasor column {spec.column!r}: {merged} contact-bounce pulse(s) "
                             "merged into the edge before them (hold-off: 0.4 of the local "
                             "once-per-revolution period)")
            p, added, dropped = repair_pulses(p)
            if added or dropped:
                notes.append(f"keyphasor column {spec.column!r}: {added} missed pulse(s) filled in, "
                             f"{dropped} double pulse(s) dropped (intervals judged against their "
                             "neighbours; a pulse narrower than the sample interval is sometimes "
                             "not sampled)")
            if p.size < 3:
                raise SignalError(f"column {spec.column!r}: {p.size} pulse(s); the rotor angle "
                                  "needs at least 3 (two revolutions)")
            timing = None
            if how == "leading edges":      # the edge is a function of the angle, not of time
                p = retime_pulses(t, v, p, threshold=spec.threshold)
                timing = pulse_timing_std(t, v, p, threshold=spec.threshold)
            ra = angle_from_pulses(t, p, timing_std_s=timing)
        except SignalError as exc:
            msg = str(exc)
            if spec.column not in msg:
                msg = f"column {spec.column!r}: {msg}"
            raise TableError(f"{table.path}: keyphasor {msg}") from None
        return ra, (f"keyphasor column {spec.column!r} ({how}, {p.size} pulses, "
                    f"{p[0]:.6g}-{p[-1]:.6g} s)")
    if "speed" in sig:
        w = sig["speed"]
        if not np.all(np.isfinite(w)):
            raise TableError(f"{table.path}: speed column {cols['speed'].column!r} has NaN cells")
        ra = angle_from_speed(t, w)
        return ra, (f"tachometer column {cols['speed'].column!r} ({cols['speed'].unit}): speed "
                    f"only, no reference mark (no unbalance angle)")
    return None, "no speed channel"
