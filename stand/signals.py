"""Signal helpers on one recorded run, shared by the reports (and meant for ``stand analyze``).

Arrays of one record: time ``t`` [s], shaft displacement ``x``, ``y`` [m],
unwrapped rotor angle ``phi`` [rad] and rotor speed ``speed`` [rad/s].  These
helpers orchestrate :mod:`dsp` the way every report needs it: where the final
constant-speed stretch starts, the per-revolution 1X vectors of a run-up, and
the free decay of a non-spinning rotor with the failure as a note instead of
an exception.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["steady_start", "forward_start", "per_revolution", "plane_free_decay"]

TWO_PI = 2.0 * math.pi


def steady_start(t, speed, rtol: float = 1e-3) -> int:
    """Index where the final stretch of constant speed starts.

    Parameters
    ----------
    t : ndarray
        Sample times [s].
    speed : ndarray or None
        Rotor speed [rad/s] at the samples; None: no speed, returns 0.
    rtol : float
        Constant means within ``rtol`` of the last speed (default 0.1 %) [-].

    Returns
    -------
    int
        The first sample of the stretch (``t.size - 1`` when only the last
        sample qualifies).
    """
    if speed is None:
        return 0
    ref = speed[-1]
    ok = np.abs(speed - ref) <= rtol * max(abs(ref), 1e-12)
    i = t.size - 1
    while i > 0 and ok[i - 1]:
        i -= 1
    return i


def forward_start(phi) -> int:
    """First index from which the rotor angle ``phi`` [rad] increases strictly to the end."""
    bad = np.nonzero(np.diff(phi) <= 0)[0]
    return 0 if bad.size == 0 else int(bad[-1] + 1)


def per_revolution(t, x, y, phi):
    """The 1X response revolution by revolution (dsp order tracking).

    Parameters
    ----------
    t, x, y : ndarray
        Times [s] and shaft displacements [m].
    phi : ndarray
        Unwrapped rotor angle [rad]; only its final strictly increasing part is used.

    Returns
    -------
    tuple of ndarray or None
        Revolution mid-times [s], speeds [rad/s] and complex 1X vectors
        x + i y [m]; None when fewer than 8 samples turn forward.

    Raises
    ------
    dsp.errors.SignalError
        Fewer than two whole revolutions.
    """
    from dsp import unbalance as ub

    i0 = forward_start(phi)
    if t.size - i0 < 8:
        return None
    sc = ub.synchronous_component(t[i0:], x[i0:], y[i0:], rotor_angle=phi[i0:], min_revolutions=2)
    ph = phi[i0:]
    j0 = math.ceil(ph[0] / TWO_PI - 1e-12)
    j1 = math.floor(ph[-1] / TWO_PI + 1e-12)
    tb = np.interp(TWO_PI * np.arange(j0, j1 + 1), ph, t[i0:])
    return 0.5 * (tb[1:] + tb[:-1]), TWO_PI / np.diff(tb), np.asarray(sc.per_revolution_m)


def plane_free_decay(t, x, y, notes: list):
    """Natural frequency and damping from the free decay of a rotor that does not turn.

    A plane decay is real: the channel that moves most (``x`` or ``y``) is
    fitted by :func:`dsp.frequency.free_decay` (matrix pencil + least
    squares); a complex fit of a real signal would see two counter-rotating
    lines.

    Parameters
    ----------
    t : ndarray
        Sample times [s].
    x, y : ndarray
        Shaft displacements [m].
    notes : list of str
        Receives ``"free decay: <reason>"`` when the fit fails.

    Returns
    -------
    object or None
        The fit (``natural_frequency_hz`` [Hz], ``natural_frequency_hz_std``
        [Hz], ``damping_ratio`` [-], ``damping_ratio_std`` [-]), or None when
        the record does not allow it (the reason is in ``notes``).
    """
    from dsp import frequency as fq
    from dsp.errors import SignalError

    try:
        return fq.free_decay(t, x if np.std(x) >= np.std(y) else y)
    except SignalError as exc:
        notes.append(f"free decay: {exc}")
        return None
