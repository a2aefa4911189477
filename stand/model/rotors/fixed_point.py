"""Rotors with a fixed point: models 2.6.1 (spherical hinge) and 2.6.2
(cylindrical hinge), digest ch2_ch3 sections 2.4-2.5, equations (2.56)-(2.110).

An axisymmetric rigid rotor (central moments A, A, C; mass M) pivots about the
fixed point O.  Its centre of mass is at axial distance ``l`` from O and the
balancer plane at axial distance ``a``.  The small Resal angles (alpha, beta)
place a point at axial distance d at ``x = d beta, y = -d alpha`` (2.70).  The
transverse moment of inertia about O is ``A_xi = A + M l^2`` (2.56).

Spherical hinge (2.64), with generalised stiffnesses ``k1 = c2 b^2`` (on alpha)
and ``k2 = c1 b^2`` (on beta)::

    A_xi alpha'' + C w beta'  + k1 alpha = -s a w^2 sin wt,
    A_xi beta''  - C w alpha' + k2 beta  =  s a w^2 cos wt,

i.e. ``M = A_xi I``, ``G = [[0, C], [-C, 0]]`` per unit spin, ``K = diag(k1, k2)``
and the balancer map ``T = [[0, a], [-a, 0]]``.  Its criterion is (2.72)::

    r_bar = -s a^2 w^2 [2 (C + A_xi) w^2 - (k1 + k2)] / (2 Delta(w^2)),
    Delta(x) = (A_xi^2 - C^2) x^2 - A_xi (k1 + k2) x + k1 k2           (2.78)

((2.72) is printed correctly; only its low-speed limit (2.76) has a sign typo:
r_bar -> +s a^2 w^2 (C + A_xi) w~^2 / (k1 k2) > 0).

Cylindrical hinge (2.104), hinge axis y: only beta, ``A_xi beta'' + k beta =
s a w^2 cos wt`` with ``k = c1 b^2``, balancer map ``[[a], [0]]``; one critical
speed ``sqrt(k/A_xi)`` and the region above it (2.110).

Gravity (not in the book; small-angle linearisation).  With the rotor axis
unit vector ``e = (beta, -alpha, 1 - (alpha^2 + beta^2)/2)`` to second order,
the potential of the rotor's weight is ``V = -M l g . e``.  Its generalised
forces are:

* a constant part ``(-M l g_y, M l g_x)`` on (alpha, beta), from the transverse
  components ``g = (g_x, g_y)``.  This is ``T_l^T (g_x, g_y) M`` with the map
  ``T_l`` of the centre of mass.  It only shifts the static equilibrium;
  second-order terms in g_x, g_y are dropped.
* a stiffness ``M l g_axial`` added to each angle's stiffness, from the axial
  component ``g_axial``.  It is measured along the axis from O towards positive
  axial distances: ``+9.81`` for a rotor hanging below the hinge (pendulum,
  stabilising) and ``-9.81`` for an inverted rotor above it (destabilising).

The closed-form critical speeds below take the *total* stiffnesses (support
plus ``M l g_axial``).  Weights in the balancer plane feel ``gravity_plane =
(g_x, g_y)`` only; their own axial-gravity stiffness ``m g_axial a`` is left to
the coupling, as it is of the order of the weights' mass.
"""
from __future__ import annotations

import math
from typing import Optional

import numpy as np

from stand.model.rotors._build import (axis_planes, finite, gyroscopic_pair, listed_unbalance, nonnegative, nonzero,
                     per_coordinate, positive, transverse_gravity, weight_force)
from stand.model.rotors.structure import LinearRotor

__all__ = ["spherical_hinge", "cylindrical_hinge", "fixed_point_stand", "hinge_stiffnesses",
           "spherical_hinge_delta", "spherical_hinge_criterion",
           "spherical_hinge_working_ranges", "spherical_hinge_natural_frequencies",
           "cylindrical_hinge_criterion", "cylindrical_hinge_critical_speed",
           "cylindrical_hinge_working_ranges", "FIXED_POINT_STAND"]

#: Measured data of the fixed-point stand of monograph section 4.4 (digest ch5_multiball
#: section 6.2; ch7_ch1 section 3): rotor mass 10300 +- 50 g, frame natural frequency
#: 3.275 +- 0.010 Hz, speed range 0-1800 rpm, run-down 175 +- 3 s from 1800 rpm.
FIXED_POINT_STAND = {"rotor_mass_kg": 10.3, "frame_frequency_hz": 3.275,
                     "max_speed_rpm": 1800.0, "rundown_s": 175.0}

_REL = 1e-12     # relative tolerance of the isotropic (k1 = k2) / spherical (A_xi = C) tests

_AT_O = " (a plane at the fixed point does not move)"


def _axial(name: str, d: float) -> float:
    """An axial distance d [m] from O of a plane: non-zero."""
    return nonzero(name, d, "m", _AT_O)


def hinge_stiffnesses(c1: float, c2: float, b: float):
    """Generalised stiffnesses (2.62) [N m/rad] of a support at distance b [m] from O
    with stiffness c1 along x and c2 along y [N/m]: ``(k1, k2) = (c2 b^2, c1 b^2)``
    (k1 acts on alpha, the tilt that moves the support along y)."""
    c1 = positive("c1", c1, "N/m")
    c2 = positive("c2", c2, "N/m")
    b = _axial("b", b)
    return c2 * b * b, c1 * b * b


def _tilt_map(d: float) -> np.ndarray:
    """(2.70): x = d beta, y = -d alpha, on (alpha, beta)."""
    return np.array([[0.0, d], [-d, 0.0]])


def _hinge_map(d: float) -> np.ndarray:
    """(2.104): x = d beta, y = 0, on (beta,) (the hinge carries y)."""
    return np.array([[d], [0.0]])


def _hinge(A, mass, l, a, g, g_axial, extra_planes, plane_map):
    """What models 2.6.1 and 2.6.2 share, validated.

    Returns ``(A_xi, M, l, planes, g, kg)``: ``A_xi = A + M l^2`` [kg m^2] (2.56),
    mass M [kg], l [m], the planes ``"balancer"`` (at a) and ``extra_planes``
    through ``plane_map`` ((2.70) or (2.104)), the transverse gravity
    ``(g_x, g_y)`` [m/s^2] and the axial-gravity stiffness ``M l g_axial``
    [N m/rad] (module docstring).
    """
    A = positive("A", A, "kg m^2")
    M = positive("mass", mass, "kg")
    l = finite("l", l, "m")
    planes = {"balancer": plane_map(_axial("a", a))}
    planes.update(axis_planes(extra_planes or {}, plane_map,
                              lambda name, d: _axial(f"extra_planes[{name!r}]", d)))
    g = transverse_gravity(g)
    kg = M * l * finite("g_axial", g_axial, "m/s^2")
    return A + M * l * l, M, l, planes, g, kg


def _total_stiffness(k, kg: float, g_axial) -> np.ndarray:
    """Support plus axial-gravity stiffness ``k + M l g_axial`` [N m/rad], which
    must be positive (a statically stable rotor, module docstring)."""
    kt = np.asarray(k, dtype=float) + kg
    if not np.all(kt > 0):
        shown = kt.tolist() if kt.size > 1 else float(kt[0])
        raise ValueError(f"total stiffness k + M l g_axial = {shown} N m/rad must be positive "
                         f"(g_axial={g_axial} m/s^2 makes the rotor statically unstable)")
    return kt


# --------------------------------------------------------------------------- 2.6.1
def spherical_hinge(A: float, C: float, mass: float, l: float, k1: float, k2: float, a: float,
                    damping=0.0, unbalance: float = 0.0, unbalance_angle: float = 0.0,
                    g=(0.0, 0.0), g_axial: float = 0.0,
                    extra_planes: Optional[dict] = None) -> LinearRotor:
    """Rotor on a spherical hinge, model 2.6.1, eq. (2.64), as a :class:`LinearRotor`.

    Parameters
    ----------
    A : float
        Central equatorial moment of inertia [kg m^2] (> 0).
    C : float
        Polar moment of inertia [kg m^2] (>= 0).
    mass : float
        Rotor mass M [kg].
    l : float
        Axial distance from O to the centre of mass [m] (any sign); ``A_xi = A + M l^2`` (2.56).
    k1, k2 : float
        Generalised support stiffnesses [N m/rad] on alpha and beta (2.62); see
        :func:`hinge_stiffnesses`.
    a : float
        Axial distance from O to the balancer plane [m] (non-zero).
    damping : float or (float, float), optional
        Viscous angular damping on (alpha, beta) [N m s/rad] (not in the book).
    unbalance, unbalance_angle : float, optional
        Static unbalance s [kg m] in the balancer plane and its angle [rad].
    g : (float, float), optional
        Transverse gravity (g_x, g_y) [m/s^2] (module docstring).
    g_axial : float, optional
        Axial gravity component [m/s^2], + for a hanging rotor (adds ``M l g_axial``
        to k1 and k2).
    extra_planes : dict of str -> float, optional
        More named planes at axial distances [m] from O (e.g. probe points).

    Returns
    -------
    LinearRotor
        Coordinates (alpha, beta) [rad]; plane ``"balancer"`` ``[[0, a], [-a, 0]]``.

    Raises
    ------
    ValueError
        On non-positive A, mass, k1 or k2, negative C, a = 0, or a total stiffness
        (with gravity) that is not positive (statically unstable inverted rotor).
    """
    C = nonnegative("C", C, "kg m^2")
    k = np.array([positive("k1", k1, "N m/rad"), positive("k2", k2, "N m/rad")])
    A_xi, M, l, planes, g, kg = _hinge(A, mass, l, a, g, g_axial, extra_planes, _tilt_map)
    return LinearRotor(
        name="spherical_hinge",
        coords=("alpha [rad]", "beta [rad]"),
        M=A_xi * np.eye(2), G=gyroscopic_pair(2, 0, 1, C),
        D=np.diag(per_coordinate("damping", damping, 2, "N m s/rad")),
        K=np.diag(_total_stiffness(k, kg, g_axial)),
        planes=planes, unbalances=listed_unbalance("balancer", unbalance, unbalance_angle),
        gravity=weight_force(g, (M, _tilt_map(l))), gravity_plane=g,
        source="Filimonikhin (2004) 2.6.1, eqs. (2.56), (2.64), (2.70)",
    )


def spherical_hinge_delta(x, A_xi: float, C: float, k1: float, k2: float):
    """Delta(x) of (2.78), x = w^2 [rad^2/s^2]: ``(A_xi^2 - C^2) x^2 - A_xi (k1 + k2) x + k1 k2``.
    Its roots are the synchronous (forward-whirl) resonances."""
    x = np.asarray(x, dtype=float)
    return (A_xi * A_xi - C * C) * x * x - A_xi * (k1 + k2) * x + k1 * k2


def spherical_hinge_criterion(omega, A_xi: float, C: float, k1: float, k2: float, a: float,
                              unbalance: float = 1.0):
    """Criterion (2.72) [m]: ``-s a^2 w^2 [2 (C + A_xi) w^2 - (k1 + k2)] / (2 Delta(w^2))``."""
    x = np.asarray(omega, dtype=float) ** 2
    num = -unbalance * a * a * x * (2.0 * (C + A_xi) * x - (k1 + k2))
    return num / (2.0 * spherical_hinge_delta(x, A_xi, C, k1, k2))


def _check_sph(A_xi, C, k1, k2):
    return (positive("A_xi", A_xi, "kg m^2"), nonnegative("C", C, "kg m^2"),
            positive("k1", k1, "N m/rad"), positive("k2", k2, "N m/rad"))


def spherical_hinge_working_ranges(A_xi: float, C: float, k1: float, k2: float):
    """Closed-form ``(critical_speeds, ranges)`` [rad/s] of every case of 2.6.1.

    With ``w~^2 = (k1 + k2)/(2 (C + A_xi))`` (2.75) and x_+ the smaller positive root
    of Delta (2.80), evaluated as ``2 k1 k2 / (A_xi (k1 + k2) + sqrt(D))``,
    ``D = A_xi^2 (k1 - k2)^2 + 4 k1 k2 C^2`` (no cancellation as A_xi -> C):

    ============================  ===============================  ==========================
    case                          critical speeds                  region
    ============================  ===============================  ==========================
    anisotropic, long A_xi > C    sqrt(x1) < w~ < sqrt(x2)  (2.87)  (w1, w~) U (sqrt(x2), inf)
    anisotropic, spherical        sqrt(k1 k2/(A_xi (k1+k2))), w~   (w1, w~)        (2.91)
    anisotropic, short A_xi < C   sqrt(x_+), w~             (2.95)  (w1, w~)
    isotropic, long               sqrt(k/(A_xi - C))        (2.99)  (w1, inf); no sign change
                                                                   at w01 = w~ (2.97)
    isotropic, spherical / short  none (r_bar > 0)   (2.101), (2.103)  none
    ============================  ===============================  ==========================

    "Isotropic" and "spherical" are tested with a relative tolerance of 1e-12.
    """
    A_xi, C, k1, k2 = _check_sph(A_xi, C, k1, k2)
    wt = math.sqrt((k1 + k2) / (2.0 * (C + A_xi)))
    iso = math.isclose(k1, k2, rel_tol=_REL)
    sph = math.isclose(A_xi, C, rel_tol=_REL)
    long_ = A_xi > C and not sph
    if iso:
        k = 0.5 * (k1 + k2)
        if long_:
            w = math.sqrt(k / (A_xi - C))
            return np.array([w]), [(w, math.inf)]
        return np.array([]), []
    D = A_xi * A_xi * (k1 - k2) ** 2 + 4.0 * k1 * k2 * C * C
    s1 = A_xi * (k1 + k2)
    x_plus = 2.0 * k1 * k2 / (s1 + math.sqrt(D))
    w1 = math.sqrt(x_plus)
    if long_:
        w3 = math.sqrt((s1 + math.sqrt(D)) / (2.0 * (A_xi * A_xi - C * C)))
        return np.array([w1, wt, w3]), [(w1, wt), (w3, math.inf)]
    return np.array([w1, wt]), [(w1, wt)]


def spherical_hinge_natural_frequencies(A_xi: float, C: float, k1: float, k2: float,
                                        omega: float = 0.0) -> np.ndarray:
    """Undamped whirl frequencies [rad/s] at spin omega: the roots lambda > 0 of
    ``(k1 - A_xi lambda^2)(k2 - A_xi lambda^2) - C^2 omega^2 lambda^2 = 0`` (the
    determinant of (2.64)); at omega = 0 they are ``sqrt(k1/A_xi), sqrt(k2/A_xi)``,
    and at lambda = omega the equation is Delta(omega^2) = 0 of (2.78)."""
    A_xi, C, k1, k2 = _check_sph(A_xi, C, k1, k2)
    b = A_xi * (k1 + k2) + C * C * omega * omega
    disc = math.sqrt(b * b - 4.0 * A_xi * A_xi * k1 * k2)
    hi = (b + disc) / (2.0 * A_xi * A_xi)
    lo = k1 * k2 / (A_xi * A_xi * hi)
    return np.array([math.sqrt(lo), math.sqrt(hi)])


# --------------------------------------------------------------------------- 2.6.2
def cylindrical_hinge(A: float, mass: float, l: float, k: float, a: float, damping: float = 0.0,
                      unbalance: float = 0.0, unbalance_angle: float = 0.0, g=(0.0, 0.0),
                      g_axial: float = 0.0, extra_planes: Optional[dict] = None) -> LinearRotor:
    """Rotor on a cylindrical hinge (axis y), model 2.6.2, eq. (2.104).

    Parameters
    ----------
    A : float
        Central equatorial moment of inertia [kg m^2]; ``A_xi = A + M l^2`` (2.56).
    mass : float
        Rotor mass M [kg].
    l : float
        Axial distance from O to the centre of mass [m].
    k : float
        Generalised stiffness ``c1 b^2`` [N m/rad] on beta (2.105).
    a : float
        Axial distance from O to the balancer plane [m] (non-zero).
    damping : float, optional
        Viscous damping on beta [N m s/rad].
    unbalance, unbalance_angle : float, optional
        Static unbalance s [kg m] in the balancer plane and its angle [rad].
    g : (float, float), optional
        Transverse gravity (g_x, g_y) [m/s^2]; g_x gives the constant moment
        ``M l g_x``, g_y is carried by the hinge.
    g_axial : float, optional
        Axial gravity [m/s^2], adds ``M l g_axial`` to k (module docstring).
    extra_planes : dict of str -> float, optional
        More named planes at axial distances [m] from O.

    Returns
    -------
    LinearRotor
        Coordinate ``beta [rad]``; plane ``"balancer"`` ``[[a], [0]]`` (x_A = a beta, y_A = 0).
    """
    k = positive("k", k, "N m/rad")
    d = nonnegative("damping", damping, "N m s/rad")
    A_xi, M, l, planes, g, kg = _hinge(A, mass, l, a, g, g_axial, extra_planes, _hinge_map)
    return LinearRotor(
        name="cylindrical_hinge",
        coords=("beta [rad]",),
        M=np.array([[A_xi]]), G=np.zeros((1, 1)), D=np.array([[d]]),
        K=np.array([_total_stiffness([k], kg, g_axial)]),
        planes=planes, unbalances=listed_unbalance("balancer", unbalance, unbalance_angle),
        gravity=weight_force(g, (M, _hinge_map(l))), gravity_plane=g,
        source="Filimonikhin (2004) 2.6.2, eqs. (2.56), (2.104)-(2.107)",
    )


def cylindrical_hinge_critical_speed(A_xi: float, k: float) -> float:
    """The single critical speed (2.105)/(2.110) [rad/s]:
    ``w1 = sqrt(k/A_xi) = sqrt(c1 b^2/A_xi)``."""
    return math.sqrt(positive("k", k, "N m/rad") / positive("A_xi", A_xi, "kg m^2"))


def cylindrical_hinge_working_ranges(A_xi: float, k: float):
    """Closed-form ``(critical_speeds, ranges)`` of (2.110): ``([w1], [(w1, inf)])``."""
    w1 = cylindrical_hinge_critical_speed(A_xi, k)
    return np.array([w1]), [(w1, math.inf)]


def cylindrical_hinge_criterion(omega, A_xi: float, k: float, a: float, unbalance: float = 1.0):
    """Criterion (2.110) [m]: ``r_bar = a s~ w^2 / (2 (w1^2 - w^2))`` with ``s~ = s a/A_xi``."""
    x = np.asarray(omega, dtype=float) ** 2
    st = unbalance * a / A_xi
    return a * st * x / (2.0 * (k / A_xi - x))


def fixed_point_stand(l: float = 0.30, a: float = 0.40, A: float = 0.08,
                      mass: float = FIXED_POINT_STAND["rotor_mass_kg"],
                      frequency: float = FIXED_POINT_STAND["frame_frequency_hz"],
                      gravity: float = 9.81, damping: float = 0.0,
                      unbalance: float = 0.0, unbalance_angle: float = 0.0) -> LinearRotor:
    """The fixed-point stand of monograph section 4.4 as a cylindrical-hinge rotor (2.104).

    Measured (digest ch5_multiball section 6.2): rotor mass 10.3 kg, frame natural
    frequency 3.275 Hz, horizontal rotor, vertical frame vibration.  The digests give
    **no geometry**, so ``l``, ``a`` and ``A`` are assumptions, order-of-magnitude values
    for a 10 kg rotor about 0.3 m long: l = 0.30 m to the centre of mass, balancer
    at a = 0.40 m, and central A = 0.08 kg m^2.  The stiffness is set so that the
    natural frequency is the measured one, ``k = A_xi (2 pi f0)^2``.  The critical
    speed, 2 pi f0 = 20.58 rad/s (196.5 rpm), therefore does not depend on the
    assumed geometry.  The amplitudes for a given unbalance do depend on it.

    The rotor axis is horizontal and the tilt beta moves the rotor vertically, so
    fixed x points up: ``g = (-gravity, 0)`` and ``g_axial = 0``.  Gravity only sets a
    static sag, ``-M l gravity / k`` [rad], and pulls the balls to the bottom of the
    track (``gravity_plane``).

    Parameters
    ----------
    l, a : float
        Assumed axial distances [m] of the centre of mass and of the balancer from O.
    A : float
        Assumed central equatorial moment of inertia [kg m^2].
    mass : float
        Rotor mass [kg] (measured: 10.3).
    frequency : float
        Frame natural frequency f0 [Hz] (measured: 3.275).
    gravity : float
        g [m/s^2]; 0 drops gravity.
    damping, unbalance, unbalance_angle : float
        As in :func:`cylindrical_hinge`.
    """
    f0 = positive("frequency", frequency, "Hz")
    M = positive("mass", mass, "kg")
    A_xi = positive("A", A, "kg m^2") + M * l * l
    k = A_xi * (2.0 * math.pi * f0) ** 2
    return cylindrical_hinge(A, M, l, k, a, damping=damping, unbalance=unbalance,
                             unbalance_angle=unbalance_angle, g=(-float(gravity), 0.0))
