"""Residual unbalance from signals: 1X order tracking, model inversion, ring
calibration, ISO 21940-11 grades.

Plain arrays in, results with standard uncertainties out (issue 5, item 2;
digest ch5 section 8.2 and section 6.1).

* :func:`synchronous_component` -- the synchronous (1X) component of the shaft
  orbit z = x + i y by order tracking (rotor-angle channel, or keyphasor
  pulses), averaged over whole revolutions;
* :func:`unbalance_from_response` -- invert the steady response of the rigid
  rotor on isotropic supports, z_1X = (U / M_Sigma) R^2 e^{i beta} /
  (1 - R^2 + 2 i zeta R);
* :func:`unbalance_from_rings` -- the laser method's calibration rings: zone
  i -> unbalance i S / 16 (monograph section 4.3.2);
* :func:`iso_21940_permissible`, :func:`iso_21940_grade` -- ISO 21940-11
  permissible residual unbalance U_per = 1000 G m / Omega [g mm] and the
  achieved balance quality grade;
* :func:`reduction_factor` -- balancer off / balancer on.

Conventions: angles are counter-clockwise in the (x, y) plane, the rotor turns
forward (counter-clockwise, increasing angle); the rotor angle is measured from
the reference (keyphasor) mark, so the 1X phase is the angle of the shaft
displacement ahead of the mark.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import SignalError, check_times
from .units import DEG_PER_RAD, GMM_PER_KG_M, converted

__all__ = ["SynchronousComponent", "synchronous_component", "UnbalanceEstimate",
           "unbalance_from_response", "RingReading", "unbalance_from_rings",
           "ISO_GRADES_MM_S", "iso_21940_permissible", "IsoGrade", "iso_21940_grade",
           "Reduction", "reduction_factor"]

TWO_PI = 2.0 * math.pi

#: ISO 21940-11 balance quality grades G [mm/s].
ISO_GRADES_MM_S = (0.4, 1.0, 2.5, 6.3, 16.0, 40.0, 100.0, 250.0, 630.0, 1600.0, 4000.0)


# --------------------------------------------------------------------------- 1X

@dataclass(frozen=True)
class SynchronousComponent:
    """The synchronous (1X) component of the shaft motion.

    Attributes
    ----------
    vector_m : complex
        Mean of z e^{-i phi} over whole revolutions: the 1X displacement in the
        rotor frame [m] (real part along the reference mark).
    amplitude_m, amplitude_std_m : float
        |vector| and its standard uncertainty [m].
    phase_rad, phase_std_rad : float
        arg(vector): angle of the 1X displacement ahead of the reference mark
        [rad], in (-pi, pi], and its standard uncertainty.
    vector_std_m : float
        Standard uncertainty of each of Re and Im of the vector [m] (the
        revolution-to-revolution scatter / sqrt(n)).
    speed_rad_s, speed_std_rad_s : float
        Mean rotor speed over the revolutions used and its uncertainty (scatter
        of the per-revolution speeds / sqrt(n)).
    revolutions : int
        Number of whole revolutions averaged.
    per_revolution_m : ndarray of complex
        The 1X vector of each revolution [m].
    t_start, t_end : float
        Time span of the revolutions used [s].
    reference_std_rad : float
        What the phase reference itself leaves open [rad] (a keyphasor's timing), already
        in ``phase_std_rad``; 0 when not known.
    """

    vector_m: complex
    amplitude_m: float
    amplitude_std_m: float
    phase_rad: float
    phase_std_rad: float
    vector_std_m: float
    speed_rad_s: float
    speed_std_rad_s: float
    revolutions: int
    per_revolution_m: np.ndarray = field(repr=False)
    t_start: float = 0.0
    t_end: float = 0.0
    reference_std_rad: float = 0.0

    phase_deg = converted("phase_rad", DEG_PER_RAD,
                          "Phase of the 1X vector ahead of the reference mark [deg].")


def _real_signal(v, name, n):
    v = np.asarray(v)
    if v.ndim != 1 or v.size != n:
        raise SignalError(f"{name}: must be a 1-D array of the same length as t ({n}), "
                          f"got shape {v.shape}")
    if np.iscomplexobj(v):
        raise SignalError(f"{name}: must be real, got complex samples")
    v = v.astype(float)
    bad = ~np.isfinite(v)
    if bad.any():
        raise SignalError(f"{name}: {int(bad.sum())} non-finite sample(s) (NaN/inf), "
                          f"first at index {int(np.argmax(bad))}")
    return v


def _phase_from_keyphasor(t, pulses):
    p = np.asarray(pulses, dtype=float).ravel()
    if p.size == 0:
        raise SignalError("keyphasor_times: no keyphasor pulse; the 1X phase needs a once-per-"
                          "revolution reference (give keyphasor_times or rotor_angle)")
    if not np.all(np.isfinite(p)):
        raise SignalError("keyphasor_times: contains NaN or inf")
    inside = p[(p >= t[0]) & (p <= t[-1])]
    if inside.size == 0:
        raise SignalError(f"keyphasor_times: no keyphasor pulse within the record "
                          f"[{t[0]:.6g}, {t[-1]:.6g}] s")
    if inside.size == 1:
        raise SignalError("keyphasor_times: only one keyphasor pulse within the record; need at "
                          "least 3 (2 whole revolutions) to order-track")
    if np.any(np.diff(inside) <= 0):
        raise SignalError("keyphasor_times: pulse times must be strictly increasing")
    # phi = 2 pi (j + (t - t_j) / (t_{j+1} - t_j)) between pulses; 0 at each pulse
    phi_p = TWO_PI * np.arange(inside.size)
    sel = (t >= inside[0]) & (t <= inside[-1])
    return np.interp(t, inside, phi_p), sel, inside


def synchronous_component(t, x, y, *, keyphasor_times=None, rotor_angle=None,
                          min_revolutions=2):
    """Synchronous (1X) component of the shaft motion by order tracking.

    The complex orbit z = x + i y is demodulated by the rotor angle phi,
    g = z e^{-i phi}, and g is averaged over each whole revolution (trapezoidal
    integral in phi, with the revolution boundaries interpolated, so the sample
    rate need not be a multiple of the speed).  The result is the mean of the
    per-revolution vectors; the uncertainties come from their scatter.

    Parameters
    ----------
    t : array_like (N,)
        Sample times [s], strictly increasing.
    x, y : array_like (N,)
        Shaft displacement [m] (or any length unit; the results carry it).
    keyphasor_times : array_like, optional
        Times [s] of the once-per-revolution pulses (the rotor at its reference
        mark).  phi is reconstructed by adding 2 pi per pulse interval (linear
        in time within an interval); samples outside the first/last pulse are
        not used.
    rotor_angle : array_like (N,), optional
        Rotor angle [rad] from the reference mark (wrapped or unwrapped).
        Takes precedence over ``keyphasor_times``.
    min_revolutions : int
        Fewest whole revolutions accepted (default 2).

    Returns
    -------
    SynchronousComponent

    Raises
    ------
    SignalError
        Bad time base (non-monotonic, NaN/inf), NaN/inf samples, a constant
        orbit, no / one keyphasor pulse, no reference at all, a rotor that is
        not turning forward, fewer than ``min_revolutions`` whole revolutions.
    """
    t = check_times(t, "t", 3)
    n = t.size
    x = _real_signal(x, "x", n)
    y = _real_signal(y, "y", n)
    z = x + 1j * y
    if np.ptp(x) == 0.0 and np.ptp(y) == 0.0:
        raise SignalError("x, y: the orbit is constant (no shaft motion recorded); "
                          "check the sensor")
    if rotor_angle is not None:
        phi = _real_signal(rotor_angle, "rotor_angle", n)
        phi = np.unwrap(phi)
        sel = np.ones(n, bool)
    elif keyphasor_times is not None:
        phi, sel, _ = _phase_from_keyphasor(t, keyphasor_times)
    else:
        raise SignalError("no phase reference: give rotor_angle or keyphasor_times")
    t, z, phi = t[sel], z[sel], phi[sel]
    dphi = np.diff(phi)
    if np.any(dphi <= 0):
        i = int(np.argmax(dphi <= 0))
        raise SignalError(f"rotor_angle: must increase (rotor turning forward, slower than half "
                          f"a revolution per sample); it does not between t = {t[i]:.6g} s and "
                          f"{t[i + 1]:.6g} s")
    if np.any(dphi >= math.pi):
        raise SignalError("rotor_angle: steps of pi or more between samples; the speed is above "
                          "half the sample rate (aliased), resample faster")
    j0 = math.ceil(phi[0] / TWO_PI - 1e-12)
    j1 = math.floor(phi[-1] / TWO_PI + 1e-12)
    n_rev = j1 - j0
    if n_rev < min_revolutions:
        raise SignalError(f"record too short: {max(n_rev, 0)} whole revolution(s) between "
                          f"t = {t[0]:.6g} s and {t[-1]:.6g} s (need at least {min_revolutions})")
    g = z * np.exp(-1j * phi)
    G = np.concatenate(([0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * dphi)))
    bounds = TWO_PI * np.arange(j0, j1 + 1)
    Gb = np.interp(bounds, phi, G.real) + 1j * np.interp(bounds, phi, G.imag)
    tb = np.interp(bounds, phi, t)
    per_rev = np.diff(Gb) / TWO_PI
    vec = complex(np.mean(per_rev))
    if n_rev > 1:
        s_re = float(np.std(per_rev.real, ddof=1) / math.sqrt(n_rev))
        s_im = float(np.std(per_rev.imag, ddof=1) / math.sqrt(n_rev))
    else:
        s_re = s_im = float("nan")
    sv = math.hypot(s_re, s_im) / math.sqrt(2.0)
    amp = abs(vec)
    # amplitude along the vector, phase across it
    if amp > 0:
        u = vec / amp
        dev = per_rev / u
        s_par = float(np.std(dev.real, ddof=1) / math.sqrt(n_rev))
        s_perp = float(np.std(dev.imag, ddof=1) / math.sqrt(n_rev))
        s_phase = s_perp / amp
    else:
        s_par, s_phase = sv, math.pi
    w_rev = TWO_PI / np.diff(tb)
    speed = float(TWO_PI * n_rev / (tb[-1] - tb[0]))
    s_speed = float(np.std(w_rev, ddof=1) / math.sqrt(n_rev)) if n_rev > 1 else float("nan")
    return SynchronousComponent(vector_m=vec, amplitude_m=amp, amplitude_std_m=s_par,
                                phase_rad=math.atan2(vec.imag, vec.real), phase_std_rad=s_phase,
                                vector_std_m=sv, speed_rad_s=speed, speed_std_rad_s=s_speed,
                                revolutions=int(n_rev), per_revolution_m=per_rev,
                                t_start=float(tb[0]), t_end=float(tb[-1]))


# ------------------------------------------------------------- model inversion

class _InGramMillimetres:
    """``unbalance_gmm``, ``unbalance_std_gmm`` [g mm] of a result holding
    ``unbalance_kg_m``, ``unbalance_std_kg_m`` [kg m]."""

    __slots__ = ()
    unbalance_gmm = converted("unbalance_kg_m", GMM_PER_KG_M, "U [g mm].")
    unbalance_std_gmm = converted("unbalance_std_kg_m", GMM_PER_KG_M,
                                  "Standard uncertainty of U [g mm].")


@dataclass(frozen=True)
class UnbalanceEstimate(_InGramMillimetres):
    """Unbalance U e^{i beta} from the 1X response.

    Attributes
    ----------
    unbalance_kg_m, unbalance_std_kg_m : float
        U = M_Sigma e [kg m] and its standard uncertainty (from the response's
        uncertainty only; model-parameter errors are not included).
    angle_rad, angle_std_rad : float
        beta: angle of the heavy spot from the reference mark [rad].
    vector_kg_m : complex
        U e^{i beta} [kg m].
    speed_ratio : float
        R = omega / omega_1.
    """

    unbalance_kg_m: float
    unbalance_std_kg_m: float
    angle_rad: float
    angle_std_rad: float
    vector_kg_m: complex
    speed_ratio: float

    angle_deg = converted("angle_rad", DEG_PER_RAD, "beta [deg].")


def _positive(name, v, allow_zero=False):
    v = float(v)
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise ValueError(f"{name} = {v!r}: must be a finite number {'>=' if allow_zero else '>'} 0")
    return v


def unbalance_from_response(response_1x, speed_rad_s, mass_kg, natural_frequency_hz,
                            damping_ratio):
    """Invert the steady 1X response of a rigid rotor on isotropic supports.

    The model (M_Sigma z'' + c z' + k z = U omega^2 e^{i(omega t + beta)})
    gives, in the rotor frame,

        z_1X = (U / M_Sigma) R^2 e^{i beta} / (1 - R^2 + 2 i zeta R),
        R = omega / omega_1,

    so U e^{i beta} = M_Sigma z_1X (1 - R^2 + 2 i zeta R) / R^2.

    Parameters
    ----------
    response_1x : complex or SynchronousComponent
        1X vector in the rotor frame [m]; a :class:`SynchronousComponent`
        also supplies its uncertainty.
    speed_rad_s : float
        Rotor speed omega [rad/s] (> 0).
    mass_kg : float
        Total vibrating mass M_Sigma [kg].
    natural_frequency_hz : float
        f_1 = omega_1 / (2 pi) [Hz].
    damping_ratio : float
        zeta = c / (2 sqrt(k M_Sigma)).

    Returns
    -------
    UnbalanceEstimate
    """
    sv = 0.0
    if isinstance(response_1x, SynchronousComponent):
        sv = response_1x.vector_std_m
        z = response_1x.vector_m
    else:
        z = complex(response_1x)
    if not (math.isfinite(z.real) and math.isfinite(z.imag)):
        raise SignalError("response_1x: not finite")
    w = _positive("speed_rad_s", speed_rad_s)
    M = _positive("mass_kg", mass_kg)
    f1 = _positive("natural_frequency_hz", natural_frequency_hz)
    zeta = _positive("damping_ratio", damping_ratio, allow_zero=True)
    R = w / (TWO_PI * f1)
    gain = M * (1.0 - R * R + 2j * zeta * R) / (R * R)
    U = z * gain
    sU = sv * abs(gain) if math.isfinite(sv) else float("nan")
    aU = abs(U)
    return UnbalanceEstimate(unbalance_kg_m=aU, unbalance_std_kg_m=sU,
                             angle_rad=math.atan2(U.imag, U.real),
                             angle_std_rad=(sU / aU if aU > 0 else math.pi),
                             vector_kg_m=U, speed_ratio=R)


# ----------------------------------------------------------------------- rings

@dataclass(frozen=True)
class RingReading(_InGramMillimetres):
    """Unbalance read from the calibration rings.

    Attributes
    ----------
    zone : int
        Zone index i: ring_radii[i] <= radius < ring_radii[i + 1].
    unbalance_kg_m : float
        i S / 16 [kg m].
    unbalance_std_kg_m : float
        Half a zone, S / 32 [kg m] (the reading resolution).
    off_scale : bool
        The spot lies beyond the last ring (the zone is a lower bound).
    interpolated_kg_m : float
        The radius interpolated linearly between the rings around it
        ((i + fraction) S / 16; extrapolated from the last two rings when off
        scale) [kg m]: what a measured radius gives when the rotor's response
        is linear in the unbalance (the rings are then equally spaced), finer
        than the zone a person reads.
    interpolated_std_kg_m : float
        Standard uncertainty of ``interpolated_kg_m`` from the radius's
        (``radius_std_m`` times the slope S / 16 per ring spacing) [kg m].
    """

    zone: int
    unbalance_kg_m: float
    unbalance_std_kg_m: float
    off_scale: bool
    interpolated_kg_m: float = math.nan
    interpolated_std_kg_m: float = math.nan


def unbalance_from_rings(radius_m, ring_radii_m, capacity_kg_m, radius_std_m=0.0):
    """Unbalance from the spot's circle and the calibration rings (zone i -> i S / 16).

    Parameters
    ----------
    radius_m : float
        Radius of the spot's circle on the screen [m].
    radius_std_m : float
        Its standard uncertainty [m] (the spot's scatter and the ring scale's
        calibration), propagated to the interpolated unbalance.
    ring_radii_m : array_like
        Ring radii [m] of zones 0, 1, 2, ... (ring i drawn for unbalance
        i S / 16; ring 0 is normally radius 0), strictly increasing.
    capacity_kg_m : float
        Balancer capacity S [kg m].

    Returns
    -------
    RingReading
    """
    r = float(radius_m)
    if not math.isfinite(r) or r < 0:
        raise SignalError(f"radius_m = {radius_m!r}: must be a finite radius >= 0 (m)")
    radii = np.asarray(ring_radii_m, dtype=float)
    if radii.ndim != 1 or radii.size < 2 or not np.all(np.isfinite(radii)) \
            or np.any(np.diff(radii) <= 0):
        raise ValueError("ring_radii_m: must be a strictly increasing 1-D array of at least 2 "
                         "finite radii (m)")
    S = _positive("capacity_kg_m", capacity_kg_m)
    i = int(np.clip(np.searchsorted(radii, r, side="right") - 1, 0, radii.size - 1))
    j = min(i, radii.size - 2)
    sr = _positive("radius_std_m", radius_std_m, allow_zero=True)
    frac = j + (r - radii[j]) / (radii[j + 1] - radii[j])
    return RingReading(zone=i, unbalance_kg_m=i * S / 16.0, unbalance_std_kg_m=S / 32.0,
                       off_scale=bool(r >= radii[-1]), interpolated_kg_m=frac * S / 16.0,
                       interpolated_std_kg_m=sr / (radii[j + 1] - radii[j]) * S / 16.0)


# ------------------------------------------------------------------------- ISO

def iso_21940_permissible(grade_mm_s, rotor_mass_kg, service_speed_rad_s):
    """Permissible residual unbalance of ISO 21940-11, U_per = 1000 G m / Omega [g mm].

    Parameters
    ----------
    grade_mm_s : float
        Balance quality grade G [mm/s] (e.g. 6.3).
    rotor_mass_kg : float
        Rotor mass m [kg].
    service_speed_rad_s : float
        Maximum service speed Omega [rad/s].

    Returns
    -------
    float
        U_per [g mm].
    """
    G = _positive("grade_mm_s", grade_mm_s)
    m = _positive("rotor_mass_kg", rotor_mass_kg)
    w = _positive("service_speed_rad_s", service_speed_rad_s)
    return 1000.0 * G * m / w


@dataclass(frozen=True)
class IsoGrade:
    """Achieved balance quality (ISO 21940-11).

    Attributes
    ----------
    grade_mm_s, grade_std_mm_s : float
        G = U Omega / (1000 m) [mm/s] (U in g mm) and its uncertainty.
    grade_class : float or None
        The best standard grade met: the smallest G class >= the achieved G
        (None if worse than G 4000).
    label : str
        e.g. "G 6.3" (or "worse than G 4000").
    target_mm_s : float or None
        Target grade, if given.
    passed : bool or None
        achieved G <= target (None without a target).
    permissible_gmm : float or None
        U_per for the target grade.
    """

    grade_mm_s: float
    grade_std_mm_s: float
    grade_class: float | None
    label: str
    target_mm_s: float | None
    passed: bool | None
    permissible_gmm: float | None


def _fmt_grade(g):
    return f"G {g:g}"


def iso_21940_grade(unbalance_gmm, rotor_mass_kg, service_speed_rad_s, target_grade_mm_s=None,
                    unbalance_std_gmm=0.0):
    """Achieved ISO 21940-11 balance quality grade for a residual unbalance.

    Parameters
    ----------
    unbalance_gmm : float
        Residual unbalance U [g mm].
    rotor_mass_kg : float
        Rotor mass m [kg].
    service_speed_rad_s : float
        Service speed Omega [rad/s].
    target_grade_mm_s : float, optional
        Grade to check against (e.g. 6.3).
    unbalance_std_gmm : float
        Standard uncertainty of U [g mm], propagated to G.

    Returns
    -------
    IsoGrade
    """
    U = _positive("unbalance_gmm", unbalance_gmm, allow_zero=True)
    m = _positive("rotor_mass_kg", rotor_mass_kg)
    w = _positive("service_speed_rad_s", service_speed_rad_s)
    G = U * w / (1000.0 * m)
    sG = float(unbalance_std_gmm) * w / (1000.0 * m)
    cls = next((g for g in ISO_GRADES_MM_S if G <= g * (1 + 1e-12)), None)
    label = _fmt_grade(cls) if cls is not None else "worse than G 4000"
    if target_grade_mm_s is None:
        return IsoGrade(G, sG, cls, label, None, None, None)
    tg = _positive("target_grade_mm_s", target_grade_mm_s)
    return IsoGrade(G, sG, cls, label, tg, bool(G <= tg * (1 + 1e-12)),
                    iso_21940_permissible(tg, m, w))


@dataclass(frozen=True)
class Reduction:
    """Reduction factor before / after (e.g. balancer off / balancer on).

    Attributes
    ----------
    factor, factor_std : float
        before / after and its standard uncertainty (inf if after = 0).
    percent : float
        100 (1 - after / before): the reduction in per cent.
    decibel : float
        20 log10(before / after) [dB].
    """

    factor: float
    factor_std: float
    percent: float
    decibel: float


def reduction_factor(before, after, before_std=0.0, after_std=0.0):
    """Reduction factor of a vibration or unbalance: before / after.

    Parameters
    ----------
    before, after : float
        Amplitudes (any consistent unit, > 0 / >= 0), e.g. the 1X amplitude or
        the unbalance with the balancer off and on.
    before_std, after_std : float
        Their standard uncertainties (propagated to first order).

    Returns
    -------
    Reduction
    """
    b = _positive("before", before)
    a = _positive("after", after, allow_zero=True)
    if a == 0:
        return Reduction(math.inf, math.nan, 100.0, math.inf)
    f = b / a
    sf = f * math.hypot(float(before_std) / b, float(after_std) / a)
    return Reduction(f, sf, 100.0 * (1.0 - a / b), 20.0 * math.log10(f))
