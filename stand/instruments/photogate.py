"""Photo-element and pulse counter: the natural-frequency test (monograph 4.3.2, item 2.3).

The photo-element of the counter-stopwatch Elwro FPM-09 sits on the screen at
the undeflected laser spot.  The rotor (not spinning) is deflected and
released; the counter starts when the beam passes the photo-element the 1st
time and stops at the 3rd pass: one full period T, f0 = 1/T (digest ch5
section 6.1).

Model
-----
The detector is a strip of width ``size`` across the chosen screen axis,
centred at ``position`` (0 = the undeflected spot); the spot is a point (fold
the spot diameter into ``size``).  A pass is the spot entering the strip.  The
counter triggers either on the entry (``trigger = "enter"``, the real
photo-element's leading edge) or on the crossing of the strip's centre
(``"centre"``, an ideal detector).  Crossings are roots of the cubic Hermite
interpolant of the spot coordinate and its velocity
(:mod:`stand.instruments.timing`).

Bias of the leading-edge trigger: in a free decay with logarithmic decrement
``delta = 2 pi zeta / sqrt(1 - zeta^2)`` the 1st and 3rd passes enter at the
same edge, but the spot is slower at the 3rd, so the counted period is short by
about ``(size/2) / (2 pi A_1) * (exp(delta) - 1)`` of T, ``A_1`` the spot's
amplitude at the 1st pass -- e.g. 0.16 % for a 0.5 mm detector, a 10 mm
spot amplitude and zeta = 0.05; this is an imperfection of the real method
(:attr:`NaturalFrequencyTest.bias_estimate`).  The centre trigger has no such
bias (zero crossings of a damped oscillation are exactly T/2 apart).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from stand.scene.model import (Balancer, InitialState, Rotor, RunSettings, Scene, SceneError,
                     SpeedDrive)
from stand.scene.instrument_settings import (check_integer, check_number)
from stand.instruments.timing import MeasurementError, level_crossings, shaft_velocity
from stand.scene.gate_settings import (  # noqa: F401 (settings read with the scene)
    PhotoGate, PHOTOGATE_KEYS, TWO_PI, PATH)

__all__ = ["PhotoGate", "GatePasses", "NaturalFrequencyTest", "screen_coordinate",
           "gate_passes", "gate_crossings", "pulse_counter_period", "natural_frequency_test",
           "damped_period", "PHOTOGATE_KEYS"]


def screen_coordinate(X, Y, VX, VY, gate: PhotoGate) -> tuple[np.ndarray, np.ndarray]:
    """Spot coordinate along the gate's axis and its velocity.

    Parameters
    ----------
    X, Y : array_like
        Spot position on the screen [m] (plane-parallel model: optical gain
        times the shaft displacement).
    VX, VY : array_like
        Spot velocity [m/s].
    """
    ux, uy = gate.unit_vector
    X, Y, VX, VY = (np.asarray(a, float) for a in (X, Y, VX, VY))
    return ux * X + uy * Y, ux * VX + uy * VY


@dataclass
class GatePasses:
    """Events of the spot at the detector (times [s], increasing).

    Attributes
    ----------
    enter : times the spot enters the strip (either edge)
    leave : times it leaves the strip
    centre : times it crosses the strip's centre line
    """

    enter: np.ndarray
    leave: np.ndarray
    centre: np.ndarray


def gate_passes(t, X, dX, gate: PhotoGate) -> GatePasses:
    """Entry, exit and centre-crossing times of the spot at the detector.

    Parameters
    ----------
    t : array_like (N,)
        Sample times [s].
    X, dX : array_like (N,)
        Spot coordinate along the gate's axis [m] and its velocity [m/s]
        (:func:`screen_coordinate`).
    gate : PhotoGate
    """
    lo = gate.position - 0.5 * gate.size
    hi = gate.position + 0.5 * gate.size
    enter = np.sort(np.concatenate([level_crossings(t, X, dX, hi, -1),
                                    level_crossings(t, X, dX, lo, +1)]))
    leave = np.sort(np.concatenate([level_crossings(t, X, dX, hi, +1),
                                    level_crossings(t, X, dX, lo, -1)]))
    centre = level_crossings(t, X, dX, gate.position, 0)
    return GatePasses(enter=enter, leave=leave, centre=centre)


def gate_crossings(t, X, dX, gate: PhotoGate) -> np.ndarray:
    """Times [s] of the pulses the counter receives: the spot entering the
    detector (``trigger = "enter"``) or crossing its centre (``"centre"``).

    See :func:`gate_passes` for the parameters.  A spot that starts inside the
    detector gives no pulse until it has left and re-entered.
    """
    p = gate_passes(t, X, dX, gate)
    return p.enter if gate.trigger == "enter" else p.centre


def pulse_counter_period(crossing_times, start: int = 1, stop: int = 3) -> float:
    """Counter reading: time from the ``start``-th to the ``stop``-th pulse [s].

    The FPM-09 method (start 1, stop 3) measures one full period of an
    oscillation through the detector.

    Raises
    ------
    MeasurementError
        Fewer than ``stop`` pulses: the counter never stops.
    """
    c = np.asarray(crossing_times, float)
    if not (isinstance(start, (int, np.integer)) and isinstance(stop, (int, np.integer))
            and 1 <= start < stop):
        raise ValueError(f"pulse_counter_period: need integers 1 <= start < stop, got "
                         f"start = {start!r}, stop = {stop!r}")
    if c.size < stop:
        raise MeasurementError(f"the pulse counter got {c.size} pulse(s), needs {stop} to stop "
                               f"(the spot did not pass the detector {stop} times: too small a "
                               f"deflection, too much damping or too short a record)")
    return float(c[stop - 1] - c[start - 1])


def damped_period(stiffness: float, damping: float, mass: float) -> float:
    """Damped period 2 pi / (omega sqrt(1 - zeta^2)) of a mass on a spring [s].

    omega = sqrt(c/M), zeta = d / (2 sqrt(c M)) = H/2 with H = d/(omega M).

    Raises
    ------
    SceneError
        zeta >= 1 (no oscillation).
    """
    w = math.sqrt(stiffness / mass)
    zeta = damping / (2.0 * math.sqrt(stiffness * mass))
    if zeta >= 1.0:
        raise SceneError(f"supports damping = {damping!r} N*s/m: damping ratio zeta = "
                         f"{zeta:.4g} >= 1, the released rotor does not oscillate; no period")
    return TWO_PI / (w * math.sqrt(1.0 - zeta * zeta))


@dataclass
class NaturalFrequencyTest:
    """Result of :func:`natural_frequency_test`.

    Attributes
    ----------
    period : float            counter reading T [s]
    frequency : float         f0 = 1/T [Hz]
    true_period : float       damped period of the free decay 2 pi/(omega sqrt(1-zeta^2)) [s]
    true_frequency : float    1/true_period [Hz]
    undamped_frequency : float omega/(2 pi) [Hz]
    zeta : float              damping ratio (= H/2)
    relative_error : float    period/true_period - 1
    bias_estimate : float     expected relative error of the leading-edge trigger (module doc)
    pulses : ndarray          counter input times [s]
    scene : Scene             the test scene that was simulated
    trajectory : Trajectory
    """

    period: float
    frequency: float
    true_period: float
    true_frequency: float
    undamped_frequency: float
    zeta: float
    relative_error: float
    bias_estimate: float
    pulses: np.ndarray
    scene: Scene
    trajectory: object


def natural_frequency_test(scene: Scene, deflection: float, gate: Optional[PhotoGate] = None,
                           *, gain: float = 1.0, weights: str = "locked", periods: float = 3.0,
                           samples_per_period: int = 200, rtol: float = 1e-10,
                           atol: float = 1e-12) -> NaturalFrequencyTest:
    """The FPM-09 natural-frequency test on a scene's stand.

    The rotor is NOT spinning (prescribed speed 0), no excitation; the shaft is
    released from ``deflection`` along the gate's axis with zero velocity, the
    simulator runs ``periods`` damped periods with ``samples_per_period``
    samples each, the spot (``gain`` times the shaft displacement) passes the
    detector and the counter reads the time from the ``start_pass``-th to the
    ``stop_pass``-th pulse.

    What is measured: the free decay of the shaft with everything it carries.
    ``weights``:

    * ``"locked"`` (default): the weights' masses are fixed to the rotor (as
      in a real test with the weights clamped): a linear oscillator of mass
      M_Sigma, whose damped period is exactly ``true_period``;
    * ``"removed"``: the balancer is taken off (mass M only);
    * ``"free"``: the balancer as in the scene; the weights move under the
      shaft's acceleration, so the decay is not exactly that of a single
      oscillator and ``true_period`` (computed with M_Sigma) is a reference.

    The rotor's unbalance does not act (it needs rotation).

    Parameters
    ----------
    scene : Scene
    deflection : float
        Initial shaft displacement along the gate's axis [m] (non-zero).
    gate : PhotoGate, optional
        Default ``PhotoGate()``.
    gain : float
        Screen coordinate per shaft displacement (optical gain, > 0).
    weights : {"locked", "removed", "free"}
    periods : float
        Length of the record in damped periods (>= 1.5 for three passes).
    samples_per_period : int
        Sample rate of the simulation in samples per damped period (>= 20).
    rtol, atol : float
        Integration tolerances (dimensionless state, length scale 1 mm without
        weights).

    Raises
    ------
    SceneError
        Bad arguments; anisotropic supports with a "radial" axis off the X/Y
        axes; no oscillation (zeta >= 1); the released spot inside the detector.
    MeasurementError
        The counter does not stop (fewer pulses than ``stop_pass``).
    """
    from stand.integrate.simulate import simulate

    gate = gate if gate is not None else PhotoGate()
    check_number("deflection", deflection, "m")
    if deflection == 0:
        raise SceneError("deflection = 0: the rotor must be deflected before release (m)")
    check_number("gain", gain, "screen m per shaft m", gt=0)
    check_number("periods", periods, "damped periods", ge=1.5, le=1e4)
    check_integer("samples_per_period", samples_per_period, 20, 100_000)
    if weights not in ("locked", "removed", "free"):
        raise SceneError(f'weights = {weights!r}: must be one of "locked", "removed", "free"')
    ux, uy = gate.unit_vector
    s = scene.supports
    along_x, along_y = abs(uy) < 1e-12, abs(ux) < 1e-12
    aniso = (s.stiffness_x != s.stiffness_y) or (s.damping_x != s.damping_y)
    if aniso and not (along_x or along_y):
        raise SceneError(f"{PATH}.direction = {math.degrees(gate.direction):.6g}: the supports "
                         f"are anisotropic, deflect along X (0 deg) or Y (90 deg) for a single "
                         f"natural frequency (deg)")
    c, d = (s.stiffness_y, s.damping_y) if along_y else (s.stiffness_x, s.damping_x)
    b = scene.balancer
    if weights == "locked":
        rotor = Rotor(mass=scene.total_mass, eccentricity=0.0)
        balancer = Balancer()
        mass = scene.total_mass
    elif weights == "removed":
        rotor = Rotor(mass=scene.rotor.mass, eccentricity=0.0)
        balancer = Balancer()
        mass = scene.rotor.mass
    else:
        rotor, balancer, mass = scene.rotor, b, scene.total_mass
    T = damped_period(c, d, mass)
    zeta = d / (2.0 * math.sqrt(c * mass))
    X0 = gain * deflection
    if abs(X0 - gate.position) <= 0.5 * gate.size:
        raise SceneError(f"deflection = {deflection!r} m: the released spot (at {X0:.6g} m on "
                         f"the screen) starts inside the detector ({PATH}.position = "
                         f"{gate.position!r} m, size = {gate.size!r} m); deflect further")
    run = RunSettings(duration=periods * T, sample_rate=samples_per_period / T, rtol=rtol,
                      atol=atol, method="auto")
    test = dataclasses.replace(
        scene, rotor=rotor, balancer=balancer,
        drive=SpeedDrive(programme=np.array([[0.0, 0.0]])), run=run,
        initial=InitialState(x=deflection * ux, y=deflection * uy, vx=0.0, vy=0.0),
        name=(scene.name or "scene") + "_natural_frequency", text="")
    traj = simulate(test)
    if not traj.success:
        raise MeasurementError(f"natural-frequency test: the simulation failed: "
                               f"{traj.stats.message}")
    vx, vy = shaft_velocity(traj)
    X, dX = screen_coordinate(gain * traj.x, gain * traj.y, gain * vx, gain * vy, gate)
    pulses = gate_crossings(traj.t, X, dX, gate)
    period = pulse_counter_period(pulses, gate.start_pass, gate.stop_pass)
    delta = TWO_PI * zeta / math.sqrt(1.0 - zeta * zeta)
    A1 = abs(X0 - gate.position) * math.exp(-delta / 4.0)
    bias = 0.0 if gate.trigger == "centre" else \
        -(0.5 * gate.size) / (TWO_PI * A1) * math.expm1(delta)
    return NaturalFrequencyTest(
        period=period, frequency=1.0 / period, true_period=T, true_frequency=1.0 / T,
        undamped_frequency=math.sqrt(c / mass) / TWO_PI, zeta=zeta,
        relative_error=period / T - 1.0, bias_estimate=bias, pulses=pulses, scene=test,
        trajectory=traj)
