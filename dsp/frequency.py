"""Natural frequency, damping and spectral lines from signals.

Plain arrays in, frozen dataclasses with standard uncertainties out.  Units are
SI; field names say whether a frequency is in Hz or rad/s.

Contents
--------
free_decay
    Matrix pencil (Hua & Sarkar 1990) on the decimated record, then a
    nonlinear least-squares refinement on all samples whose Jacobian gives the
    standard uncertainties.
photogate_period, frequency_from_crossings
    The pulse-counter / photo-gate method (period from threshold crossings):
    an independent second estimate (ch5_multiball.md "Pulse counter").
resonance_from_runup
    Resonance peak of a run-up/run-down amplitude curve with the sweep-rate
    lag removed (papers_001_003_004.md §4.3 and §5.4).
refine_frequencies
    NAFF-style (Laskar) refinement of complex-exponential components followed
    by a joint maximum-likelihood polish (:mod:`dsp.lines`, the one line
    estimator of ``dsp``: the quasi-periodic decomposition uses it too).

Aliasing
--------
A line above the Nyquist frequency folds back into the band and *cannot* be
recognised from the samples alone.  What can be detected is a line near the
band edge (where folded lines land when they are only slightly above Nyquist):
``free_decay`` and ``refine_frequencies`` raise :class:`SignalError` when an
identified frequency lies above ``max_band_fraction`` (default 0.9) of the
Nyquist frequency.  Sample at least ~5x the highest expected frequency.

The estimators live in one module per method (:mod:`dsp.decay`,
:mod:`dsp.crossings`, :mod:`dsp.runup`, :mod:`dsp.lines`); this module
re-exports their public names.
"""
from __future__ import annotations

from .crossings import CrossingFrequency, crossing_times, frequency_from_crossings, photogate_period
from .decay import FreeDecay, free_decay
from .lines import Components, crlb_frequency_std, refine_frequencies
from .runup import U_STAR, RunupResonance, resonance_from_runup, sweep_lag_rad_s

__all__ = [
    "FreeDecay", "free_decay",
    "CrossingFrequency", "photogate_period", "frequency_from_crossings", "crossing_times",
    "RunupResonance", "resonance_from_runup", "sweep_lag_rad_s", "U_STAR",
    "Components", "refine_frequencies", "crlb_frequency_std",
]
