"""One rule for every benchmark: a peer's answer is checked before its time is shown.

A benchmark compares the time of contenders that compute the same thing.  A fast
peer with a wrong answer is not a faster peer, so each one's error against the
benchmark's reference is checked first (:func:`check_peer`); a peer whose error
exceeds its tolerance is shown as ``invalid (error X > tolerance Y)`` in place of
its time, and no ratio is computed for it::

    peer = check_peer("numbalsoda LSODA", error=10.6, tolerance=3e-7)
    peer.valid                         # False: do not time it
    peer.cells("6.62 ms", "1.26")      # ['invalid (error 10.6 > tolerance 3e-07)', '-']

benchmarks/ is not a package: the scripts import this file as ``_peers`` (their
own directory is on ``sys.path`` when run as ``python benchmarks/bench_x.py``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Peer", "check_peer"]


@dataclass(frozen=True)
class Peer:
    """A contender's answer checked against the reference.

    Attributes
    ----------
    name : str
        The contender, as printed.
    error : float
        Its error against the benchmark's reference, in the benchmark's unit
        (NaN or inf: no usable answer).
    tolerance : float
        Largest error at which its time is still comparable, same unit.
    """

    name: str
    error: float
    tolerance: float

    @property
    def valid(self) -> bool:
        """True when the error is finite and at most the tolerance."""
        return math.isfinite(self.error) and self.error <= self.tolerance

    @property
    def verdict(self) -> str:
        """``"ok"`` or ``"invalid (error X > tolerance Y)"``."""
        if self.valid:
            return "ok"
        return f"invalid (error {self.error:.3g} > tolerance {self.tolerance:.3g})"

    def cells(self, *timing: str, blank: str = "-") -> list:
        """The timing cells of the peer's row: as given when valid; else the verdict in the
        first cell and ``blank`` in the others (no time, no ratio)."""
        if self.valid:
            return list(timing)
        return [self.verdict] + [blank] * (len(timing) - 1)

    def line(self, timing: str) -> str:
        """``"name: timing"`` when valid, else ``"name: invalid (error X > tolerance Y)"``."""
        return f"{self.name}: {timing if self.valid else self.verdict}"


def check_peer(name: str, error: float, tolerance: float) -> Peer:
    """Check a peer's answer before its time is printed.

    Parameters
    ----------
    name : str
        The contender.
    error : float
        Its error against the reference (NaN is taken as inf: no answer).
    tolerance : float
        Largest acceptable error, same unit; must be > 0.

    Returns
    -------
    Peer
        ``.valid``, ``.verdict``, and the row helpers ``.cells`` / ``.line``.
    """
    if not tolerance > 0:
        raise ValueError(f"check_peer({name!r}): tolerance = {tolerance!r}: must be > 0")
    error = float(error)
    return Peer(name, math.inf if math.isnan(error) else error, float(tolerance))


def best_of(fn, repeats: int):
    """Best wall time [s] of ``repeats`` calls of ``fn()`` and the last result."""
    import time

    best, res = math.inf, None
    for _ in range(max(1, int(repeats))):
        t0 = time.perf_counter()
        res = fn()
        best = min(best, time.perf_counter() - t0)
    return best, res
