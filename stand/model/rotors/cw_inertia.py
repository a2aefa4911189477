"""Mass-inertia characteristics of non-classical correction weights (CWs):
book Tables 2.1 and 2.2 and the auxiliary formulas (2.13)-(2.14)
(digest ch2_ch3 section 3.2).

A CW is a rigid body hung at a point K of the shaft axis.  Axes through K:
``xi`` normal to the figure's plane, ``eta`` and ``zeta`` in it, the centre of
mass on the ``-zeta`` axis at distance ``l`` (2.8).  The tabulated quantities:

* ``m`` [kg] mass, ``l`` [m] distance K - centre of mass, ``S = m l`` [kg m]
  balancing capacity (2.1);
* Table 2.1 (bodies satisfying (2.7)-(2.8)): ``A = J_xi`` and
  ``B = J_eta = J_zeta`` [kg m^2] about K;
* Table 2.2 (bodies satisfying (2.10)-(2.11)): ``A = J_xi = J_eta = J_zeta``
  (and the volume ``V`` [m^3] for the solid bodies).

``gamma`` is used as the density [kg/m^3] (the book calls it "specific
weight" but uses ``m = gamma V`` (2.13)).  ``a = r / R`` is the ratio of the
inner to the outer radius.

Corrections (digest section 3.2, 7.4), each with a ``paper_exact`` flag:

* Table 2.1 half-ring: ``A = m0 R^2 (1 + a^2)/2``, ``B = m0 R^2 (1 + a^2)/4``
  (printed ``(1 - a^2)``; the printed form contradicts the hollow
  half-cylinder row of the same table, whose ``A = pi R^4 h gamma (1-a^4)/4 =
  m R^2 (1 + a^2)/2``);
* (2.14) rod about its end: ``m0 l0^2 / 3`` (printed ``/ 2``; the table itself
  uses 1/3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

from stand.model.rotors._build import check, positive

__all__ = [
    "CWInertia", "two_point_pendulums", "two_rods", "two_physical_pendulums", "half_ring",
    "half_disk", "hollow_half_cylinder", "solid_half_cylinder", "three_point_pendulums",
    "three_rods", "three_physical_pendulums", "solid_hemisphere", "hollow_hemisphere",
    "pendulum_moment", "rod_moment", "cylinder_volume", "cylinder_moment",
    "half_cylinder_capacity",
]

SQ2 = math.sqrt(2.0)
SQ3 = math.sqrt(3.0)


@dataclass(frozen=True)
class CWInertia:
    """Mass-inertia characteristics of one CW (Tables 2.1/2.2).

    Attributes
    ----------
    m : float  mass [kg]
    l : float  distance from the suspension point K to the centre of mass [m]
    S : float  balancing capacity ``m l`` [kg m] (2.1)
    A : float  moment of inertia about xi through K [kg m^2]
    B : float  moment about eta and zeta through K [kg m^2] (= A for Table 2.2)
    V : float or None  volume [m^3] (solid bodies only)
    source : str
    """

    m: float
    l: float
    S: float
    A: float
    B: float
    V: Optional[float] = None
    source: str = ""


def _ratio(a):
    """The radius ratio ``a = r/R`` [-], 0 <= a < 1."""
    v = check("a = r/R", a, "-", "nonnegative")
    if not v < 1.0:
        raise ValueError(f"a = r/R must satisfy 0 <= a < 1 [-], got {a!r}")
    return v


def _l_half_annulus(R, a):
    """Centroid distance of a half annulus ``4R(1 - a^3) / (3 pi (1 - a^2))`` [m]."""
    return 4.0 * R * (1 - a ** 3) / (3.0 * math.pi * (1 - a ** 2))


# ------------------------------------------------------------ auxiliary (2.14)
def pendulum_moment(m0: float, l0: float) -> float:
    """(2.14): point pendulum about its pivot, ``m0 l0^2`` [kg m^2]."""
    return positive("m0", m0, "kg") * positive("l0", l0, "m") ** 2


def rod_moment(m0: float, l0: float, paper_exact: bool = False) -> float:
    """(2.14): uniform thin rod of length ``l0`` [m] about its end,
    ``m0 l0^2 / 3`` [kg m^2] (corrected; ``paper_exact=True``: the printed ``/ 2``)."""
    return pendulum_moment(m0, l0) / (2.0 if paper_exact else 3.0)


def cylinder_volume(R: float, h: float) -> float:
    """(2.14): ``pi R^2 h`` [m^3]."""
    return math.pi * positive("R", R, "m") ** 2 * positive("h", h, "m")


def cylinder_moment(m0: float, R: float) -> float:
    """(2.14): solid cylinder about its axis, ``m0 R^2 / 2`` [kg m^2]."""
    return 0.5 * positive("m0", m0, "kg") * positive("R", R, "m") ** 2


def half_cylinder_capacity(m0: float, R: float) -> float:
    """(2.14): capacity of a solid half-cylinder (half-disk), ``4 R m0 / (3 pi)`` [kg m]."""
    return 4.0 * positive("R", R, "m") * positive("m0", m0, "kg") / (3.0 * math.pi)


# ------------------------------------------------------------------ Table 2.1
def two_point_pendulums(m0: float, l0: float) -> CWInertia:
    """Table 2.1 row 1: two point pendulums (mass ``m0`` [kg], length ``l0`` [m]) at 90 deg,
    symmetric about -zeta: ``m = 2 m0``, ``l = l0/sqrt 2``, ``A = 2 m0 l0^2``, ``B = m0 l0^2``."""
    m0 = positive("m0", m0, "kg")
    l0 = positive("l0", l0, "m")
    return CWInertia(2 * m0, l0 / SQ2, SQ2 * m0 * l0, 2 * m0 * l0 ** 2, m0 * l0 ** 2,
                     source="Table 2.1 row 1")


def two_rods(m0: float, l0: float) -> CWInertia:
    """Table 2.1 row 2: two uniform rods (``m0`` [kg], length ``l0`` [m]) at 90 deg:
    ``l = l0/(2 sqrt 2)``, ``A = 2 m0 l0^2/3``, ``B = m0 l0^2/3``."""
    m0 = positive("m0", m0, "kg")
    l0 = positive("l0", l0, "m")
    J = rod_moment(m0, l0)
    return CWInertia(2 * m0, l0 / (2 * SQ2), SQ2 * m0 * l0 / 2, 2 * J, J, source="Table 2.1 row 2")


def two_physical_pendulums(m0: float, l0: float, Jx0: float, Jy0: float, Jz0: float) -> CWInertia:
    """Table 2.1 row 3: two physical pendulums at 90 deg (each: mass ``m0`` [kg],
    centre of mass at ``l0`` [m] from K, principal moments about K ``Jx0`` (normal
    to the figure), ``Jy0`` (in the figure, across), ``Jz0`` (along the pendulum) [kg m^2]):
    ``A = 2 Jx0``, ``B = Jy0 + Jz0``."""
    m0 = positive("m0", m0, "kg")
    l0 = positive("l0", l0, "m")
    Jx0, Jy0, Jz0 = (positive(n, v, "kg m^2") for n, v in (("Jx0", Jx0), ("Jy0", Jy0), ("Jz0", Jz0)))
    return CWInertia(2 * m0, l0 / SQ2, SQ2 * m0 * l0, 2 * Jx0, Jy0 + Jz0, source="Table 2.1 row 3")


def half_ring(R: float, m0: float, a: float, paper_exact: bool = False) -> CWInertia:
    """Table 2.1 row 4: thin planar half-ring (half annulus) of outer radius ``R`` [m],
    ``a = r/R``, mass ``m0`` [kg], centre K at the centre of the annulus::

        l = 4R(1 - a^3) / (3 pi (1 - a^2)),  A = m0 R^2 (1 + a^2)/2,  B = m0 R^2 (1 + a^2)/4

    ``paper_exact=True`` gives the printed ``(1 - a^2)`` in A and B (an error:
    see the module docstring).
    """
    R = positive("R", R, "m")
    m0 = positive("m0", m0, "kg")
    a = _ratio(a)
    f = (1 - a * a) if paper_exact else (1 + a * a)
    l = _l_half_annulus(R, a)
    return CWInertia(m0, l, m0 * l, 0.5 * m0 * R * R * f, 0.25 * m0 * R * R * f,
                     source="Table 2.1 row 4" + (" (printed 1 - a^2)" if paper_exact else
                                                " (corrected 1 + a^2)"))


def half_disk(R: float, m0: float) -> CWInertia:
    """Table 2.1 row 5: thin half-disk: ``l = 4R/(3 pi)``, ``A = m0 R^2/2``, ``B = m0 R^2/4``."""
    r = half_ring(R, m0, 0.0)
    return CWInertia(r.m, r.l, r.S, r.A, r.B, source="Table 2.1 row 5")


def hollow_half_cylinder(R: float, h: float, gamma: float, a: float) -> CWInertia:
    """Table 2.1 row 6: hollow half-cylinder (outer ``R``, inner ``a R``, thickness
    ``h`` along xi, centred on K) [m], density ``gamma`` [kg/m^3]::

        V = pi R^2 h (1 - a^2)/2,  m = gamma V,  S = 2 R^3 h gamma (1 - a^3)/3,
        A = pi R^4 h gamma (1 - a^4)/4,
        B = pi R^4 h gamma (1 - a^4)/8 + pi R^2 h^3 gamma (1 - a^2)/24
    """
    R = positive("R", R, "m")
    h = positive("h", h, "m")
    g = positive("gamma", gamma, "kg/m^3")
    a = _ratio(a)
    V = 0.5 * math.pi * R * R * h * (1 - a * a)
    pi = math.pi
    return CWInertia(g * V, _l_half_annulus(R, a), 2.0 / 3.0 * R ** 3 * h * g * (1 - a ** 3),
                     pi * R ** 4 * h * g * (1 - a ** 4) / 4,
                     pi * R ** 4 * h * g * (1 - a ** 4) / 8 + pi * R * R * h ** 3 * g * (1 - a * a) / 24,
                     V, "Table 2.1 row 6")


def solid_half_cylinder(R: float, h: float, gamma: float) -> CWInertia:
    """Table 2.1 row 7: solid half-cylinder: ``m = pi R^2 h gamma/2``, ``l = 4R/(3 pi)``,
    ``S = 2 R^3 h gamma/3``, ``A = pi R^4 h gamma/4``,
    ``B = pi R^2 h gamma (R^2/8 + h^2/24)``."""
    c = hollow_half_cylinder(R, h, gamma, 0.0)
    return CWInertia(c.m, c.l, c.S, c.A, c.B, c.V, "Table 2.1 row 7")


# ------------------------------------------------------------------ Table 2.2
def three_point_pendulums(m0: float, l0: float) -> CWInertia:
    """Table 2.2 row 1: three mutually perpendicular point pendulums:
    ``m = 3 m0``, ``l = l0/sqrt 3``, ``S = sqrt 3 m0 l0``, ``A = 2 m0 l0^2``."""
    m0 = positive("m0", m0, "kg")
    l0 = positive("l0", l0, "m")
    A = 2 * m0 * l0 ** 2
    return CWInertia(3 * m0, l0 / SQ3, SQ3 * m0 * l0, A, A, source="Table 2.2 row 1")


def three_rods(m0: float, l0: float) -> CWInertia:
    """Table 2.2 row 2: three mutually perpendicular uniform rods:
    ``l = l0/(2 sqrt 3)``, ``S = sqrt 3 m0 l0/2``, ``A = 2 m0 l0^2/3``."""
    m0 = positive("m0", m0, "kg")
    l0 = positive("l0", l0, "m")
    A = 2 * rod_moment(m0, l0)
    return CWInertia(3 * m0, l0 / (2 * SQ3), SQ3 * m0 * l0 / 2, A, A, source="Table 2.2 row 2")


def three_physical_pendulums(m0: float, l0: float, Jx0: float, Jz0: float) -> CWInertia:
    """Table 2.2 row 3: three mutually perpendicular physical pendulums, bodies of
    revolution (moments about K: ``Jx0 = Jy0`` across, ``Jz0`` along, [kg m^2]):
    ``l = l0/sqrt 3``, ``A = Jz0 + 2 Jx0``."""
    m0 = positive("m0", m0, "kg")
    l0 = positive("l0", l0, "m")
    Jx0 = positive("Jx0", Jx0, "kg m^2")
    Jz0 = positive("Jz0", Jz0, "kg m^2")
    A = Jz0 + 2 * Jx0
    return CWInertia(3 * m0, l0 / SQ3, SQ3 * m0 * l0, A, A, source="Table 2.2 row 3")


def hollow_hemisphere(R: float, gamma: float, a: float) -> CWInertia:
    """Table 2.2 row 5: hollow hemisphere (outer ``R``, inner ``a R`` [m], density
    ``gamma`` [kg/m^3]), K at the centre::

        V = 2 pi R^3 (1 - a^3)/3,  l = 3R(1 - a^4) / (8 (1 - a^3)),
        S = pi R^4 gamma (1 - a^4)/4,  A = 4 pi R^5 gamma (1 - a^5)/15
    """
    R = positive("R", R, "m")
    g = positive("gamma", gamma, "kg/m^3")
    a = _ratio(a)
    V = 2.0 / 3.0 * math.pi * R ** 3 * (1 - a ** 3)
    A = 4.0 / 15.0 * math.pi * R ** 5 * g * (1 - a ** 5)
    return CWInertia(g * V, 3.0 / 8.0 * R * (1 - a ** 4) / (1 - a ** 3),
                     math.pi * R ** 4 * g * (1 - a ** 4) / 4, A, A, V, "Table 2.2 row 5")


def solid_hemisphere(R: float, gamma: float) -> CWInertia:
    """Table 2.2 row 4: solid hemisphere: ``V = 2 pi R^3/3``, ``l = 3R/8``,
    ``S = pi R^4 gamma/4``, ``A = 4 pi R^5 gamma/15`` (= 2 m R^2/5)."""
    c = hollow_hemisphere(R, gamma, 0.0)
    return CWInertia(c.m, c.l, c.S, c.A, c.B, c.V, "Table 2.2 row 4")
