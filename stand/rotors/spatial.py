"""Rigid rotor in spatial motion: book sections 2.7.1-2.7.3 and paper 003 (model M2).

Coordinates ``q = (x, y, alpha, beta)``: the translation of the centre of mass
[m] and the Resal tilts [rad] (digest ch2_ch3 section 2.6).  The equations are
the book's (2.118) with the gyroscopic terms of (2.122)::

    M x''                     + k_1j q_j = s w^2 cos(w t)
    M y''                     + k_2j q_j = s w^2 sin(w t)
    A alpha'' + C w beta'     + k_3j q_j = -s a w^2 sin(w t)
    A beta''  - C w alpha'    + k_4j q_j =  s a w^2 cos(w t)

i.e. ``G = [[0,0,0,0],[0,0,0,0],[0,0,0,C],[0,0,-C,0]]`` per unit spin.  A point
of the axis at axial distance ``a`` from the centre of mass moves as (2.131)
``x_B = x + a beta``, ``y_B = y - a alpha``, so its plane map is
``T(a) = [[1, 0, 0, a], [0, 1, -a, 0]]``; the unbalance forcing of
:class:`stand.rotors.LinearRotor` (``T^T s w^2 (cos, sin)``) is then exactly the
right-hand side above (the factor ``a`` in the moment equations is the one
missing from the printed (2.119)-(2.120); digest section 2.6).

Axial coordinate convention.  ``a`` (planes) and the support positions share
one axial coordinate ``zeta`` measured from the centre of mass, with
``K[x, beta] = sum_i c_ix zeta_i``.  Table 2.4 (book) puts support / shaft
segment 1 at ``zeta = +l1`` and 2 at ``zeta = -l2`` (this is what makes its
printed ``c14`` signs come out; checked against beam theory), while paper 003
(eq. (12), (14)) puts support 1 at ``zeta = -l1`` and 2 at ``zeta = +l2``.
Each constructor states which one it uses.

Contents
--------
* :class:`SupportStiffness` with the forms (2.118), (2.119), (2.121)/(2.122)
  and the Table 2.4 schemes (:func:`two_elastic_supports`,
  :func:`cantilever_disk`, :func:`disk_on_hinged_shaft`,
  :func:`disk_on_clamped_shaft` with the corrected ``c33 = 4EJ(l1+l2)/(l1 l2)``).
* :func:`spatial_rotor`: the :class:`LinearRotor` of (2.118)/(2.122).
* Closed forms of 2.7.2/2.7.3: :func:`delta` (2.126), :func:`r_ac` (2.133),
  :func:`high_speed_limit` (2.134)-(2.137), :func:`auxiliary_speed` (2.138),
  :func:`frequency_polynomial` / :func:`frequency_roots` (2.139)-(2.141),
  :func:`critical_speeds` (2.142)-(2.153), :func:`symmetric_critical_speeds`
  (2.155)-(2.159), :func:`two_balancer_ranges` (2.160).
* Paper 003 (M2): :func:`two_support_rotor` -> :class:`TwoSupportRotor` with
  (14), (31)-(34), (17)-(19), (26), (36)-(41), (43) and the compact criterion
  "K_xi(w) and K_eta(w) negative definite" (papers digest sections 2.3-2.6).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .structure import LinearRotor, Unbalance

__all__ = [
    "SupportStiffness", "two_elastic_supports", "isotropic_supports", "cantilever_disk",
    "disk_on_hinged_shaft", "disk_on_clamped_shaft", "plane_map", "spatial_rotor",
    "static_unbalance", "couple_unbalance", "rotor_shape", "delta", "r_ac",
    "high_speed_limit", "balances_at_high_speed", "auxiliary_speed", "frequency_polynomial",
    "frequency_roots", "SpeedRegions", "critical_speeds", "symmetric_critical_speeds",
    "intersect_ranges", "two_balancer_ranges", "TwoSupportRotor", "two_support_rotor",
]

COORDS = ("x [m]", "y [m]", "alpha [rad]", "beta [rad]")
_REL = 1e-12


# ----------------------------------------------------------------- validation
def _positive(name: str, value, unit: str) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0.0):
        raise ValueError(f"{name} must be a finite positive number [{unit}], got {value!r}")
    return v


def _nonneg(name: str, value, unit: str) -> float:
    v = float(value)
    if not (math.isfinite(v) and v >= 0.0):
        raise ValueError(f"{name} must be a finite non-negative number [{unit}], got {value!r}")
    return v


def _finite(name: str, value, unit: str) -> float:
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite [{unit}], got {value!r}")
    return v


def _check_isotropic_coefficients(c11, c14, c33):
    c11 = _positive("c11", c11, "N/m")
    c33 = _positive("c33", c33, "N m/rad")
    c14 = _finite("c14", c14, "N/rad")
    if c11 * c33 <= c14 * c14:
        raise ValueError(f"supports must be positive definite: c11*c33 = {c11 * c33!r} "
                         f"[N^2/rad] must exceed c14^2 = {c14 * c14!r} [N^2/rad^2]")
    return c11, c14, c33


# ------------------------------------------------------------------ stiffness
@dataclass(frozen=True, eq=False)
class SupportStiffness:
    """Symmetric 4 x 4 support stiffness (or damping) matrix of (2.118) in
    ``q = (x, y, alpha, beta)``.

    Units: ``k_11, k_12, k_22`` [N/m], ``k_13, k_14, k_23, k_24`` [N/rad],
    ``k_33, k_34, k_44`` [N m/rad] (for a damping matrix, the same per second).

    Build it with :meth:`isotropic` (2.121)-(2.122), :meth:`principal` (2.119)
    or :meth:`general` (2.118), or with the Table 2.4 functions.
    """

    matrix: np.ndarray
    source: str = "(2.118)"

    def __post_init__(self):
        k = np.asarray(self.matrix, dtype=float)
        if k.shape != (4, 4) or not np.all(np.isfinite(k)):
            raise ValueError(f"support matrix must be a finite 4x4 array in (x, y, alpha, beta), "
                             f"got shape {k.shape}")
        if not np.allclose(k, k.T, rtol=0, atol=1e-12 * (1 + np.abs(k).max())):
            raise ValueError("support matrix k_ij of (2.118) must be symmetric")
        object.__setattr__(self, "matrix", 0.5 * (k + k.T))

    # constructors -------------------------------------------------------
    @classmethod
    def isotropic(cls, c11: float, c14: float, c33: float,
                  source: str = "(2.121)-(2.122)") -> "SupportStiffness":
        """Isotropic supports (2.121)-(2.122): ``c22 = c11``, ``c44 = c33``, ``c23 = c14``.

        Parameters
        ----------
        c11 : float  translational stiffness [N/m] (> 0)
        c14 : float  coupling [N/rad] (``K[x, beta] = c14``, ``K[y, alpha] = -c14``)
        c33 : float  tilting stiffness [N m/rad] (> 0), with ``c11 c33 > c14^2``
        """
        c11, c14, c33 = _check_isotropic_coefficients(c11, c14, c33)
        return cls.principal(c11, c11, c33, c33, c14, c14, source=source)

    @classmethod
    def principal(cls, c11, c22, c33, c44, c14=0.0, c23=0.0,
                  source: str = "(2.119)") -> "SupportStiffness":
        """Anisotropic supports with common principal directions (2.119)::

            M x'' + c11 x + c14 beta = ...,      M y'' + c22 y - c23 alpha = ...
            A alpha'' + ... + c33 alpha - c23 y,  A beta'' + ... + c44 beta + c14 x
        """
        k = np.zeros((4, 4))
        k[0, 0], k[1, 1], k[2, 2], k[3, 3] = (float(c11), float(c22), float(c33), float(c44))
        k[0, 3] = k[3, 0] = float(c14)
        k[1, 2] = k[2, 1] = -float(c23)
        return cls(k, source)

    @classmethod
    def general(cls, k) -> "SupportStiffness":
        """The most general symmetric ``k_ij`` of (2.118) (4 x 4, SI units of the class)."""
        return cls(np.asarray(k, dtype=float), "(2.118)")

    # queries ------------------------------------------------------------
    @property
    def is_isotropic(self) -> bool:
        """True for the form (2.122) (c22 = c11, c44 = c33, c23 = c14, no other coupling)."""
        k = self.matrix
        tol = _REL * (1 + np.abs(k).max())
        iso = np.zeros((4, 4))
        iso[0, 0] = iso[1, 1] = k[0, 0]
        iso[2, 2] = iso[3, 3] = k[2, 2]
        iso[0, 3] = iso[3, 0] = k[0, 3]
        iso[1, 2] = iso[2, 1] = -k[0, 3]
        return bool(np.all(np.abs(k - iso) <= tol))

    def isotropic_coefficients(self):
        """``(c11, c14, c33)`` of (2.122); ValueError if the supports are anisotropic."""
        if not self.is_isotropic:
            raise ValueError(f"supports {self.source} are not isotropic (2.121); use the "
                             "generic LinearRotor criterion instead of the closed forms")
        k = self.matrix
        return float(k[0, 0]), float(k[0, 3]), float(k[2, 2])


def _supports_at(positions, cx, cy, source) -> SupportStiffness:
    """Point supports at axial positions ``zeta_i`` [m] with x/y stiffnesses [N/m]:
    potential ``sum 1/2 cx_i (x + zeta_i beta)^2 + 1/2 cy_i (y - zeta_i alpha)^2``."""
    k = np.zeros((4, 4))
    for z, kx, ky in zip(positions, cx, cy):
        tx = np.array([1.0, 0.0, 0.0, z])
        ty = np.array([0.0, 1.0, -z, 0.0])
        k += kx * np.outer(tx, tx) + ky * np.outer(ty, ty)
    return SupportStiffness(k, source)


def two_elastic_supports(l1: float, l2: float, c1: float, c2: float, c3: float,
                         c4: float) -> SupportStiffness:
    """Table 2.4 row 1: rigid rotor on two elastic (possibly anisotropic) supports.

    Support 1 ("left", stiffness ``c1`` along x, ``c2`` along y [N/m]) at
    ``zeta = +l1`` and support 2 ("right", ``c3`` along x, ``c4`` along y) at
    ``zeta = -l2`` (the book's sign convention, module docstring)::

        c11 = c1 + c3, c14 = c1 l1 - c3 l2, c22 = c2 + c4, c23 = c2 l1 - c4 l2,
        c33 = c2 l1^2 + c4 l2^2, c44 = c1 l1^2 + c3 l2^2

    Parameters
    ----------
    l1, l2 : float  distances of the supports from the centre of mass [m] (> 0)
    c1, c2, c3, c4 : float  support stiffnesses [N/m] (> 0)
    """
    l1 = _positive("l1", l1, "m")
    l2 = _positive("l2", l2, "m")
    c1, c2, c3, c4 = (_positive(n, v, "N/m") for n, v in
                      (("c1", c1), ("c2", c2), ("c3", c3), ("c4", c4)))
    return SupportStiffness.principal(c1 + c3, c2 + c4, c2 * l1 ** 2 + c4 * l2 ** 2,
                                      c1 * l1 ** 2 + c3 * l2 ** 2, c1 * l1 - c3 * l2,
                                      c2 * l1 - c4 * l2, source="Table 2.4 row 1")


def isotropic_supports(l1: float, l2: float, c_1: float, c_2: float) -> SupportStiffness:
    """Table 2.4 row 1 with isotropic supports (``c2 = c1``, ``c4 = c3``): support 1
    of stiffness ``c_1`` [N/m] at ``zeta = +l1``, support 2 of ``c_2`` at ``zeta = -l2``."""
    return two_elastic_supports(l1, l2, c_1, c_1, c_2, c_2)


def _EJ(E, J):
    return _positive("E", E, "Pa") * _positive("J", J, "m^4")


def cantilever_disk(E: float, J: float, l: float) -> SupportStiffness:
    """Table 2.4 row 2: disk at the free end of a clamped (cantilever) massless shaft.

    ``c11 = 12EJ/l^3``, ``c14 = 6EJ/l^2``, ``c33 = 4EJ/l`` (clamp at ``zeta = +l``).

    Parameters
    ----------
    E : float  Young's modulus [Pa];  J : float  area moment of the section [m^4]
    l : float  shaft length [m]
    """
    EJ = _EJ(E, J)
    l = _positive("l", l, "m")
    return SupportStiffness.isotropic(12 * EJ / l ** 3, 6 * EJ / l ** 2, 4 * EJ / l,
                                      "Table 2.4 row 2")


def disk_on_hinged_shaft(E: float, J: float, l1: float, l2: float) -> SupportStiffness:
    """Table 2.4 row 3: disk on a massless shaft simply supported (hinged) at both ends,
    at distances ``l1`` (end 1, ``zeta = +l1``) and ``l2`` (end 2, ``zeta = -l2``) [m]::

        c11 = 3EJ(l1^3 + l2^3)/(l1^3 l2^3), c14 = 3EJ(l2^2 - l1^2)/(l1^2 l2^2),
        c33 = 3EJ(l1 + l2)/(l1 l2)

    (the sum of two pinned-far-end segments).
    """
    EJ = _EJ(E, J)
    l1 = _positive("l1", l1, "m")
    l2 = _positive("l2", l2, "m")
    return SupportStiffness.isotropic(
        3 * EJ * (l1 ** 3 + l2 ** 3) / (l1 ** 3 * l2 ** 3),
        3 * EJ * (l2 ** 2 - l1 ** 2) / (l1 ** 2 * l2 ** 2),
        3 * EJ * (l1 + l2) / (l1 * l2), "Table 2.4 row 3")


def disk_on_clamped_shaft(E: float, J: float, l1: float, l2: float,
                          paper_exact: bool = False) -> SupportStiffness:
    """Table 2.4 row 4: disk on a massless shaft clamped at both ends (``l1`` at
    ``zeta = +l1``, ``l2`` at ``zeta = -l2``) [m]::

        c11 = 12EJ(l1^3 + l2^3)/(l1^3 l2^3), c14 = 6EJ(l2^2 - l1^2)/(l1^2 l2^2),
        c33 = 4EJ(l1 + l2)/(l1 l2)          (corrected)

    The book prints ``c33 = 6EJ(l1 + l2)/(l1 l2)``; a clamped-guided segment of
    length l has rotational stiffness 4EJ/l, so the corrected value is
    ``4EJ/l1 + 4EJ/l2`` (digest ch2_ch3 section 2.6, 7.4).  ``paper_exact=True``
    restores the printed 6EJ (for reproducing the book only; note that the
    printed matrix is still positive definite, so no error is raised).
    """
    EJ = _EJ(E, J)
    l1 = _positive("l1", l1, "m")
    l2 = _positive("l2", l2, "m")
    f33 = 6.0 if paper_exact else 4.0
    return SupportStiffness.isotropic(
        12 * EJ * (l1 ** 3 + l2 ** 3) / (l1 ** 3 * l2 ** 3),
        6 * EJ * (l2 ** 2 - l1 ** 2) / (l1 ** 2 * l2 ** 2),
        f33 * EJ * (l1 + l2) / (l1 * l2),
        "Table 2.4 row 4" + (" (printed 6EJ)" if paper_exact else " (corrected 4EJ)"))


# --------------------------------------------------------------- the rotor
def plane_map(a: float) -> np.ndarray:
    """Plane map (2.131) of the axis point at axial distance ``a`` [m] from the
    centre of mass: ``(x_B, y_B) = (x + a beta, y - a alpha)``."""
    a = _finite("a", a, "m")
    return np.array([[1.0, 0.0, 0.0, a], [0.0, 1.0, -a, 0.0]])


def static_unbalance(s: float, angle: float = 0.0, a: float = 0.0):
    """A static unbalance ``s`` [kg m] at ``angle`` [rad] in the plane ``a`` [m]
    (default: the centre-of-mass plane), as a list of ``(a, s, angle)``."""
    return [(float(a), _nonneg("s", s, "kg m"), float(angle))]


def couple_unbalance(s: float, a1: float, a2: float, angle: float = 0.0):
    """A couple unbalance: ``s`` [kg m] at ``angle`` in plane ``a1`` and ``s`` at
    ``angle + pi`` in plane ``a2`` [m] (moment ``s (a1 - a2)`` [kg m^2], no static part)."""
    s = _nonneg("s", s, "kg m")
    if float(a1) == float(a2):
        raise ValueError(f"couple unbalance needs two different planes, got a1 = a2 = {a1!r} m")
    return [(float(a1), s, float(angle)), (float(a2), s, float(angle) + math.pi)]


def spatial_rotor(M: float, A: float, C: float, supports: SupportStiffness,
                  balancers=(0.0,), unbalances=(), damping=None,
                  name: str = "spatial_rigid") -> LinearRotor:
    """Rigid rotor in spatial motion, (2.118) with the gyroscopic terms of (2.122).

    Parameters
    ----------
    M : float  mass [kg];  A : float  transverse central moment [kg m^2];
    C : float  polar moment [kg m^2]
    supports : SupportStiffness  (isotropic (2.122), principal (2.119) or general (2.118))
    balancers : float or sequence of float
        Axial positions ``a`` [m] of the balancer planes from the centre of
        mass (one or two), named ``"balancer1"``, ``"balancer2"``, ...
    unbalances : sequence of (a [m], s [kg m], angle [rad])
        Unbalances, each in its own plane ``"unbalance1"``, ...; see
        :func:`static_unbalance`, :func:`couple_unbalance`.
    damping : SupportStiffness or (4, 4) array, optional
        Viscous damping matrix [N s/m, N s/rad, N m s/rad] (default none, as in the book).

    Returns
    -------
    LinearRotor
        Coordinates (x, y, alpha, beta); planes ``"com"`` (a = 0), the balancer
        and unbalance planes.
    """
    M = _positive("M", M, "kg")
    A = _positive("A", A, "kg m^2")
    C = _nonneg("C", C, "kg m^2")
    if not isinstance(supports, SupportStiffness):
        supports = SupportStiffness.general(supports)
    if damping is None:
        D = np.zeros((4, 4))
    else:
        D = (damping.matrix if isinstance(damping, SupportStiffness)
             else SupportStiffness.general(damping).matrix)
    bal = np.atleast_1d(np.asarray(balancers, dtype=float))
    planes = {"com": plane_map(0.0)}
    for j, a in enumerate(bal, 1):
        planes[f"balancer{j}"] = plane_map(a)
    ubs = []
    for j, u in enumerate(unbalances, 1):
        try:
            a, s, ang = u
        except (TypeError, ValueError):
            raise ValueError(f"unbalance {j} must be (a [m], s [kg m], angle [rad]), got {u!r}")
        planes[f"unbalance{j}"] = plane_map(a)
        ubs.append(Unbalance(f"unbalance{j}", _nonneg("s", s, "kg m"), float(ang)))
    G = np.zeros((4, 4))
    G[2, 3], G[3, 2] = C, -C
    return LinearRotor(name=name, coords=COORDS, M=np.diag([M, M, A, A]), G=G, D=D,
                       K=supports.matrix, planes=planes, unbalances=tuple(ubs),
                       source=f"Filimonikhin 2004 sec. 2.7, (2.118)/(2.122); supports {supports.source}")


# ------------------------------------------------------- 2.7.2 closed forms
def rotor_shape(A: float, C: float) -> str:
    """``"long"`` (C < A), ``"spherical"`` (C = A, relative 1e-12) or ``"short"`` (C > A), (2.19)-(2.21)."""
    A = _positive("A", A, "kg m^2")
    C = _nonneg("C", C, "kg m^2")
    if math.isclose(A, C, rel_tol=_REL):
        return "spherical"
    return "long" if C < A else "short"


def delta(omega, M, A, C, c11, c14, c33):
    """(2.126): ``Delta(w^2) = (c11 - M w^2)(c33 - (A - C) w^2) - c14^2`` [N^2/rad].
    ``omega`` [rad/s] may be an array."""
    w2 = np.square(np.asarray(omega, dtype=float))
    return (c11 - M * w2) * (c33 - (A - C) * w2) - c14 * c14


def r_ac(omega, M, A, C, c11, c14, c33, a, s=1.0):
    """Engineering criterion (2.133) for a balancer at axial distance ``a`` [m]::

        r_Ac = -[(A + M a^2 - C) w^2 - c33 - c11 a^2 + 2 a c14] s w^2 / Delta(w^2)

    [m] for an unbalance ``s`` [kg m]; autobalancing needs ``r_Ac < 0``.  It is
    the (time-constant) projection of the plane's deflection on the unbalance,
    equal to :meth:`LinearRotor.criterion` of :func:`spatial_rotor`.
    """
    w2 = np.square(np.asarray(omega, dtype=float))
    num = (A + M * a * a - C) * w2 - c33 - c11 * a * a + 2 * a * c14
    return -num * s * w2 / delta(omega, M, A, C, c11, c14, c33)


def high_speed_limit(M, A, C, a, s=1.0) -> float:
    """(2.134)-(2.137): ``r_Ac -> -(A + M a^2 - C) s / (M (A - C))`` [m] as w -> inf
    (``A != C``; for the spherical rotor the limit is ``+a^2 s / c33``-like, not given)."""
    if math.isclose(A, C, rel_tol=_REL):
        raise ValueError(f"high_speed_limit needs A != C (non-spherical rotor), got A = C = {A!r} kg m^2")
    return -(A + M * a * a - C) * s / (M * (A - C))


def balances_at_high_speed(M, A, C, a) -> bool:
    """(2.135)-(2.137): high-speed autobalancing iff ``C < A`` (long rotor, any ``a``)
    or ``C > A + M a^2``, i.e. a short rotor with ``|a| < sqrt((C - A)/M)``;
    never for a spherical rotor."""
    M = _positive("M", M, "kg")
    shape = rotor_shape(A, C)
    if shape == "long":
        return True
    if shape == "spherical":
        return False
    return bool(A + M * a * a < C)


def auxiliary_speed(M, A, C, c11, c14, c33, a) -> float:
    """(2.138): ``w~ = sqrt((c33 + c11 a^2 - 2 a c14) / (A + M a^2 - C))`` [rad/s],
    the zero of the numerator of (2.133).  ``inf`` when ``A + M a^2 = C``
    (spherical rotor with ``a = 0``), ``nan`` when ``A + M a^2 < C`` (no real zero)."""
    num = c33 + c11 * a * a - 2 * a * c14
    den = A + M * a * a - C
    if abs(den) <= _REL * max(A, C):
        return math.inf
    return math.sqrt(num / den) if den > 0 else math.nan


def frequency_polynomial(M, A, C, c11, c14, c33):
    """(2.139)-(2.140): ``Delta(x) = a2 x^2 - a1 x + a0`` in ``x = w^2`` with
    ``a2 = M(A - C)``, ``a1 = c11 (A - C) + M c33``, ``a0 = c11 c33 - c14^2`` and the
    discriminant ``D = [c11 (A - C) - M c33]^2 + 4 c14^2 M (A - C)``.

    Returns ``(a2, a1, a0, D)``.  (The book says "up to sign"; the sign is +.)
    """
    a2 = M * (A - C)
    a1 = c11 * (A - C) + M * c33
    a0 = c11 * c33 - c14 * c14
    D = (c11 * (A - C) - M * c33) ** 2 + 4 * c14 * c14 * M * (A - C)
    return a2, a1, a0, D


def frequency_roots(M, A, C, c11, c14, c33) -> np.ndarray:
    """Real roots ``x = w^2`` [rad^2/s^2] of (2.139), sorted ((2.141) in a
    cancellation-free form).  Two roots if ``A != C`` (both positive for a long
    rotor; ``x_- < 0 < x_+`` for a short one), one (``a0 / (M c33)``, (2.145)) if ``A = C``."""
    a2, a1, a0, D = frequency_polynomial(M, A, C, c11, c14, c33)
    if math.isclose(A, C, rel_tol=_REL):
        return np.array([a0 / a1])
    q = 0.5 * (a1 + math.copysign(math.sqrt(D), a1))
    return np.sort(np.array([q / a2, a0 / q]))


@dataclass(frozen=True)
class SpeedRegions:
    """Critical speeds and autobalancing regions of one balancer plane.

    Attributes
    ----------
    case : str
        ``"long"``, ``"spherical"``, ``"short, A+Ma^2>C"`` or ``"short, A+Ma^2<=C"``.
    speeds : tuple of float
        Critical speeds [rad/s], ascending.
    ranges : tuple of (float, float)
        Autobalancing speed ranges [rad/s]; the last end may be ``inf``.
    equations : str
        Book equations used.
    """

    case: str
    speeds: tuple
    ranges: tuple
    equations: str = ""

    def contains(self, omega: float) -> bool:
        """True if ``omega`` [rad/s] lies in an autobalancing range."""
        return any(lo < omega < hi for lo, hi in self.ranges)


def _merge(ranges):
    """Join ranges that touch (a cancelled critical speed, e.g. a = 0)."""
    out = []
    for lo, hi in sorted(ranges):
        if out and math.isclose(out[-1][1], lo, rel_tol=1e-12):
            out[-1] = (out[-1][0], hi)
        elif lo < hi:
            out.append((lo, hi))
    return tuple(out)


def _case_regions(shape, P, wt, roots, equations):
    """Regions from the sign analysis of (2.133): ``r_Ac < 0`` iff ``N / Delta > 0``."""
    if shape == "long":                      # (2.142)-(2.144)
        w = sorted([wt, math.sqrt(roots[0]), math.sqrt(roots[1])])
        case, ranges = "long", [(w[0], w[1]), (w[2], math.inf)]
    elif shape == "spherical":               # (2.145)-(2.147)
        wk = math.sqrt(roots[0])
        case = "spherical"
        if math.isinf(wt):                   # a = 0: numerator constant
            w, ranges = [wk], [(wk, math.inf)]
        else:
            w = sorted([wk, wt])
            ranges = [(w[0], w[1])]
    else:
        wp = math.sqrt(roots[-1])            # the positive root x_+
        if P > 0:                            # (2.148)-(2.150)
            w = sorted([wp, wt])
            case, ranges = "short, A+Ma^2>C", [(w[0], w[1])]
        else:                                # (2.151)-(2.153)
            w = [wp]
            case, ranges = "short, A+Ma^2<=C", [(wp, math.inf)]
    ranges = _merge(ranges)
    speeds = tuple(sorted({float(x) for r in ranges for x in r if math.isfinite(x)}))
    return SpeedRegions(case, speeds, tuple((float(a), float(b)) for a, b in ranges), equations)


def critical_speeds(M, A, C, c11, c14, c33, a) -> SpeedRegions:
    """Critical speeds and regions of (2.133) for isotropic supports (2.142)-(2.153).

    * long (C < A): ``{w~, sqrt(x1), sqrt(x2)}`` sorted to w1 < w2 < w3,
      region ``(w1, w2) U (w3, inf)`` (any order of w~, (2.144));
    * spherical (A = C): ``w_k = sqrt((c11 c33 - c14^2)/(M c33))`` and
      ``w~ = sqrt((c33 + c11 a^2 - 2 a c14)/(M a^2))``, region between them
      (corrected (2.145)-(2.146)); ``a = 0``: ``(w_k, inf)``;
    * short (C > A) with ``A + M a^2 > C``: between ``sqrt(x_+)`` and w~ (2.148)-(2.150);
    * short with ``A + M a^2 <= C``: ``(sqrt(x_+), inf)`` (2.151)-(2.153).

    Touching ranges (a cancelled critical speed) are merged.

    Parameters
    ----------
    M [kg], A, C [kg m^2], c11 [N/m], c14 [N/rad], c33 [N m/rad], a [m]
    """
    M = _positive("M", M, "kg")
    c11, c14, c33 = _check_isotropic_coefficients(c11, c14, c33)
    a = _finite("a", a, "m")
    shape = rotor_shape(A, C)
    P = A + M * a * a - C
    return _case_regions(shape, P, auxiliary_speed(M, A, C, c11, c14, c33, a),
                         frequency_roots(M, A, C, c11, c14, c33),
                         "(2.133), (2.138)-(2.153)")


def symmetric_critical_speeds(M, A, C, c11, c33, a) -> SpeedRegions:
    """Symmetric mounting (c14 = 0, section 2.7.3): the explicit speeds (2.155)-(2.159)::

        w1 = sqrt(c11/M),  w2 = sqrt((c33 + c11 a^2)/(A + M a^2 - C)),  w3 = sqrt(c33/(A - C))

    * long (2.155)-(2.156): ``(w1, w2) U (w3, inf)``; the book assumes
      ``c11/M < c33/(A - C)`` (then w1 < w2 < w3); otherwise the three are
      sorted (w3 < w2 < w1) and the same pattern holds;
    * spherical (2.157): ``(w1, w2)`` (``(w1, inf)`` for a = 0);
    * short, ``A + M a^2 > C`` (2.158): between w1 and w2;
    * short, ``A + M a^2 <= C`` (2.159): ``(w1, inf)``.
    """
    M = _positive("M", M, "kg")
    c11, _, c33 = _check_isotropic_coefficients(c11, 0.0, c33)
    a = _finite("a", a, "m")
    shape = rotor_shape(A, C)
    P = A + M * a * a - C
    w1 = math.sqrt(c11 / M)
    w2 = math.inf if abs(P) <= _REL * max(A, C) else (
        math.sqrt((c33 + c11 * a * a) / P) if P > 0 else math.nan)
    if shape == "long":
        roots = [w1 ** 2, c33 / (A - C)]
    elif shape == "spherical":
        roots = [w1 ** 2]
    else:
        roots = [c33 / (A - C), w1 ** 2]     # x_- < 0 < x_+ = c11/M
    return _case_regions(shape, P, w2, roots, "(2.154)-(2.159)")


def intersect_ranges(r1, r2):
    """Intersection of two lists of (lo, hi) ranges [rad/s] (rule (2.160))."""
    out = []
    for a0, a1 in r1:
        for b0, b1 in r2:
            lo, hi = max(a0, b0), min(a1, b1)
            if lo < hi:
                out.append((lo, hi))
    return tuple(sorted(out))


def two_balancer_ranges(M, A, C, c11, c14, c33, a1, a2):
    """Two balancers at ``a1``, ``a2`` [m]: the book's rule (2.160)
    ``Omega = Omega_1 ∩ Omega_2`` of the single-plane regions (2.142)-(2.153).

    Note: this is the book's engineering rule.  Paper 003's generalised
    criterion (:meth:`TwoSupportRotor.is_stable`) is stricter for dynamic
    balancing (a long rotor only above its largest critical speed).
    """
    return intersect_ranges(critical_speeds(M, A, C, c11, c14, c33, a1).ranges,
                            critical_speeds(M, A, C, c11, c14, c33, a2).ranges)


# ------------------------------------------------------------ paper 003 (M2)
@dataclass(frozen=True)
class TwoSupportRotor:
    """Paper 003 model M2: rigid compound rotor on two isotropic elastic supports.

    Axial coordinate ``zeta`` from the rotor's centre of mass O: support 1 at
    ``-l1``, support 2 at ``+l2`` (paper (12)); the compound rotor's centre of
    mass G at ``zeta_G``; balancer planes at ``a_i``.  ``J_xi``, ``J_eta`` are
    the transverse moments about the O axes, ``C`` the axial moment (all of the
    compound rotor in the main motion); ``d1``, ``d2`` optional support damping.
    Use :func:`two_support_rotor` to build it (validation).

    Central axes (31)-(33)::

        J_G = J - M zeta_G^2,  l1~ = l1 + zeta_G,  l2~ = l2 - zeta_G,  a~ = a - zeta_G,
        c11~ = c1 + c2,  c14~ = c2 l2~ - c1 l1~,  c33~ = c1 l1~^2 + c2 l2~^2

    Rotating-frame steady equations (17): ``K_xi(w) (x~, phi) = w^2 (M xi_G, J_xi_zeta)``,
    ``K_eta(w) (y~, -theta) = w^2 (M eta_G, J_eta_zeta)`` with
    ``K(w) = [[c11~ - M w^2, c14~], [c14~, c33~ - (J_G - C) w^2]]``; the fixed-
    frame tilts are ``beta <-> phi``, ``alpha <-> theta``.
    """

    c1: float
    c2: float
    l1: float
    l2: float
    M: float
    J_xi: float
    J_eta: float
    C: float
    zeta_G: float = 0.0
    d1: float = 0.0
    d2: float = 0.0

    # (14), (31)-(34) -----------------------------------------------------
    def stiffness_O(self):
        """(14): ``(c11, c14, c33)`` about O: ``c1 + c2``, ``c2 l2 - c1 l1``,
        ``c1 l1^2 + c2 l2^2`` [N/m, N/rad, N m/rad]."""
        return (self.c1 + self.c2, self.c2 * self.l2 - self.c1 * self.l1,
                self.c1 * self.l1 ** 2 + self.c2 * self.l2 ** 2)

    @property
    def l_tilde(self):
        """(32): distances of the supports from G, ``(l1 + zeta_G, l2 - zeta_G)`` [m]."""
        return self.l1 + self.zeta_G, self.l2 - self.zeta_G

    def central_moments(self):
        """(31): ``(J_G_xi, J_G_eta) = (J_xi - M zeta_G^2, J_eta - M zeta_G^2)`` [kg m^2]."""
        s = self.M * self.zeta_G ** 2
        return self.J_xi - s, self.J_eta - s

    def stiffness_G(self, c1=None, c2=None):
        """(33): ``(c11~, c14~, c33~)`` about G (pass ``c1``, ``c2`` = damping
        coefficients to get the damping analogue)."""
        c1 = self.c1 if c1 is None else c1
        c2 = self.c2 if c2 is None else c2
        L1, L2 = self.l_tilde
        return c1 + c2, c2 * L2 - c1 * L1, c1 * L1 ** 2 + c2 * L2 ** 2

    def invariant(self) -> float:
        """(34): ``c11~ c33~ - c14~^2 = c1 c2 (l1 + l2)^2`` [N^2/rad] (shift-invariant)."""
        c11, c14, c33 = self.stiffness_G()
        return c11 * c33 - c14 * c14

    def a_tilde(self, a):
        """(32): balancer-plane position from G, ``a - zeta_G`` [m]."""
        return np.asarray(a, dtype=float) - self.zeta_G

    def _J(self, axis):
        Jx, Je = self.central_moments()
        if axis in ("xi", "x"):
            return Jx
        if axis in ("eta", "y"):
            return Je
        raise ValueError(f"axis must be 'xi' or 'eta', got {axis!r}")

    # (17)-(19), (38)-(41) -------------------------------------------------
    def K(self, omega: float, axis: str = "xi") -> np.ndarray:
        """(17): rotating-frame synchronous stiffness ``K_xi(w)`` or ``K_eta(w)`` (2 x 2)."""
        c11, c14, c33 = self.stiffness_G()
        w2 = float(omega) ** 2
        return np.array([[c11 - self.M * w2, c14], [c14, c33 - (self._J(axis) - self.C) * w2]])

    def delta_coefficients(self, axis: str = "xi"):
        """(39): ``(a, b, c)`` of ``Delta_1(w) = a w^4 - b w^2 + c`` (38) and ``D = b^2 - 4ac``."""
        c11, c14, c33 = self.stiffness_G()
        JC = self._J(axis) - self.C
        a, b, c = self.M * JC, JC * c11 + self.M * c33, c11 * c33 - c14 * c14
        return a, b, c, (self.M * c33 - JC * c11) ** 2 + 4 * self.M * JC * c14 * c14

    def delta(self, omega, axis: str = "xi"):
        """(38): ``Delta_{1,2}(w) = det K_{xi,eta}(w)`` [N^2/rad]; ``omega`` may be an array."""
        a, b, c, _ = self.delta_coefficients(axis)
        w2 = np.square(np.asarray(omega, dtype=float))
        return a * w2 * w2 - b * w2 + c

    def critical_speeds(self, axis: str = "xi") -> np.ndarray:
        """(40)-(41): critical speeds of the compound rotor [rad/s], ascending.

        ``J_G > C``: two, ``sqrt((b -+ sqrt(D)) / (2a))`` (40); ``J_G < C``: one,
        ``sqrt((b - sqrt(D)) / (2a))`` (41); ``J_G = C``: one, ``sqrt(c / b)``.
        """
        a, b, c, D = self.delta_coefficients(axis)
        if abs(a) <= _REL * self.M * max(self._J(axis), self.C):
            return np.array([math.sqrt(c / b)])
        q = 0.5 * (b + math.copysign(math.sqrt(D), b))   # cancellation-free roots
        return np.sqrt(np.sort([x for x in (q / a, c / q) if x > 0]))

    def plane_stiffness(self, a) -> float:
        """(33): ``c~_(i) = c1 (l1~ + a~)^2 + c2 (l2~ - a~)^2`` [N m/rad], the tilting
        stiffness about the axis point of the plane at ``a`` [m] (from O)."""
        at = float(self.a_tilde(a))
        L1, L2 = self.l_tilde
        return self.c1 * (L1 + at) ** 2 + self.c2 * (L2 - at) ** 2

    def plane_speed(self, a, axis: str = "xi") -> float:
        """(36)-(37): ``w_i = sqrt(c~_(i) / P_i)``, ``P_i = J_G + M a~^2 - C`` [rad/s]
        (``nan`` if ``P_i <= 0``)."""
        at = float(self.a_tilde(a))
        P = self._J(axis) + self.M * at * at - self.C
        return math.sqrt(self.plane_stiffness(a) / P) if P > 0 else math.nan

    # criterion (1)/(24)-(30), (43) ----------------------------------------
    def criterion_form(self, omega: float, a1: float, a2: float) -> np.ndarray:
        """(26) with ``mu m = 1``: the 4 x 4 symmetric matrix of ``f`` in
        ``(xi_1, xi_2, eta_1, eta_2)`` [m per (kg m)],
        ``diag(w^2 P K_xi^-1 P^T, w^2 P K_eta^-1 P^T)``, ``P = [[1, a1~], [1, a2~]]``.
        The main motion is stable iff it is negative definite (undamped rotor)."""
        P = np.array([[1.0, float(self.a_tilde(a1))], [1.0, float(self.a_tilde(a2))]])
        w2 = float(omega) ** 2
        F = np.zeros((4, 4))
        F[:2, :2] = w2 * P @ np.linalg.solve(self.K(omega, "xi"), P.T)
        F[2:, 2:] = w2 * P @ np.linalg.solve(self.K(omega, "eta"), P.T)
        return 0.5 * (F + F.T)

    def is_stable(self, omega: float) -> bool:
        """Compact form of the generalised criterion for two distinct planes:
        stable main motion iff ``K_xi(w)`` and ``K_eta(w)`` are negative definite
        (papers digest section 2.4).  Independent of the plane positions."""
        return all(bool(np.all(np.linalg.eigvalsh(self.K(omega, ax)) < 0)) for ax in ("xi", "eta"))

    def single_plane_stable(self, omega: float, a: float) -> bool:
        """(42)-(43): static balancing by one balancer at ``a`` [m]: stable iff
        ``(c~_(1) - w^2 P_1) / Delta < 0`` for both xi and eta."""
        at = float(self.a_tilde(a))
        out = True
        for ax in ("xi", "eta"):
            P = self._J(ax) + self.M * at * at - self.C
            out &= bool((self.plane_stiffness(a) - omega ** 2 * P) / self.delta(omega, ax) < 0)
        return out

    # steady response (18)-(19) -------------------------------------------
    def steady_response(self, omega: float, unbalances) -> dict:
        """(18)-(19): rotating-frame steady (main-motion) displacement ``K^-1 RHS``.

        ``unbalances``: sequence of ``(a [m from O], s [kg m], angle [rad])``.
        With support damping (d1, d2) the two systems couple::

            [[K_xi, -w D], [w D, K_eta]] (x~, phi, y~, -theta) = w^2 (F_xi, F_eta)

        Returns a dict with ``x``, ``y`` (of G) [m], ``theta``, ``phi`` [rad]
        (rotor frame; the fixed-frame motion is ``x + i y -> (x + i y) e^{i w t}``,
        ``beta - i alpha -> (phi - i theta) e^{i w t}``).
        """
        w = float(omega)
        F = np.zeros(4)
        for a, s, ang in unbalances:
            at = float(self.a_tilde(a))
            F += w * w * s * np.array([math.cos(ang), at * math.cos(ang),
                                       math.sin(ang), at * math.sin(ang)])
        d11, d14, d33 = self.stiffness_G(self.d1, self.d2)
        Dm = np.array([[d11, d14], [d14, d33]])
        S = np.block([[self.K(w, "xi"), -w * Dm], [w * Dm, self.K(w, "eta")]])
        x, phi, y, mth = np.linalg.solve(S, F)
        return {"x": x, "y": y, "theta": -mth, "phi": phi}

    # fixed-frame LinearRotor ----------------------------------------------
    def linear_rotor(self, balancers=(), unbalances=(), name: str = "two_support") -> LinearRotor:
        """The fixed-frame :class:`LinearRotor` in central coordinates
        ``(x_G, y_G, alpha, beta)`` (axisymmetric compound rotor only, ``J_xi = J_eta``;
        an unequal pair makes the fixed-frame coefficients periodic).

        Planes: ``"com"`` (G), ``"support1"``, ``"support2"``, ``"O"``,
        ``"balancer1"``, ... at ``a_i`` [m from O] and ``"unbalance1"``, ...
        """
        if not math.isclose(self.J_xi, self.J_eta, rel_tol=_REL):
            raise ValueError(f"linear_rotor needs an axisymmetric rotor, got J_xi = {self.J_xi!r} "
                             f"and J_eta = {self.J_eta!r} kg m^2; use K_xi/K_eta (rotating frame)")
        JG = self.central_moments()[0]
        L1, L2 = self.l_tilde
        K = _supports_at((-L1, L2), (self.c1, self.c2), (self.c1, self.c2), "paper 003 (33)").matrix
        D = _supports_at((-L1, L2), (self.d1, self.d2), (self.d1, self.d2), "damping").matrix
        G = np.zeros((4, 4))
        G[2, 3], G[3, 2] = self.C, -self.C
        planes = {"com": plane_map(0.0), "support1": plane_map(-L1), "support2": plane_map(L2),
                  "O": plane_map(-self.zeta_G)}
        for j, a in enumerate(np.atleast_1d(np.asarray(balancers, dtype=float)), 1):
            planes[f"balancer{j}"] = plane_map(float(self.a_tilde(a)))
        ubs = []
        for j, (a, s, ang) in enumerate(unbalances, 1):
            planes[f"unbalance{j}"] = plane_map(float(self.a_tilde(a)))
            ubs.append(Unbalance(f"unbalance{j}", _nonneg("s", s, "kg m"), float(ang)))
        return LinearRotor(name=name, coords=("x_G [m]", "y_G [m]", "alpha [rad]", "beta [rad]"),
                           M=np.diag([self.M, self.M, JG, JG]), G=G, D=D, K=K, planes=planes,
                           unbalances=tuple(ubs),
                           source="paper 003 (Filimonikhina & Filimonikhin), (12)-(14), (31)-(33)")


def two_support_rotor(c1: float, c2: float, l1: float, l2: float, M: float, J_xi: float,
                      J_eta: float, C: float, zeta_G: float = 0.0, d1: float = 0.0,
                      d2: float = 0.0) -> TwoSupportRotor:
    """Paper 003 (model M2): rigid compound rotor on two isotropic supports.

    Parameters
    ----------
    c1, c2 : float   support stiffnesses [N/m] (> 0)
    l1, l2 : float   distances of supports 1 (at zeta = -l1) and 2 (at +l2) from O [m]
    M : float        mass of the compound rotor [kg]
    J_xi, J_eta : float  transverse moments about the O axes [kg m^2] (> M zeta_G^2)
    C : float        axial moment [kg m^2]
    zeta_G : float   axial position of the compound centre of mass G [m], |zeta_G| shifts (31)-(32)
    d1, d2 : float   optional support viscous damping [N s/m] (not in the paper)
    """
    c1 = _positive("c1", c1, "N/m")
    c2 = _positive("c2", c2, "N/m")
    l1 = _finite("l1", l1, "m")
    l2 = _finite("l2", l2, "m")
    if l1 + l2 <= 0:
        raise ValueError(f"support separation l1 + l2 must be > 0 m, got {l1 + l2!r} m")
    M = _positive("M", M, "kg")
    J_xi = _positive("J_xi", J_xi, "kg m^2")
    J_eta = _positive("J_eta", J_eta, "kg m^2")
    C = _nonneg("C", C, "kg m^2")
    zeta_G = _finite("zeta_G", zeta_G, "m")
    for n, J in (("J_xi", J_xi), ("J_eta", J_eta)):
        if J - M * zeta_G ** 2 <= 0:
            raise ValueError(f"{n} = {J!r} kg m^2 must exceed M zeta_G^2 = {M * zeta_G ** 2!r} "
                             "kg m^2 (the central moment (31) must be positive)")
    return TwoSupportRotor(c1, c2, l1, l2, M, J_xi, J_eta, C, zeta_G,
                           _nonneg("d1", d1, "N s/m"), _nonneg("d2", d2, "N s/m"))


def spatial_scene_rotor(mass, A, C, l1, l2, c1, c2=None, balancer_positions=(0.0,),
                        unbalance=0.0, unbalance_position=0.0, unbalance_angle=0.0,
                        couple_unbalance=0.0, couple_positions=(0.0, 0.0),
                        stiffness_damping=0.0, screen_positions=()) -> LinearRotor:
    """Scene-file form of :func:`spatial_rotor` (plain numbers only): a rigid
    rotor on two isotropic supports (Table 2.4 row 1 with c1 = c2 left, c3 = c4
    right; supports at distances l1, l2 [m] from the centre of mass).

    Parameters
    ----------
    mass : float  M [kg];  A, C : float  transverse and polar moments [kg m^2]
    l1, l2 : float  support distances [m];  c1, c2 : float  support stiffnesses [N/m]
    balancer_positions : list of float  axial positions a [m] of the balancer
        planes ("balancer1", "balancer2", ...)
    unbalance, unbalance_position, unbalance_angle : static unbalance s [kg m]
        at a [m], angle [rad] (plane "unbalance1")
    couple_unbalance : float  s [kg m] of a couple (s at couple_positions[0],
        -s at couple_positions[1]) [m]
    stiffness_damping : float  beta [s]: damping matrix beta K (stiffness-proportional)
    screen_positions : list of float  axial positions [m] of laser screens: the
        beam along the shaft axis hits a screen at distance y where the axis
        line is, x + y beta, y - y alpha (2.131): planes "screen1", "screen2", ...
        (two screens give both correction planes, (4.2)-(4.3), :mod:`dsp.two_plane`)
    """
    sup = isotropic_supports(l1, l2, c1, c1 if c2 is None else c2)
    unb = []
    if unbalance:
        unb += static_unbalance(unbalance, unbalance_angle, unbalance_position)
    if couple_unbalance:
        unb += _couple(couple_unbalance, couple_positions[0], couple_positions[1],
                                   unbalance_angle)
    beta = float(stiffness_damping)
    if not (math.isfinite(beta) and beta >= 0):
        raise ValueError(f"stiffness_damping = {stiffness_damping!r}: must be >= 0 (s)")
    damping = beta * np.asarray(sup.matrix, float) if beta else None
    bp = balancer_positions if isinstance(balancer_positions, (list, tuple)) else (balancer_positions,)
    rot = spatial_rotor(mass, A, C, sup, balancers=tuple(float(a) for a in bp), unbalances=unb,
                        damping=damping)
    sp = screen_positions if isinstance(screen_positions, (list, tuple)) else (screen_positions,)
    if sp:
        import dataclasses

        planes = dict(rot.planes)
        for k, y in enumerate(sp, start=1):
            planes[f"screen{k}"] = plane_map(float(y))
        rot = dataclasses.replace(rot, planes=planes)
    return rot


_couple = couple_unbalance   # (the scene wrapper's parameter shadows the name)
