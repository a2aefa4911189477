"""The gravity-insensitive non-classical autobalancer: the coupled pair (book 7.1).

Digest ``ch7_ch1.md`` sections 0, 1 and 5 (Filimonikhin 2004, section 7.1).

Physical model (digest 1.2)
---------------------------
A vertical rotor in plane-parallel motion on isotropic visco-elastic supports
(stiffness ``c`` [N/m], external viscous coefficient ``H3`` [N s/m] on the
absolute velocity of the shaft point K) spins at the constant rate ``omega``
[rad/s].  Two identical correction weights (CWs) are coupled so that they turn
about transverse axes by equal angles in *opposite* directions: the upper one
hangs, the lower one is inverted, both centres of mass move sideways by
``l sin(phi)`` and their vertical shifts cancel, so gravity does no work
(digest 1.1).  The pair is modelled as one weight of mass ``m`` (the pair's
total), arm ``l`` [m], moment of inertia ``A`` [kg m^2] about the transverse
axes and ``B`` [kg m^2] about the rotor axis (both taken constant, as in the
book).  Its orientation is given by the transverse angle ``phi`` and the angle
about the rotor axis (``psi`` relative to the rotor, ``alpha = psi + R_omega
tau`` absolute).  The CWs' centre of mass sits, relative to the pivot, at the
complex horizontal offset ``l * i sin(phi) e^{i alpha}``.  Viscous moments act
on the relative rates: ``-H1 phi'`` and ``-H2 psi'`` [N m s].

Dimensionless variables, (7.3)-(7.5) with erratum E2 (``xi = x l / rho1^2``,
not the printed ``x / rho1``; the printed scale would not make ``R_m`` appear in
the rotor equations -- see :func:`GravityPairParams.from_physical` and the test
``test_e2_length_scale``)::

    tau = omega0 t,  omega0 = sqrt(c / M_Sigma),  rho1 = sqrt(A/m), rho2 = sqrt(B/m)
    z = (x + i y) l / rho1^2           (fixed frame)
    R_m = m l^2/(M_Sigma rho1^2),  R_omega = omega/omega0,  R_rho = rho2/rho1,
    h1 = H1/(A omega0),  h2 = H2/(B omega0),  H = H3/(M_Sigma omega0),
    e0 = M e/(m l).

Equations of motion, fixed frame, (7.34) (verified by the digest and again here
by a Lagrangian derivation with sympy)::

    phi'' + h1 phi' + Im(z'' e^{-i alpha}) cos(phi) = 0
    [alpha'' + h2 (alpha' - R_omega)] R_rho^2 - Re(z'' e^{-i alpha}) sin(phi) = 0
    z'' + H z' + z - R_m < {(2 alpha' phi' - i phi'') cos(phi)
          + [alpha'' + i (phi'^2 + alpha'^2)] sin(phi)} e^{i alpha}
          + R_omega^2 e0 e^{i (R_omega tau + gamma)} > = 0

The rotating-frame form is (7.2) with erratum E1: the braces of the two rotor
equations contain ``phi''`` and ``psi''`` where the print (an OCR loss) has
``phi'`` and ``psi'``.  The oracle's ``rhs_rotating`` (tests/oracles/gravity_pair.py) implements the corrected form and,
with ``printed_e1=True``, the printed one (for the erratum test only).

The second derivatives enter linearly; eliminating ``z''`` decouples the two
weight equations exactly (the 4x4 mass matrix has the determinant
``(1 - R_m cos^2 phi)(R_rho^2 - R_m sin^2 phi)`` times a constant, cf. the
coefficient a_8 of (7.13)), so each right-hand-side evaluation is closed form:

    phi''  (1 - R_m cos^2 phi)         = -h1 phi' - cos(phi) Im(F e^{-i alpha})
    alpha''(R_rho^2 - R_m sin^2 phi)  = -h2 R_rho^2 (alpha' - R_omega) + sin(phi) Re(F e^{-i alpha})

with ``F = -H z' - z + R_m[(2 alpha' phi' cos phi + i (phi'^2 + alpha'^2) sin phi) e^{i alpha}
+ R_omega^2 e0 e^{i(R_omega tau + gamma)}]`` and then
``z'' = F + R_m (alpha'' sin phi - i phi'' cos phi) e^{i alpha}``.

State vectors
-------------
Fixed frame (the oracle's ``rhs``)::

    y = [phi, alpha, x, y, phi', alpha', x', y']     (rad, rad, -, -, per tau ...)

Rotating frame (the oracle's ``rhs_rotating``)::

    y = [phi, psi, xi, eta, phi', psi', xi', eta']

with ``psi = alpha - R_omega tau`` and ``xi + i eta = z e^{-i R_omega tau}`` (7.35).

Modules
-------
This module re-exports the parameters (:mod:`.gravity_pair_params`) and the model's functions from
:mod:`.gravity_pair_motion` (frames, energy).  The theory is in :mod:`stand.theories.weights`:
steady motions (7.6)-(7.9) and their stability in ``gravity_pair_steady``, quasi-periodic
motions (7.38)-(7.46) in ``gravity_pair_qp``.
"""
from __future__ import annotations

from stand.model.balancers.gravity_pair_params import GravityPairParams
from stand.model.balancers.gravity_pair_motion import energy, to_fixed, to_rotating

__all__ = [
    "GravityPairParams", "to_rotating", "to_fixed", "energy",
]
