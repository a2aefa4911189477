"""Model 2.5.2: a rotor elastically mounted in a body that is itself elastically
mounted (two-mass system), digest ch2_ch3 section 2.2, equations (2.32)-(2.44).

Equations (2.32), with the stiffness roles the equations show (the book's
legend at its line 1226 is reversed): ``c1`` joins the body to the ground and
``c2`` joins the rotor to the body::

    M1 x1'' + c2 (x1 - x2) + c1 x1 = 0,     M2 x2'' + c2 (x2 - x1) = s w^2 cos wt,

and the same in y.  Optional viscous dampers ``d1`` (body-ground) and ``d2``
(rotor-body) sit in parallel with the springs (the book has none).

Closed forms: the natural frequencies (2.37)-(2.39) are the roots of
``Delta(x) = M1 M2 x^2 - [M1 c2 + M2 (c1 + c2)] x + c1 c2`` (x = w^2); the
rotor's deflection along the unbalance (2.42) is
``r_2e = (c1 + c2 - M1 w^2) s w^2 / Delta(w^2)``, so the critical speeds
(2.43) are ``sqrt(x1) < sqrt((c1 + c2)/M1) < sqrt(x2)`` and the autobalancing
region (2.44) is ``(w1, w2) U (w3, inf)``.
"""
from __future__ import annotations

import math

import numpy as np

from stand.model.rotors._build import listed_unbalance, nonnegative, positive, transverse_gravity, weight_force
from stand.model.rotors.structure import LinearRotor

__all__ = ["two_mass", "two_mass_natural_frequencies", "two_mass_critical_speeds",
           "two_mass_working_ranges", "two_mass_criterion"]


def two_mass(body_mass: float, rotor_mass: float, body_stiffness: float, rotor_stiffness: float,
             body_damping: float = 0.0, rotor_damping: float = 0.0, unbalance: float = 0.0,
             unbalance_angle: float = 0.0, g=(0.0, 0.0)) -> LinearRotor:
    """Two-mass rotor of model 2.5.2, eq. (2.32), as a :class:`LinearRotor`.

    Parameters
    ----------
    body_mass : float
        M1 [kg], the elastically mounted body (housing).
    rotor_mass : float
        M2 [kg], the rotor (without the correction weights).
    body_stiffness : float
        c1 [N/m], isotropic, body to ground.
    rotor_stiffness : float
        c2 [N/m], isotropic, rotor to body.
    body_damping, rotor_damping : float, optional
        d1, d2 [N s/m], viscous, in parallel with c1 and c2 (default 0 as in the book).
    unbalance : float, optional
        Static unbalance s [kg m] of the rotor, in plane ``"balancer"`` (0: none listed).
    unbalance_angle : float, optional
        Its angle [rad] from the rotor's reference mark.
    g : (float, float), optional
        Transverse gravity components (gx, gy) [m/s^2] in the fixed frame; zero for a
        vertical axis (the book neglects gravity).

    Returns
    -------
    LinearRotor
        Coordinates (x1, y1, x2, y2) [m]; planes ``"balancer"`` = rotor translation
        (x2, y2) and ``"body"`` = body translation (x1, y1) (housing probe point).
    """
    M1, M2, c1, c2 = _check(body_mass, rotor_mass, body_stiffness, rotor_stiffness)
    d1 = nonnegative("body_damping", body_damping, "N s/m")
    d2 = nonnegative("rotor_damping", rotor_damping, "N s/m")
    g = transverse_gravity(g)

    def coupling(k_ground: float, k_between: float) -> np.ndarray:
        # order (x1, y1, x2, y2): body rows get k_ground + k_between, rotor rows k_between
        blk = np.array([[k_ground + k_between, -k_between], [-k_between, k_between]])
        return np.kron(blk, np.eye(2))

    body = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    rotor = np.array([[0, 0, 1.0, 0], [0, 0, 0, 1.0]])
    return LinearRotor(
        name="two_mass",
        coords=("x1 [m]", "y1 [m]", "x2 [m]", "y2 [m]"),
        M=np.diag([M1, M1, M2, M2]), G=np.zeros((4, 4)), D=coupling(d1, d2), K=coupling(c1, c2),
        planes={"balancer": rotor, "body": body},
        unbalances=listed_unbalance("balancer", unbalance, unbalance_angle),
        gravity=weight_force(g, (M1, body), (M2, rotor)), gravity_plane=g,
        source="Filimonikhin (2004) 2.5.2, eq. (2.32); c1 body-ground, c2 rotor-body",
    )


def _check(M1, M2, c1, c2):
    """Validated ``(M1 [kg], M2 [kg], c1 [N/m], c2 [N/m])`` of (2.32)."""
    return (positive("body_mass", M1, "kg"), positive("rotor_mass", M2, "kg"),
            positive("body_stiffness", c1, "N/m"), positive("rotor_stiffness", c2, "N/m"))


def two_mass_natural_frequencies(body_mass, rotor_mass, body_stiffness, rotor_stiffness):
    """Undamped natural frequencies (w1, w3) [rad/s] of (2.32), from (2.39):
    ``x_{1,2} = p -/+ sqrt(p^2 - c1 c2/(M1 M2))``, ``p = [M1 c2 + M2 (c1 + c2)]/(2 M1 M2)``.
    Each is a double (forward and backward whirl) frequency of the isotropic system."""
    M1, M2, c1, c2 = _check(body_mass, rotor_mass, body_stiffness, rotor_stiffness)
    p = (M1 * c2 + M2 * (c1 + c2)) / (2.0 * M1 * M2)
    q = c1 * c2 / (M1 * M2)
    root = math.sqrt(p * p - q)        # p^2 - q > 0 always (discriminant of (2.37))
    x1 = q / (p + root)                # = p - root, without cancellation
    x2 = p + root
    return np.array([math.sqrt(x1), math.sqrt(x2)])


def two_mass_critical_speeds(body_mass, rotor_mass, body_stiffness, rotor_stiffness):
    """Critical speeds (2.43) [rad/s]: ``w1 = sqrt(x1) < w2 = sqrt((c1 + c2)/M1) < w3 = sqrt(x2)``;
    w2 is the body's anti-resonance (absorber) frequency, ``Delta(w2^2) = -c2^2 < 0``."""
    M1, M2, c1, c2 = _check(body_mass, rotor_mass, body_stiffness, rotor_stiffness)
    w1, w3 = two_mass_natural_frequencies(M1, M2, c1, c2)
    return np.array([w1, math.sqrt((c1 + c2) / M1), w3])


def two_mass_working_ranges(body_mass, rotor_mass, body_stiffness, rotor_stiffness):
    """Closed-form ``(critical_speeds, ranges)`` of (2.43)-(2.44), in the format of
    :func:`stand.model.rotors.structure.working_ranges`: ranges ``[(w1, w2), (w3, inf)]``."""
    w = two_mass_critical_speeds(body_mass, rotor_mass, body_stiffness, rotor_stiffness)
    return w, [(float(w[0]), float(w[1])), (float(w[2]), math.inf)]


def two_mass_criterion(omega, body_mass, rotor_mass, body_stiffness, rotor_stiffness,
                       unbalance: float = 1.0):
    """Rotor deflection along the unbalance (2.42) [m]:
    ``r_2e = (c1 + c2 - M1 w^2) s w^2 / Delta(w^2)`` (constant in time, so it equals
    the revolution average r_bar of (2.15)); ``omega`` [rad/s] may be an array."""
    M1, M2, c1, c2 = _check(body_mass, rotor_mass, body_stiffness, rotor_stiffness)
    x = np.asarray(omega, dtype=float) ** 2
    delta = M1 * M2 * x * x - (M1 * c2 + M2 * (c1 + c2)) * x + c1 * c2
    return (c1 + c2 - M1 * x) * unbalance * x / delta
