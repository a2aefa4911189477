"""Model 2.5.3: a rotor during cutting / grinding, digest ch2_ch3 section 2.3,
equations (2.45)-(2.55).

A rigid rotor of mass M presses on the machined surface (x tangential, y
normal).  Its supports have principal stiffnesses ``c_xi``, ``c_eta`` rotated
by ``alpha`` from (x, y), giving (2.47)::

    c_x  = c_xi cos^2 a + c_eta sin^2 a,
    c_xy = (c_xi - c_eta) sin a cos a,
    c_y  = c_xi sin^2 a + c_eta cos^2 a.

With Coulomb friction T = f N (2.45) and a contact that is never lost, with a
constant approach y = y0 (2.49), the y equation of (2.48) gives the normal
reaction and the x equation reduces to one degree of freedom (2.50)::

    N = c_y y0 + c_xy x - s w^2 sin wt + M g,
    M x'' + (c_x + f c_xy) x = s w^2 (cos wt + f sin wt) - f (M g + c_y y0) - c_xy y0.

Derivation of the forcing's f term: T = f N carries N's unbalance term
``-s w^2 sin wt``, and ``-T`` enters the x equation, so the unbalance pushes x
by ``F_x + f F_y``.  In the generic form this is the plane map
``T_u = [[1], [f]]`` (plane ``"unbalance"``): ``T_u^T (F_x, F_y) = F_x + f F_y``.
The rotor's own unbalance is listed in that plane.  The balancer plane keeps the
kinematic map ``T = [[1], [0]]``: the rotor centre is at (x, y0), and y is held
by the contact.

Limitation: the generic structure uses one map both for the displacement of a
plane and for the forces applied to it (virtual work).  Friction breaks that
symmetry.  So the correction weights, which act through ``"balancer"``, do not
feel the f coupling of their y forces (nor ``-f m g`` of their weight).  For
weights much lighter than the rotor this is the criterion's own order of
accuracy.  The engineering criterion is unaffected: both maps give (2.52),
``r_bar = s w^2 / (2 (k - M w^2))`` with ``k = c_x + f c_xy``.
"""
from __future__ import annotations

import math

import numpy as np

from stand.model.rotors._build import check, finite, listed_unbalance, nonnegative, positive
from stand.model.rotors.structure import LinearRotor

__all__ = ["grinding_rotor", "grinding", "rotated_stiffness", "grinding_critical_speed",
           "grinding_working_ranges", "grinding_criterion", "contact_force", "static_offset"]

G0 = 9.81


def rotated_stiffness(c_xi: float, c_eta: float, alpha: float):
    """(2.47): ``(c_x, c_xy, c_y)`` [N/m] of principal stiffnesses c_xi, c_eta [N/m]
    whose axes are rotated by alpha [rad] from the surface axes (x, y)."""
    cxi = positive("c_xi", c_xi, "N/m")
    ceta = positive("c_eta", c_eta, "N/m")
    a = finite("alpha", alpha, "rad")
    ca, sa = math.cos(a), math.sin(a)
    return cxi * ca * ca + ceta * sa * sa, (cxi - ceta) * sa * ca, cxi * sa * sa + ceta * ca * ca


def _effective(mass, c_xi, c_eta, alpha, f):
    """Validated ``(M, f, c_x, c_xy, c_y, k)`` of (2.47), (2.50), with the effective
    stiffness ``k = c_x + f c_xy`` [N/m] checked positive."""
    M = positive("mass", mass, "kg")
    fr = check("f (Coulomb friction coefficient)", f, "-", "nonnegative")
    cx, cxy, cy = rotated_stiffness(c_xi, c_eta, alpha)
    k = cx + fr * cxy
    if not k > 0:
        raise ValueError(f"effective stiffness c_x + f c_xy = {k!r} N/m must be positive "
                         f"(c_x={cx}, c_xy={cxy}, f={fr}); otherwise (2.50) is statically unstable")
    return M, fr, cx, cxy, cy, k


def grinding_rotor(mass: float, c_xi: float, c_eta: float, alpha: float, f: float, y0: float = 0.0,
             damping: float = 0.0, unbalance: float = 0.0, unbalance_angle: float = 0.0,
             g: float = G0) -> LinearRotor:
    """Reduced 1-DOF grinding rotor (2.50) as a :class:`LinearRotor` (alias :func:`grinding`;
    the scene type ``"grinding"`` of :mod:`stand.scene.structure_tables` calls this name).

    Parameters
    ----------
    mass : float
        M [kg].
    c_xi, c_eta : float
        Principal support stiffnesses [N/m].
    alpha : float
        Rotation of the stiffness axes from the surface axes [rad] (2.47).
    f : float
        Coulomb friction coefficient [-] (2.45), >= 0.
    y0 : float, optional
        Constant preload approach [m] (2.49).
    damping : float, optional
        Viscous damping along x [N s/m] (not in the book; default 0).
    unbalance, unbalance_angle : float, optional
        Static unbalance s [kg m] (in plane ``"unbalance"``) and its angle [rad].
    g : float, optional
        Gravity [m/s^2] acting along -y, normal to the surface (2.46).

    Returns
    -------
    LinearRotor
        One coordinate ``x [m]``; planes ``"balancer"`` ``[[1], [0]]`` (centre at
        (x, y0)) and ``"unbalance"`` ``[[1], [f]]`` (the force map of (2.50)).  The
        ``gravity`` field holds the whole constant force of (2.50),
        ``-f (M g + c_y y0) - c_xy y0`` [N] (gravity and preload through the contact),
        so ``K^-1 gravity`` is the offset x1 of (2.51).  ``gravity_plane = (0, -g)``.

    Raises
    ------
    ValueError
        For a non-positive mass or stiffness, negative f, or ``c_x + f c_xy <= 0``.
    """
    M, fr, cx, cxy, cy, k = _effective(mass, c_xi, c_eta, alpha, f)
    d = nonnegative("damping", damping, "N s/m")
    gg = finite("g", g, "m/s^2")
    y0 = finite("y0", y0, "m")
    return LinearRotor(
        name="grinding",
        coords=("x [m]",),
        M=np.array([[M]]), G=np.zeros((1, 1)), D=np.array([[d]]), K=np.array([[k]]),
        planes={"balancer": np.array([[1.0], [0.0]]), "unbalance": np.array([[1.0], [fr]])},
        # the weights in the balancer plane push through the friction too: F_x + f F_y
        force_maps={"balancer": np.array([[1.0], [fr]])},
        unbalances=listed_unbalance("unbalance", unbalance, unbalance_angle),
        gravity=np.array([-fr * (M * gg + cy * y0) - cxy * y0]),
        gravity_plane=np.array([0.0, -gg]),
        source="Filimonikhin (2004) 2.5.3, eqs. (2.47), (2.50); unbalance map [[1],[f]]",
    )


#: Short alias of :func:`grinding_rotor`.
grinding = grinding_rotor


def grinding_critical_speed(mass, c_xi, c_eta, alpha, f):
    """The single critical speed (2.53) [rad/s]: ``w1 = sqrt((c_x + f c_xy)/M)``;
    for a frictionless guide (f = 0) it is (2.55), ``sqrt(c_x/M)``."""
    M, _, _, _, _, k = _effective(mass, c_xi, c_eta, alpha, f)
    return math.sqrt(k / M)


def grinding_working_ranges(mass, c_xi, c_eta, alpha, f):
    """Closed-form ``(critical_speeds, ranges)`` of (2.53)-(2.54): ``([w1], [(w1, inf)])``."""
    w1 = grinding_critical_speed(mass, c_xi, c_eta, alpha, f)
    return np.array([w1]), [(w1, math.inf)]


def grinding_criterion(omega, mass, c_xi, c_eta, alpha, f, unbalance: float = 1.0):
    """Criterion (2.52) [m]: ``r_bar = s w^2 / (2 (c_x + f c_xy - M w^2))``."""
    M, _, _, _, _, k = _effective(mass, c_xi, c_eta, alpha, f)
    x = np.asarray(omega, dtype=float) ** 2
    return unbalance * x / (2.0 * (k - M * x))


def contact_force(x, t, omega, mass, c_xi, c_eta, alpha, y0: float = 0.0, unbalance: float = 0.0,
                  unbalance_angle: float = 0.0, g: float = G0):
    """Normal contact reaction N [N] of (2.50) at constant spin omega [rad/s]:
    ``N = c_y y0 + c_xy x - s w^2 sin(w t + angle) + M g``.

    ``x`` [m] and ``t`` [s] may be arrays.  The reduction (2.49)-(2.50) holds only
    while ``N >= 0`` (contact kept); callers check this along a simulated run.
    """
    M = positive("mass", mass, "kg")
    _, cxy, cy = rotated_stiffness(c_xi, c_eta, alpha)
    x = np.asarray(x, dtype=float)
    t = np.asarray(t, dtype=float)
    return (cy * y0 + cxy * x - unbalance * omega * omega * np.sin(omega * t + unbalance_angle)
            + M * g)


def static_offset(mass, c_xi, c_eta, alpha, f, y0: float = 0.0, g: float = G0) -> float:
    """Constant part x1 [m] of the steady solution (2.51):
    ``x1 = -[f (M g + c_y y0) + c_xy y0] / (c_x + f c_xy)``."""
    M, fr, _, cxy, cy, k = _effective(mass, c_xi, c_eta, alpha, f)
    return -(fr * (M * g + cy * y0) + cxy * y0) / k
