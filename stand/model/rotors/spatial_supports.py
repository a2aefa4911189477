"""Rigid rotor in spatial motion, book section 2.7.1: the support stiffness
matrices (2.118), (2.119), (2.121)-(2.122), the Table 2.4 schemes, and the
plane maps (2.131) of the points of the rotor's axis.

Coordinates ``q = (x, y, alpha, beta)``: the translation of the centre of mass
[m] and the Resal tilts [rad] (digest ch2_ch3 section 2.6).  A point of the
axis at axial distance ``a`` from the centre of mass moves as (2.131)
``x_B = x + a beta``, ``y_B = y - a alpha``: ``T(a) = [[1, 0, 0, a], [0, 1, -a, 0]]``.
A point support of stiffnesses ``(c_x, c_y)`` at ``zeta`` contributes
``c_x t_x t_x^T + c_y t_y t_y^T`` with ``(t_x, t_y)`` the rows of ``T(zeta)``.

Axial coordinate convention.  ``a`` (planes) and the support positions share
one axial coordinate ``zeta`` measured from the centre of mass, with
``K[x, beta] = sum_i c_ix zeta_i``.  Table 2.4 (book) puts support / shaft
segment 1 at ``zeta = +l1`` and 2 at ``zeta = -l2`` (this is what makes its
printed ``c14`` signs come out; checked against beam theory), while paper 003
(eq. (12), (14)) puts support 1 at ``zeta = -l1`` and 2 at ``zeta = +l2``.
Each constructor states which one it uses.

The rotor itself is :func:`stand.model.rotors.spatial.spatial_rotor`, which
re-exports the public names of this module.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stand.model.rotors._build import finite, nonnegative, positive
from stand.model.rotors.structure import Unbalance

__all__ = ["COORDS", "SupportStiffness", "two_elastic_supports", "isotropic_supports",
           "cantilever_disk", "disk_on_hinged_shaft", "disk_on_clamped_shaft", "plane_map",
           "numbered_planes"]

COORDS = ("x [m]", "y [m]", "alpha [rad]", "beta [rad]")
_REL = 1e-12     # relative tolerance of the isotropy / spherical-rotor (A = C) tests


def _check_isotropic_coefficients(c11, c14, c33):
    """Validated ``(c11 [N/m], c14 [N/rad], c33 [N m/rad])`` of (2.122), positive definite."""
    c11 = positive("c11", c11, "N/m")
    c33 = positive("c33", c33, "N m/rad")
    c14 = finite("c14", c14, "N/rad")
    if c11 * c33 <= c14 * c14:
        raise ValueError(f"supports must be positive definite: c11*c33 = {c11 * c33!r} "
                         f"[N^2/rad] must exceed c14^2 = {c14 * c14!r} [N^2/rad^2]")
    return c11, c14, c33


def plane_map(a: float) -> np.ndarray:
    """Plane map (2.131) of the axis point at axial distance ``a`` [m] from the
    centre of mass: ``(x_B, y_B) = (x + a beta, y - a alpha)``."""
    a = finite("a", a, "m")
    return np.array([[1.0, 0.0, 0.0, a], [0.0, 1.0, -a, 0.0]])


def numbered_planes(balancers=(), unbalances=(), origin: float = 0.0):
    """The balancer and unbalance planes of a spatial rotor, numbered from 1.

    Parameters
    ----------
    balancers : float or sequence of float
        Axial positions ``a`` [m] of the balancer planes ``"balancer1"``, ...
    unbalances : sequence of (a [m], s [kg m], angle [rad])
        Unbalances, each in its own plane ``"unbalance1"``, ...
    origin : float
        Axial position [m] of the coordinates' reference point in the same
        axial coordinate (0 for the centre of mass of :func:`spatial_rotor`;
        ``zeta_G`` for the central axes (32) of paper 003).

    Returns
    -------
    planes : dict of str -> ndarray (2, 4)
        :func:`plane_map` of each plane at ``a - origin``.
    unbalances : tuple of Unbalance
    """
    planes = {}
    for j, a in enumerate(np.atleast_1d(np.asarray(balancers, dtype=float)), 1):
        planes[f"balancer{j}"] = plane_map(a - origin)
    ubs = []
    for j, u in enumerate(unbalances, 1):
        try:
            a, s, ang = u
        except (TypeError, ValueError):
            raise ValueError(f"unbalance {j} must be (a [m], s [kg m], angle [rad]), got {u!r}") from None
        planes[f"unbalance{j}"] = plane_map(finite(f"unbalance {j} position a", a, "m") - origin)
        ubs.append(Unbalance(f"unbalance{j}", nonnegative("s", s, "kg m"), float(ang)))
    return planes, tuple(ubs)


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
        tx, ty = plane_map(z)                 # (x + zeta beta, y - zeta alpha), (2.131)
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
    l1 = positive("l1", l1, "m")
    l2 = positive("l2", l2, "m")
    c1, c2, c3, c4 = (positive(n, v, "N/m") for n, v in
                      (("c1", c1), ("c2", c2), ("c3", c3), ("c4", c4)))
    return SupportStiffness.principal(c1 + c3, c2 + c4, c2 * l1 ** 2 + c4 * l2 ** 2,
                                      c1 * l1 ** 2 + c3 * l2 ** 2, c1 * l1 - c3 * l2,
                                      c2 * l1 - c4 * l2, source="Table 2.4 row 1")


def isotropic_supports(l1: float, l2: float, c_1: float, c_2: float) -> SupportStiffness:
    """Table 2.4 row 1 with isotropic supports (``c2 = c1``, ``c4 = c3``): support 1
    of stiffness ``c_1`` [N/m] at ``zeta = +l1``, support 2 of ``c_2`` at ``zeta = -l2``."""
    return two_elastic_supports(l1, l2, c_1, c_1, c_2, c_2)


def _EJ(E, J):
    return positive("E", E, "Pa") * positive("J", J, "m^4")


def cantilever_disk(E: float, J: float, l: float) -> SupportStiffness:
    """Table 2.4 row 2: disk at the free end of a clamped (cantilever) massless shaft.

    ``c11 = 12EJ/l^3``, ``c14 = 6EJ/l^2``, ``c33 = 4EJ/l`` (clamp at ``zeta = +l``).

    Parameters
    ----------
    E : float  Young's modulus [Pa];  J : float  area moment of the section [m^4]
    l : float  shaft length [m]
    """
    EJ = _EJ(E, J)
    l = positive("l", l, "m")
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
    l1 = positive("l1", l1, "m")
    l2 = positive("l2", l2, "m")
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
    l1 = positive("l1", l1, "m")
    l2 = positive("l2", l2, "m")
    f33 = 6.0 if paper_exact else 4.0
    return SupportStiffness.isotropic(
        12 * EJ * (l1 ** 3 + l2 ** 3) / (l1 ** 3 * l2 ** 3),
        6 * EJ * (l2 ** 2 - l1 ** 2) / (l1 ** 2 * l2 ** 2),
        f33 * EJ * (l1 + l2) / (l1 * l2),
        "Table 2.4 row 4" + (" (printed 6EJ)" if paper_exact else " (corrected 4EJ)"))
