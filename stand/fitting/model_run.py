"""One simulation of the fit: the scene with trial values, driven as the record was, read
at the record's samples in the sensors' own quantity.

:class:`Setup` is everything a simulation needs, small and picklable (the scene document,
the record's sample times and drive, the sensors' plane and quantity), so that the
finite-difference columns of the Jacobian run on a process pool or a Dask cluster
(:func:`model_channel` is the mapped function).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Optional

import numpy as np

from stand.fitting.paths import FitError, scene_with

__all__ = ["Setup", "model_channel", "NUISANCE"]

#: the shaft's initial state at the record's first sample, fitted beside the scene values
#: (the record rarely starts at rest: its first keyphasor pulse comes after the run-up began)
NUISANCE = ("initial.x", "initial.y", "initial.vx", "initial.vy")
NUISANCE_UNITS = ("m", "m", "m/s", "m/s")


@dataclass(frozen=True)
class Setup:
    """What a simulation of the fit needs (module docstring).

    Attributes
    ----------
    doc : dict                 the template scene's TOML document
    stem : str                 the scene's name
    paths : tuple of str       the free scene values, in the order of the parameter vector
    times : ndarray (N,)       the samples to fit [s from the record's first sample, where the
                               simulation starts]
    drive : stand.fitting.record.RecordedDrive or None
        The record's drive (None: the scene's own programme).
    order : int                0 displacement, 1 velocity, 2 acceleration
    plane : str or None        the sensors' plane (None: the scene's main plane)
    rtol, atol : float         the integrator's tolerances
    nuisance : bool            the parameter vector goes on with the initial shaft state
    lead_in : bool             ... and ends with where the drive's lead-in starts from rest
    """

    doc: dict
    stem: str
    paths: tuple
    times: np.ndarray
    drive: Optional[object]
    order: int
    plane: Optional[str]
    rtol: float = 1e-9
    atol: float = 1e-11
    nuisance: bool = True
    lead_in: bool = False

    def scene(self, theta, end: Optional[float] = None):
        """The Scene of the parameter vector ``theta`` (free values in their file units, then
        the initial shaft state [m, m/s], then the lead-in's start [s]), driven by the
        record, lasting to ``end`` [s]."""
        from stand.scene.model import InitialState, SpeedDrive

        k = len(self.paths)
        sc = scene_with(self.doc, dict(zip(self.paths, theta[:k])), self.stem)
        if sc.kind == "book":
            raise FitError("a [weight_model] scene runs the book's own equations in its own "
                           "time scale; fit its rotor-family form instead")
        duration = float(self.times[-1] if end is None else end)
        rep = {"instruments": {}, "run": dataclasses.replace(
            sc.run, duration=duration, sample_rate=1.0 / duration,
            rtol=min(sc.run.rtol, self.rtol), atol=min(sc.run.atol, self.atol))}
        if self.drive is not None:
            prog, phi0 = self.drive.full(float(theta[-1]) if self.lead_in else None)
            rep["drive"] = SpeedDrive(programme=prog, initial_angle=phi0)
        if self.nuisance:
            x, y, vx, vy = (float(v) for v in theta[k:k + 4])
            rep["initial"] = InitialState(x=x, y=y, vx=vx, vy=vy)
        return dataclasses.replace(sc, **rep)


def _stencils(times, order, end):
    """The samples to fit (to ``end``) and, for a velocity or acceleration, the three times
    around each one whose model values give its derivative (t - h, t, t + h; one-sided at
    the record's ends): ``(t, grid, stencil (3, n) indices into grid, offsets (3, n))``."""
    t = times if end is None else times[times <= end + 1e-12]
    if order == 0:
        return t, t, None, None
    h = 0.05 * float(np.median(np.diff(times))) if times.size > 1 else 1e-4
    off = np.tile(np.array([-h, 0.0, h])[:, None], (1, t.size))
    off[:, t - h < 0.0] += h                       # the first sample: t, t + h, t + 2h
    off[:, t + h > t[-1]] -= h                     # the last: t - 2h, t - h, t
    pts = t[None, :] + off
    grid = np.unique(pts)
    return t, grid, np.searchsorted(grid, pts), off


def _derivative(z, off, order):
    """d^order z / dt^order at offset 0 from three values ``z`` (3, n) at ``off`` (3, n)
    (Lagrange's three-point formulas on any spacing)."""
    a, b, c = off
    if order == 1:
        wa = (0 - b + 0 - c) / ((a - b) * (a - c))
        wb = (0 - a + 0 - c) / ((b - a) * (b - c))
        wc = (0 - a + 0 - b) / ((c - a) * (c - b))
    else:
        wa = 2.0 / ((a - b) * (a - c))
        wb = 2.0 / ((b - a) * (b - c))
        wc = 2.0 / ((c - a) * (c - b))
    return wa * z[0] + wb * z[1] + wc * z[2]


def model_channel(setup: Setup, theta, end: Optional[float] = None) -> np.ndarray:
    """The model's sensor signal x + i y at the record's samples up to ``end`` [s], in the
    record's quantity (SI); NaN where the run stopped early."""
    from stand.integrate.simulate import simulate

    sc = setup.scene(np.asarray(theta, float), end)
    t, grid, idx, off = _stencils(setup.times, setup.order, end)
    planes, _ = simulate(sc, extra_times=grid, planes_only=True)
    plane = setup.plane or sc.main_plane
    if plane not in planes:
        raise FitError(f"the record's sensors look at plane {plane!r}; the scene's planes: "
                       f"{', '.join(planes)}")
    xy = planes[plane]
    zg = np.full(grid.size, np.nan + 0j)
    zg[:xy.shape[0]] = xy[:, 0] + 1j * xy[:, 1]
    if setup.order == 0:
        return zg
    return _derivative(zg[idx], off, setup.order)
