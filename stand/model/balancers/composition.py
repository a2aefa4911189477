"""The book weight models as generic compositions: planar rotor x body weight (SI).

Each model of :mod:`stand.model.balancers` brings its own rotor: a rigid rotor in
plane-parallel motion on isotropic visco-elastic supports (chapters 6-7,
paper 001).  :func:`composition` rebuilds it as the stand composes any scene
-- a :class:`~stand.model.rotors.structure.LinearRotor` (the planar rotor 2.5.1)
plus one body weight of :mod:`stand.model.rotors.bodies` in its plane
``"balancer"`` -- so that the generic compiled right-hand side
(:mod:`stand.model.rotors.bodies_kernel`) can be checked against the book's own
equations (``tests/test_body_weights.py``), and a ``[weight_model]`` scene
runs on the generic kernel.

Units of the dimensionless models (ch. 6, 7.1, 7.2): the book's time
``tau = omega0 t`` and lengths in units of ``rho^2 / l`` are recorded with the
choice ``M_Sigma = 1 kg``, ``omega0 = 1 rad/s`` (so ``c = 1 N/m``), ``l = 1 m``
and ``A = m l^2 = R_m kg m^2`` (``rho = 1 m``): then ``t = tau`` and the
shaft displacement in metres *is* the book's ``x`` (the inverse of the
scalings (6.9)-(6.11), (7.3)-(7.5), (7.48)-(7.50))::

    m = R_m,  M = 1 - R_m,  A = R_m,  B = R_rho^2 A,  H1 = h1 A,  H2 = h2 B,
    H3 = H,  g_a = R_g^2,  M e = e0 m l  (angle gamma)

Paper 001 is in SI already: rotor ``m1``, ``c = m1 Omega_0^2``, ``chi = n m1``,
and a liquid of lever ``lambda`` with ``m2 lambda = m1 (1/psi - 1)`` (only the
product enters model M1); the speed law (6) is the programme
``omega_0 + 2 epsilon t``.
"""
from __future__ import annotations

import math

import numpy as np

from stand.model.rotors.bodies import LiquidWeight, PlaneBody, SphericalWeight, TiltingWeight
from stand.model.rotors.planar_supports import planar_rotor

__all__ = ["composition", "Composition"]


class Composition:
    """A book model as ``rotor`` (LinearRotor), ``body`` (PlaneBody), ``programme``
    (``[[t_s, omega_rad_s], ...]``) and the initial shaft state ``q0``, ``qd0`` [m, m/s]."""

    def __init__(self, rotor, body, programme, q0=(0.0, 0.0), qd0=(0.0, 0.0), length=1.0):
        self.rotor, self.body, self.programme = rotor, body, np.asarray(programme, float)
        self.q0, self.qd0 = np.asarray(q0, float), np.asarray(qd0, float)
        self.length = length    #: metres per unit of the book's shaft displacement


def _unit_rotor(R_m, H, e0, gamma=0.0):
    M = 1.0 - R_m
    return planar_rotor(M, 1.0, 1.0, H, H, unbalance=e0 * R_m, unbalance_angle=gamma)


def composition(kind: str, p, duration: float = 1.0, initial=None) -> Composition:
    """The generic composition of book model ``kind`` with parameters ``p``.

    Parameters
    ----------
    kind : {"two_axis", "gravity_pair", "damper", "liquid_float", "liquid_chamber"}
    p : the model's parameter dataclass
    duration : float
        Run length [s] (the programme is extended to it; paper 001's run-up).
    initial : array or float, optional
        The book model's fixed-frame initial state (its ``STATE_COLUMNS``); the
        body starts from the same state.  For the liquid chamber: the constant
        speed [rad/s] (default half the critical speed).
    """
    if kind in ("two_axis", "gravity_pair"):
        R_m, R_rho = p.R_m, p.R_rho
        ga = p.R_g ** 2 if kind == "two_axis" else 0.0
        ph0, al0, x0, y0, dph0, dal0, dx0, dy0 = (
            initial if initial is not None else (0.3, 0.0, 0.0, 0.0, 0.0, p.R_omega, 0.0, 0.0))
        A = R_m
        B = R_rho ** 2 * A
        body = TiltingWeight("two_axis_pendulum" if kind == "two_axis" else "coupled_pair",
                             mass=R_m, arm=1.0, inertia_tilt=A, inertia_axial=B,
                             tilt_drag=p.h1 * A, turn_drag=p.h2 * B, axial_gravity=ga,
                             initial_tilt=ph0, initial_angle=al0, initial_tilt_rate=dph0,
                             initial_speed=dal0 - p.R_omega)
        rotor = _unit_rotor(R_m, p.H, p.e0, getattr(p, "gamma", 0.0))
        return Composition(rotor, PlaneBody("balancer", body), [[0.0, p.R_omega]],
                           (x0, y0), (dx0, dy0))
    if kind == "damper":
        R_m = p.R_m
        if p.friction is not None:
            raise ValueError("damper: dry friction (7.79)-(7.84) has no generic composition yet")
        if initial is None:
            from stand.model.balancers.damper_motion import state_from_angles

            initial = state_from_angles(0.3, 0.0, p.R_omega, frame="fixed")
        x0, y0, dx0, dy0 = initial[:4]
        n = np.asarray(initial[4:7], float)
        W = np.asarray(initial[7:10], float)
        body = SphericalWeight(mass=R_m, arm=1.0, inertia=R_m, drag=p.h * R_m,
                               axial_gravity=p.R_g ** 2, constraint_gain=p.k_c)
        comp = Composition(_unit_rotor(R_m, p.H, p.e0, p.gamma), PlaneBody("balancer", body),
                           [[0.0, p.R_omega]], (x0, y0), (dx0, dy0))
        comp.initial_body = np.concatenate([n, W])
        return comp
    if kind == "liquid_float":
        m1 = p.m1
        lever = 2.0
        m2 = m1 * (1.0 / p.psi - 1.0) / lever
        # r1 = 1 m; lever = r1^2/(r1^2 - r2^2)
        r2 = math.sqrt(1.0 - 1.0 / lever)
        body = LiquidWeight("liquid_float", mass=m2, chamber_radius=1.0, surface_radius=r2)
        rotor = planar_rotor(m1, m1 * p.Omega_0 ** 2, m1 * p.Omega_0 ** 2, p.n * m1, p.n * m1,
                             unbalance=m1 * p.e)
        sp = p.speed()
        T = max(float(duration), 1e-9)
        prog = [[0.0, float(sp.omega(0.0))], [T, float(sp.omega(T))]]
        if initial is None:
            from stand.model.balancers.liquid_float_motion import initial_state

            initial = initial_state(p, frame="fixed")
        return Composition(rotor, PlaneBody("balancer", body), prog, initial[:2], initial[2:4])
    if kind == "liquid_chamber":
        # thesis 002: dry rotor M (disk + chamber + unbalance mass), liquid m = rho V, the
        # critical speed and decay rate of (2.5) of the rotor with the liquid (M + m); the
        # in-plane gravity of an inclined shaft is left out, as in the thesis (digest 2.2)
        Mt = p.total_mass
        c = Mt * p.critical_speed ** 2
        chi = 2.0 * p.n * Mt
        R, h, V = p.chamber_radius, p.chamber_height, p.liquid_volume
        r = math.sqrt(R * R - V / (math.pi * h))
        body = LiquidWeight("liquid_chamber", p.liquid_mass, R, r, height=h, volume=V,
                            density=p.liquid_density, viscosity=p.kinematic_viscosity)
        rotor = planar_rotor(p.dry_mass, c, c, chi, chi, unbalance=p.rotor_unbalance)
        speed = float(initial) if initial is not None else 0.5 * p.critical_speed
        return Composition(rotor, PlaneBody("balancer", body), [[0.0, speed]])
    raise ValueError(f"kind = {kind!r}: one of two_axis, gravity_pair, damper, liquid_float, "
                     "liquid_chamber")


def book_params(scene, speed: float | None = None):
    """The book model of a planar scene with one body weight: ``(kind, params)`` or None.

    The inverse of :func:`composition`: the planar rotor on isotropic supports
    with one body weight in the plane ``"balancer"`` (and no balls) is the book's
    stand, so its dimensionless parameters follow from (6.9)-(6.11), (7.3)-(7.5),
    (7.48)-(7.50) (``M_Sigma = M + m``, ``omega0 = sqrt(c/M_Sigma)``,
    ``R_omega = speed/omega0``); paper 001's M1 for a liquid whose centre of
    mass follows at once; thesis 002's parameters for a chamber.

    Parameters
    ----------
    scene : stand.scene.model.Scene
    speed : float, optional
        Spin [rad/s] (default: the programme's last speed).
    """
    from stand.model.rotors.bodies import LiquidWeight, SphericalWeight, TiltingWeight

    if scene.kind != "planar" or len(scene.bodies) != 1 or scene.balancer.count:
        return None
    s, r = scene.supports, scene.rotor
    if s.stiffness_x != s.stiffness_y or s.damping_x != s.damping_y:
        return None
    b = scene.bodies[0].body
    c, chi, M = s.stiffness_x, s.damping_x, r.mass
    prog = scene.drive.programme if scene.drive.kind == "speed" else None
    w = float(speed if speed is not None else (prog[-1, 1] if prog is not None else 0.0))
    Ms = M + b.mass
    w0 = math.sqrt(c / Ms)
    common = dict(R_omega=w / w0, H=chi / (Ms * w0))
    if isinstance(b, TiltingWeight):
        m, l, A, B = b.mass, b.arm, b.inertia_tilt, b.inertia_axial
        rho2 = A / m
        kw = dict(R_m=m * l * l / (Ms * rho2), R_rho=math.sqrt(B / A), h1=b.tilt_drag / (A * w0),
                  h2=b.turn_drag / (B * w0), e0=r.unbalance / (m * l), **common)
        if b.kind == "coupled_pair":
            from stand.model.balancers.gravity_pair_params import GravityPairParams

            return "gravity_pair", GravityPairParams(gamma=r.unbalance_angle, **kw)
        from stand.model.balancers.two_axis_params import TwoAxisParams

        return "two_axis", TwoAxisParams(R_g=math.sqrt(b.axial_gravity * l / (rho2 * w0 * w0)),
                                         **kw)
    if isinstance(b, SphericalWeight):
        from stand.model.balancers.damper_params import DamperParams

        m, l, A = b.mass, b.arm, b.inertia
        rho2 = A / m
        return "damper", DamperParams(R_m=m * l * l / (Ms * rho2),
                                      R_g=math.sqrt(b.axial_gravity * l / (rho2 * w0 * w0)),
                                      h=b.drag / (A * w0), e0=r.unbalance / (m * l),
                                      gamma=r.unbalance_angle, **common)
    if isinstance(b, LiquidWeight) and b.kind == "liquid_float":
        from stand.model.balancers.liquid_float_params import LiquidFloatParams

        w_start = float(prog[0, 1]) if prog is not None else w
        eps = 0.0
        if prog is not None and len(prog) >= 2 and prog[1, 0] > prog[0, 0]:
            eps = 0.5 * (prog[1, 1] - prog[0, 1]) / (prog[1, 0] - prog[0, 0])
        return "liquid_float", LiquidFloatParams(
            Omega_0=math.sqrt(c / M), psi=M / (M + b.mass * b.lever), n=chi / M,
            e=r.eccentricity, omega_0=w_start, epsilon=eps, m1=M)
    if isinstance(b, LiquidWeight):
        from stand.model.balancers.liquid_chamber_params import LiquidChamberParams

        D0 = r.unbalance
        horizontal = any(abs(g) > 0 for g in scene.linear_rotor().gravity_plane)
        return "liquid_chamber", LiquidChamberParams(
            rotor_mass=max(M - D0, 0.0), chamber_mass=0.0, unbalance_mass=D0,
            unbalance_radius=1.0, critical_speed=math.sqrt(c / (M + b.mass)),
            chamber_radius=b.chamber_radius, chamber_height=b.height, liquid_volume=b.volume,
            liquid_density=b.density, kinematic_viscosity=b.viscosity,
            damping_rate=chi / (2.0 * (M + b.mass)),
            inclination=0.0 if horizontal else math.pi / 2)
    return None
