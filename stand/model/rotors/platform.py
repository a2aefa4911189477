"""Paper 004 (Drach): 6-DOF vertical-axis rotor on a suspended platform (model M3).

A rigid platform carrying a rigid rotor (vertical spin axis, constant spin
``omega``) hangs from the housing on elastic rods/springs with viscous dampers
through a trapezoidal (four-bar) pendulum linkage, and is tied to the housing by
an elastic sealing diaphragm (papers digest section 3).  Generalised
coordinates (3.1) ``q = (x, y, z, alpha, beta, gamma)``: translations [m] of the
platform's centre of inertia O and small rotations [rad] about X, Y, Z.  The
equations of motion (38)::

    M q'' + (G + D) q' + A q = F(t)

``M`` (39), ``G`` (40, gyroscopic, proportional to omega), ``D`` (41, dampers),
``A`` (42, stiffness incl. gravity of the pendulum linkage), ``F`` (43, rotor
unbalance ``m_2 e``).  In :class:`~stand.model.rotors.structure.LinearRotor` form
``K = A`` and ``G`` is stored **per unit spin** (``G_paper = omega * G``).

Linkage (digest 3.3-3.5): the pendulum adds the rotations
``alpha_1 = alpha - d_4 y``, ``beta_1 = beta + d_3 x`` with (19)
``d_3 = (S_1 - b_1) / (b_1 h + z_k (S_1 - b_1))`` and ``d_4`` alike (1 -> 2);
gravity gives ``Pi_1 = m g (delta_1 x^2 + delta_2 y^2 + delta_3 gamma^2) / 2``
(32)-(33).  Rod i (stiffness c_1i, damper h_i) contributes
``c_1i v_i v_i^T / l_i^2`` to A and ``h_i v_i v_i^T / l_i^2`` to D, with
``v_i = (d_1, d_2, l_iz, d_5, d_6, d_7)`` ((18)-(19) in compact form; ``v . q``
is the rod elongation times l_i).  The diaphragm at point M adds
``c_2x P_x^T P_x + c_2y P_y^T P_y + c_2z P_z^T P_z`` with the rows P of (25).

Two switches (digest 5.1, model M3)
-----------------------------------
``paper_exact=False`` (default, *corrected*) and ``paper_exact=True`` (the
printed formulas of digest 3.9, flagged items included).  The corrected model
differs from the printed one in exactly these entries, each for the reason
given (digest 3.5-3.6):

* ``M_14 = M_41``: printed ``-m_2 y_D d_3``; corrected ``-m_2 x_D y_D d_3``
  (Hessian of the kinetic energy (27)-(28) after ``alpha -> alpha - d_4 y``,
  ``beta -> beta + d_3 x``; the printed entry is dimensionally wrong: kg m vs
  kg m^2 x 1/m).
* ``a_23``: printed ``-c_2x y_M d_4``; corrected ``-c_2z y_M d_4`` (the y-z
  product only occurs in ``Delta r_zm^2`` of (25)-(26)).
* ``a_25``: missing in print; corrected ``+c_2z x_M y_M d_4`` (the term
  ``+2 x_M y_M d_4 y beta`` of ``Delta r_zm^2`` is missing from (26)).
* ``a_26``: printed ``-c_2y x_M (1 + z_M d_4)``; corrected ``+`` (from
  ``Delta r_ym = (1 + z_M d_4) y + x_M gamma - ...``, (25)).
* ``a_56``: printed ``-c_2y y_M z_M``; corrected ``-c_2x y_M z_M`` (the
  beta-gamma product only occurs in ``Delta r_xm^2``).
* ``a_66``: printed ``c_2x z_M^2``; corrected ``c_2x y_M^2`` (the printed (26)
  has ``gamma^2 z_m^2`` for ``gamma^2 y_m^2``).
* ``F_beta``: printed ``m_2 omega^2 e z_D sin(omega t)``; corrected
  ``cos(omega t)`` (moment of the centrifugal force at D; the only form
  consistent with the printed ``F_x ~ (1 + z_D d_3) cos``, since
  ``F_x = F_x^(0) + d_3 F_beta``).
* ``F_gamma``: printed ``m_2 omega^2 e (y_D cos + x_D sin)``; corrected
  ``m_2 omega^2 e (x_D sin - y_D cos)`` (z-moment ``x F_y - y F_x`` of the
  centrifugal force at ``(x_D, y_D)``).
* gyroscopic factor: printed ``G`` (40) has ``2 I_p omega`` (from the kinetic
  energy term ``I_p omega (beta alpha' - alpha beta')`` of (27), twice the
  standard one); corrected ``I_p omega`` (spin-axis angular velocity
  ``omega + (beta alpha' - alpha beta') / 2`` for small tilts), i.e. the
  corrected ``G`` is exactly half the printed one.

Not corrected, in both modes (``delta_offset_term`` keyword): the third
numerator term ``(2 m_2 / m) x_D S_1 b_1 d_3^2`` of ``delta_1`` (and its y
analogue in ``delta_2``) of (33) has the wrong dimension (digest 3.5, [ERR?]) and
could not be reconstructed from the digest; it is kept as printed by default,
and ``delta_offset_term=False`` drops it (equivalent to ``m_2 = 0`` in that
term).  It vanishes for vertical hangers (``d_3 = d_4 = 0``) or ``x_D = y_D = 0``.

Planes and the unbalance force
------------------------------
Plane ``"rotor"`` is point D = ``(x_D, y_D, z_D)`` on the spin axis (the foot of
the perpendicular from the rotor's centre of mass, (31)).  Its fixed-frame
transverse displacement is ((5) with alpha_1, beta_1)::

    dx = (1 + z_D d_3) x + z_D beta - y_D gamma
    dy = (1 + z_D d_4) y - z_D alpha + x_D gamma

and ``T^T s omega^2 (cos, sin)(omega t)`` with ``s = m_2 e`` reproduces the
**corrected** F (43) entry for entry (including ``F_gamma``: the centrifugal
force at ``(x_D + e cos, y_D + e sin)`` has the z-moment of the same force at D,
so one plane point suffices).  The **printed** F (paper_exact) is *not*
``T^T (...)`` of any point (its ``F_beta``/``F_gamma`` are not moments of a
horizontal force); use :func:`force_amplitude` / :func:`generalized_force`,
the generalised-force hooks, for the exact F of either mode.  Plane
``"balancer"`` is the point ``(x_D, y_D, z_B)`` of the spin axis where a passive
autobalancer would sit (``z_B`` defaults to ``z_D``).

The paper gives **no numbers** (digest 3.8).  :func:`default_params` is an
assumed, plausible set (a small suspended centrifuge), with the stiffness ratio
of digest 5.2 item 5: pendulum ~2 rad/s, axial springs ~500 rad/s.

Module layout: the parameters (:class:`Hanger`, :func:`quadrifilar_hangers`,
:class:`PlatformParams`, :func:`default_params`) are defined in
:mod:`stand.model.rotors.platform_params` and re-exported here; this module holds
the linkage (19), (33), the matrices (39)-(42), the plane maps and forces (5),
(43), and the :class:`LinearRotor` with its modal and Campbell data.
"""
from __future__ import annotations

import math
from typing import Optional, Sequence

import numpy as np
from scipy import linalg

from stand.model.rotors._build import finite
from stand.model.rotors.platform_params import (Hanger, PlatformParams, default_hangers, default_params, quadrifilar_hangers,
                              scene_params)
from stand.model.rotors.structure import LinearRotor, Unbalance

__all__ = [
    "Hanger", "PlatformParams", "default_params", "quadrifilar_hangers", "default_hangers",
    "scene_params",
    "linkage_coefficients", "hanger_vector", "mass_matrix", "gyro_matrix",
    "damping_matrix", "stiffness_matrix", "plane_map", "force_amplitude",
    "generalized_force", "platform_rotor", "modal_frequencies", "campbell",
    "COORDS",
]

COORDS = ("x [m]", "y [m]", "z [m]", "alpha [rad]", "beta [rad]", "gamma [rad]")


# ------------------------------------------------------------------ linkage
def linkage_coefficients(params: PlatformParams, delta_offset_term: bool = True) -> dict:
    """Pendulum-linkage coefficients d_3, d_4 (19) [1/m] and delta_1, delta_2 [1/m],
    delta_3 [m] of the gravity potential (33).

    ``delta_offset_term=False`` drops the dimensionally inconsistent third
    numerator term of delta_1, delta_2 (module docstring).
    """
    p = params
    den1 = p.b1 * p.h + p.z_k * (p.S1 - p.b1)
    den2 = p.b2 * p.h + p.z_k * (p.S2 - p.b2)
    d3 = (p.S1 - p.b1) / den1
    d4 = (p.S2 - p.b2) / den2
    k = 1.0 if delta_offset_term else 0.0
    delta1 = (p.b1 ** 2 * p.h + 2.0 * (p.S1 - p.b1) ** 2 * p.z_k
              + k * 2.0 * p.m2 / p.m * p.x_D * p.S1 * p.b1 * d3 ** 2) / den1 ** 2
    delta2 = (p.b2 ** 2 * p.h + 2.0 * (p.S2 - p.b2) ** 2 * p.z_k
              + k * 2.0 * p.m2 / p.m * p.y_D * p.S2 * p.b2 * d4 ** 2) / den2 ** 2
    r2 = p.b1 ** 2 + p.b2 ** 2
    delta3 = r2 / (4.0 * p.h) * (1.0 + 4.0 * ((p.b2 * p.y_D - p.b1 * p.x_D) / r2) ** 2)
    return {"d3": d3, "d4": d4, "delta1": delta1, "delta2": delta2, "delta3": delta3}


def hanger_vector(hanger: Hanger, d3: float, d4: float) -> np.ndarray:
    """``v = (d_1, d_2, l_iz, d_5, d_6, d_7)`` [m, m, m, m^2, m^2, m^2] of (18)-(19):
    the rod elongation is ``v . q / l_i`` to first order, so
    ``a^(i)_kl = v_k v_l / l_i^2``."""
    lx, ly, lz = hanger.rod_vector()
    x, y, z = hanger.x, hanger.y, hanger.z
    d5 = y * lz - z * ly
    d6 = z * lx - x * lz
    d7 = x * ly - y * lx
    d1 = lx + d3 * d6
    d2 = ly - d5 * d4
    return np.array([d1, d2, lz, d5, d6, d7])


# ------------------------------------------------------------------ matrices
def mass_matrix(params: PlatformParams, paper_exact: bool = False) -> np.ndarray:
    """Mass matrix M (39) [kg, kg m, kg m^2]; ``paper_exact`` keeps the printed M_14."""
    p = params
    c = linkage_coefficients(p)
    d3, d4 = c["d3"], c["d4"]
    m, m2, Ia, Ib, Ic = p.m, p.m2, p.I_a1, p.I_b1, p.I_c1
    xD, yD, zD = p.x_D, p.y_D, p.z_D
    m14 = -m2 * yD * d3 if paper_exact else -m2 * xD * yD * d3
    M = np.array([
        [m + Ib * d3 ** 2 + 2 * m2 * zD * d3, m2 * xD * yD * d3 * d4, -m2 * xD * d3, m14,
         Ib * d3 + m2 * zD, -m2 * yD - m2 * yD * zD * d3],
        [0, m + Ia * d4 ** 2 + 2 * m2 * zD * d4, -m2 * yD * d4, -m2 * zD - Ia * d4,
         m2 * xD * yD * d4, m2 * xD + m2 * xD * zD * d4],
        [0, 0, m, m2 * yD, -m2 * xD, 0.0],
        [0, 0, 0, Ia, -m2 * xD * yD, -m2 * xD * zD],
        [0, 0, 0, 0, Ib, -m2 * yD * zD],
        [0, 0, 0, 0, 0, Ic],
    ], dtype=float)
    return np.triu(M) + np.triu(M, 1).T


def gyro_matrix(params: PlatformParams, paper_exact: bool = False) -> np.ndarray:
    """Gyroscopic matrix per unit spin [kg m^2 (/m, /m^2)]: ``G_paper(omega) = omega * G``.

    Corrected: ``I_p`` factor; ``paper_exact``: the printed (40) with ``2 I_p``.
    """
    c = linkage_coefficients(params)
    d3, d4 = c["d3"], c["d4"]
    k = (2.0 if paper_exact else 1.0) * params.I_p
    G = np.zeros((6, 6))
    G[0, 1] = k * d3 * d4
    G[0, 3] = -k * d3
    G[1, 4] = -k * d4
    G[3, 4] = k
    return G - G.T


def damping_matrix(params: PlatformParams) -> np.ndarray:
    """Damping matrix D (41) [N s/m, ...]: ``sum_i h_i v_i v_i^T / l_i^2``."""
    c = linkage_coefficients(params)
    D = np.zeros((6, 6))
    for hg in params.hangers:
        if hg.damping:
            v = hanger_vector(hg, c["d3"], c["d4"])
            D += hg.damping * np.outer(v, v) / hg.length ** 2
    return D


def stiffness_matrix(params: PlatformParams, paper_exact: bool = False,
                     delta_offset_term: bool = True) -> np.ndarray:
    """Stiffness matrix A (42) [N/m, N, N m] (gravity + rods + diaphragm).

    Corrected: the diaphragm part is ``P^T diag(c_2x, c_2y, c_2z) P`` from (25);
    ``paper_exact``: the printed diaphragm terms (a_23, a_26, a_56, a_66 as
    printed, a_25 without its diaphragm term).
    """
    p = params
    c = linkage_coefficients(p, delta_offset_term)
    d3, d4 = c["d3"], c["d4"]
    A = np.zeros((6, 6))
    for hg in p.hangers:
        if hg.c:
            v = hanger_vector(hg, d3, d4)
            A += hg.c * np.outer(v, v) / hg.length ** 2
    A[0, 0] += p.m * p.g * c["delta1"]
    A[1, 1] += p.m * p.g * c["delta2"]
    A[5, 5] += p.m * p.g * c["delta3"]
    A += _diaphragm_stiffness(p, d3, d4, paper_exact)
    return 0.5 * (A + A.T)


def _diaphragm_stiffness(p: PlatformParams, d3: float, d4: float, paper_exact: bool) -> np.ndarray:
    """Diaphragm part of A (42), entry by entry.

    The corrected entries equal ``P^T diag(c_2x, c_2y, c_2z) P`` with the rows
    ``P_x = (1 + z_M d_3, 0, 0, 0, z_M, -y_M)``,
    ``P_y = (0, 1 + z_M d_4, 0, -z_M, 0, x_M)``,
    ``P_z = (-x_M d_3, -y_M d_4, 1, y_M, -x_M, 0)`` of (25); writing them out keeps every unflagged
    entry bit-identical between the two switches.
    """
    cx, cy, cz = p.c2x, p.c2y, p.c2z
    xm, ym, zm = p.x_M, p.y_M, p.z_M
    U = np.zeros((6, 6))              # upper triangle
    U[0, 0] = cx * (1 + zm * d3) ** 2 + cz * xm ** 2 * d3 ** 2
    U[0, 1] = cz * xm * ym * d3 * d4
    U[0, 2] = -cz * xm * d3
    U[0, 3] = -cz * ym * xm * d3
    U[0, 4] = cx * zm * (1 + zm * d3) + cz * xm ** 2 * d3
    U[0, 5] = -cx * ym * (1 + zm * d3)
    U[1, 1] = cy * (1 + zm * d4) ** 2 + cz * ym ** 2 * d4 ** 2
    U[1, 3] = -cy * zm * (1 + zm * d4) - cz * ym ** 2 * d4
    U[2, 2] = cz
    U[2, 3] = cz * ym
    U[2, 4] = -cz * xm
    U[3, 3] = cy * zm ** 2 + cz * ym ** 2
    U[3, 4] = -cz * ym * xm
    U[3, 5] = -cy * xm * zm
    U[4, 4] = cx * zm ** 2 + cz * xm ** 2
    if paper_exact:                   # printed (42), flagged [ERR] entries
        U[1, 2] = -cx * ym * d4
        U[1, 4] = 0.0                 # a_25: diaphragm term missing in print
        U[1, 5] = -cy * xm * (1 + zm * d4)
        U[4, 5] = -cy * ym * zm
        U[5, 5] = cx * zm ** 2 + cy * xm ** 2
    else:                             # corrected from (25)
        U[1, 2] = -cz * ym * d4
        U[1, 4] = cz * xm * ym * d4
        U[1, 5] = cy * xm * (1 + zm * d4)
        U[4, 5] = -cx * ym * zm
        U[5, 5] = cx * ym ** 2 + cy * xm ** 2
    return np.triu(U) + np.triu(U, 1).T


# ------------------------------------------------------------------ planes, forces
def plane_map(params: PlatformParams, z: float) -> np.ndarray:
    """T (2 x 6) of the spin-axis point ``(x_D, y_D, z)``: its fixed-frame
    transverse displacement ``(dx, dy) = T q`` [m], from (5) with alpha_1, beta_1."""
    c = linkage_coefficients(params)
    xD, yD = params.x_D, params.y_D
    return np.array([
        [1 + z * c["d3"], 0.0, 0.0, 0.0, z, -yD],
        [0.0, 1 + z * c["d4"], 0.0, -z, 0.0, xD],
    ])


def _force_coeffs(params: PlatformParams, paper_exact: bool):
    """F = s * (Ccoef * C + Scoef * Sn) with C = omega^2 cos, Sn = omega^2 sin."""
    p = params
    if not paper_exact:
        T = plane_map(p, p.z_D)
        return T[0].copy(), T[1].copy()
    c = linkage_coefficients(p)
    Cc = np.array([1 + p.z_D * c["d3"], 0, 0, 0, 0, p.y_D], dtype=float)
    Sc = np.array([0, 1 + p.z_D * c["d4"], 0, -p.z_D, p.z_D, p.x_D], dtype=float)
    return Cc, Sc


def force_amplitude(params: PlatformParams, omega: float, paper_exact: bool = False) -> np.ndarray:
    """Complex amplitude F_hat (6,) [N, N m] of the unbalance force (43) at constant
    spin omega [rad/s]: ``F(t) = Re(F_hat e^{i omega t})`` (cos -> 1, sin -> -i).

    Corrected: equals ``T_rotor^T s omega^2 (1, -i)``.  ``paper_exact``: the
    printed (43) (``F_beta ~ sin``, ``F_gamma ~ y_D cos + x_D sin``), which is
    not of that form; this is the generalised-force hook a simulation needs.
    """
    omega = finite("omega", omega, "rad/s")
    Cc, Sc = _force_coeffs(params, paper_exact)
    return params.s * omega ** 2 * (Cc - 1j * Sc)


def generalized_force(params: PlatformParams, phi, phi_dot, phi_ddot=0.0,
                      paper_exact: bool = False) -> np.ndarray:
    """Real generalised unbalance force (6,) [N, N m] at rotor angle phi [rad],
    speed phi_dot [rad/s] and acceleration phi_ddot [rad/s^2].

    Eq. (43) with ``omega^2 cos -> phi'^2 cos phi + phi'' sin phi`` and
    ``omega^2 sin -> phi'^2 sin phi - phi'' cos phi`` (digest 3.6, variable
    speed); for constant speed ``phi = omega t`` it is (43) itself (corrected
    or, with ``paper_exact``, as printed).
    """
    Cc, Sc = _force_coeffs(params, paper_exact)
    cp, sp = math.cos(phi), math.sin(phi)
    C = phi_dot ** 2 * cp + phi_ddot * sp
    Sn = phi_dot ** 2 * sp - phi_ddot * cp
    return params.s * (Cc * C + Sc * Sn)


# ------------------------------------------------------------------ the rotor
def platform_rotor(params: Optional[PlatformParams] = None, paper_exact: bool = False,
                   delta_offset_term: bool = True, *,
                   m: Optional[float] = None, m2: Optional[float] = None,
                   I_a1: Optional[float] = None, I_b1: Optional[float] = None,
                   I_c1: Optional[float] = None, I_p: Optional[float] = None,
                   S1: Optional[float] = None, S2: Optional[float] = None,
                   b1: Optional[float] = None, b2: Optional[float] = None,
                   h: Optional[float] = None, z_k: Optional[float] = None,
                   c2x: Optional[float] = None, c2y: Optional[float] = None,
                   c2z: Optional[float] = None, x_M: Optional[float] = None,
                   y_M: Optional[float] = None, z_M: Optional[float] = None,
                   x_D: Optional[float] = None, y_D: Optional[float] = None,
                   z_D: Optional[float] = None, e: Optional[float] = None,
                   g: Optional[float] = None, z_B: Optional[float] = None,
                   rod_stiffness: Optional[float] = None, rod_damping: Optional[float] = None,
                   rim_damping: Optional[float] = None, rim_radius: Optional[float] = None,
                   rim_length: Optional[float] = None) -> LinearRotor:
    """The paper-004 system as a :class:`LinearRotor` (K = A, G per unit spin).

    Parameters
    ----------
    params : PlatformParams, optional
        Default: :func:`default_params` (assumed numbers).
    paper_exact : bool
        False (default): corrected model; True: the printed formulas (module
        docstring lists every difference).
    delta_offset_term : bool
        Keep the printed third numerator term of delta_1, delta_2 (33).
    m, m2, I_a1, ..., z_B, rod_stiffness, rod_damping, rim_damping, rim_radius, rim_length
        Keyword parameters (SI units, each None = the :func:`default_params` value; the
        scene file's ``[structure]`` keys): the :class:`PlatformParams` fields m [kg],
        m2 [kg], I_a1, I_b1, I_c1, I_p [kg m^2], S1, S2, b1, b2, h, z_k [m], c2x, c2y,
        c2z [N/m], x_M, y_M, z_M, x_D, y_D, z_D [m], e [m], g [m/s^2], z_B [m], and the
        hangers of :func:`default_hangers` (rebuilt from the linkage geometry):
        rod_stiffness [N/m] and rod_damping [N s/m] of each of the four rods,
        rim_damping [N s/m] of each of the four horizontal rim dampers at rim_radius [m]
        (rods of rim_length [m]).  Not allowed together with ``params``.

    Returns
    -------
    LinearRotor
        Coordinates ``(x, y, z, alpha, beta, gamma)``; planes ``"rotor"`` (point
        D) and ``"balancer"`` (``(x_D, y_D, z_B)``); one unbalance
        ``Unbalance("rotor", m2 e, 0)``.  With ``paper_exact`` the printed F is
        not ``T^T(...)``: use :func:`force_amplitude` / :func:`generalized_force`.
    """
    given = {k: v for k, v in (("m", m), ("m2", m2), ("I_a1", I_a1), ("I_b1", I_b1),
                               ("I_c1", I_c1), ("I_p", I_p), ("S1", S1), ("S2", S2), ("b1", b1),
                               ("b2", b2), ("h", h), ("z_k", z_k), ("c2x", c2x), ("c2y", c2y),
                               ("c2z", c2z), ("x_M", x_M), ("y_M", y_M), ("z_M", z_M),
                               ("x_D", x_D), ("y_D", y_D), ("z_D", z_D), ("e", e), ("g", g),
                               ("z_B", z_B), ("rod_stiffness", rod_stiffness),
                               ("rod_damping", rod_damping), ("rim_damping", rim_damping),
                               ("rim_radius", rim_radius), ("rim_length", rim_length))
             if v is not None}
    if isinstance(params, dict):       # a scene file's `params = {...}` table: the same keys
        given = {**params, **given}
        params = None
    if params is not None and given:
        raise ValueError(f"give either params (a PlatformParams) or the keyword parameters "
                         f"{', '.join(given)}, not both")
    p = params if params is not None else (scene_params(**given) if given else default_params())
    M = mass_matrix(p, paper_exact)
    try:
        np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        raise ValueError(f"mass matrix M (39) [kg, kg m, kg m^2] is not positive definite for "
                         f"these parameters (check m = {p.m} kg, I_a1 = {p.I_a1}, I_b1 = {p.I_b1}, "
                         f"I_c1 = {p.I_c1} kg m^2 against m2 = {p.m2} kg and the offsets "
                         f"x_D, y_D, z_D = {p.x_D}, {p.y_D}, {p.z_D} m)") from None
    planes = {"rotor": plane_map(p, p.z_D), "balancer": plane_map(p, p.balancer_z)}
    unb = (Unbalance("rotor", p.s, 0.0),) if p.s > 0 else ()
    return LinearRotor(
        name="platform_paper004", coords=COORDS, M=M, G=gyro_matrix(p, paper_exact),
        D=damping_matrix(p), K=stiffness_matrix(p, paper_exact, delta_offset_term),
        planes=planes, unbalances=unb, gravity=np.zeros(6), gravity_plane=np.zeros(2),
        source=("paper 004 (Drach), eqs. (38)-(43), papers digest 3.6; "
                + ("printed formulas (paper_exact)" if paper_exact else "corrected (digest 5.1 M3)")),
    )


def modal_frequencies(params: Optional[PlatformParams] = None, paper_exact: bool = False,
                      delta_offset_term: bool = True, return_modes: bool = False):
    """Undamped, non-spinning natural frequencies [rad/s]: the generalised
    eigenproblem ``A u = w^2 M u`` (38) with G = D = 0, ascending.

    A negative entry ``-sqrt(|w^2|)`` flags a statically unstable mode (A not
    positive definite).  With ``return_modes`` also the M-normalised mode
    shapes (columns).
    """
    p = default_params() if params is None else params
    M = mass_matrix(p, paper_exact)
    A = stiffness_matrix(p, paper_exact, delta_offset_term)
    lam, U = linalg.eigh(A, M)
    w = np.sign(lam) * np.sqrt(np.abs(lam))
    return (w, U) if return_modes else w


def campbell(params: Optional[PlatformParams], speeds: Sequence[float],
             paper_exact: bool = False, delta_offset_term: bool = True) -> np.ndarray:
    """Campbell data: natural frequencies [rad/s] (rows: spin speeds [rad/s],
    columns: modes) via :meth:`LinearRotor.campbell` (damped, with G(omega))."""
    return platform_rotor(params, paper_exact, delta_offset_term).campbell(speeds)
