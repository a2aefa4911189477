"""``[[weights]]`` tables of the body kinds: SI keys, or the book's dimensionless form as sugar.

::

    [[weights]]
    plane = "balancer"
    type = "two_axis_pendulum"     # or coupled_pair, damper, liquid_float, liquid_chamber
    mass = 0.05                    # kg
    arm = 0.04                     # m, hinge to centre of mass
    inertia_tilt = 1.2e-4          # kg m^2 about the tilt axis (default m l^2)
    inertia_axial = 0.6e-4         # kg m^2 about the shaft axis (default inertia_tilt / 2)
    tilt_drag = 1e-4               # N m s
    turn_drag = 1e-4               # N m s
    axial_gravity = 9.80665        # m/s^2 (default: g on a vertical shaft, 0 on a horizontal one)
    housing_radius = 0.05          # m, optional: the weight must fit (arm < housing_radius)
    initial_tilt = 5.0             # deg
    initial_angle = 0.0            # deg from the rotor's mark

The dimensionless sugar (chapters 6-7) gives the weight in units of the rotor
it sits on (the planar rotor: ``M_Sigma = M + m``, ``omega0 = sqrt(c/M_Sigma)``)
with its mass and arm in SI::

    type = "two_axis_pendulum"
    mass = 0.05
    arm = 0.04
    dimensionless = { R_m = 0.2, R_rho = 0.7071, R_g = 0.4, h1 = 0.1, h2 = 0.1 }

(``rho1^2 = m l^2 / (M_Sigma R_m)``, ``A = m rho1^2``, ``B = R_rho^2 A``,
``H1 = h1 A omega0``, ``H2 = h2 B omega0``, ``g_a = R_g^2 rho1^2 omega0^2 / l``;
for the damper ``h`` for ``h1``.)

Liquids::

    type = "liquid_float"          # paper 001
    liquid_mass = 0.4              # kg
    chamber_radius = 0.1           # m (r1)
    float_radius = 0.07            # m (r2): the free surface

    type = "liquid_chamber"        # thesis 002
    chamber_radius = 0.1           # m (R)
    chamber_height = 0.03          # m (h)
    fill_volume = 2.0e-4           # m^3 (V), 0 < V < pi R^2 h
    density = 1000.0               # kg/m^3
    viscosity = 1.0e-6             # m^2/s (kinematic; the theory's liquid choice)
    relaxation_time = 0.0          # s: free surface to the axis (0: at once)
"""
from __future__ import annotations

import math
from typing import Mapping

from stand.io.validate import _Table, _fmt
from stand.errors import SceneError
from stand.model.rotors.bodies import G_STANDARD, LiquidWeight, PlaneBody, SphericalWeight, TiltingWeight

__all__ = ["BODY_TYPES", "parse_body"]

DEG = math.pi / 180.0
TWO_PI = 2.0 * math.pi
#: weight kind -> source
BODY_TYPES = {"two_axis_pendulum": "monograph ch. 6", "coupled_pair": "monograph ch. 7.1",
              "damper": "monograph ch. 7.2", "liquid_float": "paper 001 (model M1)",
              "liquid_chamber": "thesis 002"}
_TILT_KEYS = ("mass", "arm", "inertia_tilt", "inertia_axial", "tilt_drag", "turn_drag",
              "axial_gravity", "housing_radius", "initial_tilt", "initial_angle",
              "initial_tilt_rate", "initial_speed", "dimensionless")
_DAMPER_KEYS = ("mass", "arm", "inertia", "drag", "axial_gravity", "housing_radius",
                "initial_tilt", "initial_angle", "dimensionless")
_FLOAT_KEYS = ("liquid_mass", "chamber_radius", "float_radius", "chamber_height")
_CHAMBER_KEYS = ("chamber_radius", "chamber_height", "fill_volume", "density", "viscosity",
                 "relaxation_time")


def _rotor_units(rotor, mass):
    """(M_Sigma [kg], omega0 [rad/s]) of the planar rotor carrying a weight of ``mass``."""
    Ms = float(rotor.M[0, 0]) + mass
    c = float(rotor.K[0, 0])
    return Ms, math.sqrt(c / Ms)


def _sugar(t: _Table, kind: str, m: float, l: float, rotor) -> dict:
    """SI inertia, drags and gravity from the book's dimensionless form."""
    d = _Table(t.data["dimensionless"], t.name("dimensionless"))
    d.allow(("R_m", "R_g", "h") if kind == "damper" else ("R_m", "R_rho", "R_g", "h1", "h2"))
    if rotor is None or rotor.n != 2 or rotor.name != "planar":
        raise SceneError(f"{t.name('dimensionless')}: the book's dimensionless form is defined on "
                         "the planar rotor (its M_Sigma and omega0); give SI keys on this rotor")
    Ms, w0 = _rotor_units(rotor, m)
    R_m = d.number("R_m", "-", gt=0)
    rho2 = m * l * l / (Ms * R_m)
    if rho2 < l * l * (1.0 - 1e-12):
        raise SceneError(f"{d.name('R_m')} = {_fmt(R_m)}: must be <= m/M_Sigma = {m / Ms:.6g} "
                         "(the inertia about the hinge is at least m l^2)")
    A = m * rho2
    out = {"A": A, "g_a": d.number("R_g", "-", 0.0, ge=0) ** 2 * rho2 * w0 * w0 / l}
    if kind == "damper":
        out["H1"] = d.number("h", "-", 0.0, ge=0) * A * w0
        return out
    B = d.number("R_rho", "-", math.sqrt(0.5), gt=0) ** 2 * A
    out.update(B=B, H1=d.number("h1", "-", 0.0, ge=0) * A * w0,
               H2=d.number("h2", "-", 0.0, ge=0) * B * w0)
    return out


def _fits(t: _Table, l: float):
    if "housing_radius" in t:
        Rh = t.number("housing_radius", "m", gt=0)
        if l >= Rh:
            raise SceneError(f"{t.name('arm')} = {_fmt(l)}: must be < housing_radius = {_fmt(Rh)} "
                             "(m; the weight would hit its housing)")


def _inertia(t: _Table, key: str, l: float, m: float, default: float) -> float:
    J = t.number(key, "kg*m^2", default, gt=0)
    if J < m * l * l * (1.0 - 1e-12):
        raise SceneError(f"{t.name(key)} = {_fmt(J)}: must be >= m l^2 = {m * l * l:.6g} "
                         "(kg*m^2, about the hinge; parallel-axis theorem)")
    return J


def parse_body(item: Mapping, where: str, plane: str, rotor=None) -> PlaneBody:
    """One ``[[weights]]`` table of a body kind (module docstring) -> :class:`PlaneBody`.

    Parameters
    ----------
    item : mapping
        The table without its ``plane`` key.
    where : str
        Its dotted name for the messages, e.g. ``"weights[0]"``.
    plane : str
        The plane it sits in.
    rotor : LinearRotor, optional
        The structure (defaults of the gravity; the dimensionless sugar).
    """
    t = _Table(dict(item), where)
    kind = t.string("type", tuple(BODY_TYPES))
    horizontal = rotor is not None and any(abs(g) > 0 for g in rotor.gravity_plane)
    g_default = 0.0 if horizontal else G_STANDARD
    if kind in ("two_axis_pendulum", "coupled_pair"):
        t.allow(("type",) + _TILT_KEYS)
        m = t.number("mass", "kg", gt=0)
        l = t.number("arm", "m", gt=0)
        _fits(t, l)
        if "dimensionless" in t:
            for k in ("inertia_tilt", "inertia_axial", "tilt_drag", "turn_drag", "axial_gravity"):
                if k in t:
                    raise SceneError(f"{t.name(k)}: give either SI keys or {t.name('dimensionless')}")
            s = _sugar(t, kind, m, l, rotor)
            A, B, H1, H2, ga = s["A"], s["B"], s["H1"], s["H2"], s["g_a"]
        else:
            A = _inertia(t, "inertia_tilt", l, m, m * l * l)
            B = t.number("inertia_axial", "kg*m^2", 0.5 * A, gt=0)
            H1 = t.number("tilt_drag", "N*m*s", 0.0, ge=0)
            H2 = t.number("turn_drag", "N*m*s", 0.0, ge=0)
            ga = t.number("axial_gravity", "m/s^2", g_default if kind == "two_axis_pendulum"
                          else 0.0, ge=0)
        if kind == "coupled_pair" and ga:
            raise SceneError(f"{t.name('axial_gravity')} = {_fmt(ga)}: the coupled pair is built so "
                             "that gravity does no work (ch. 7.1); use two_axis_pendulum")
        body = TiltingWeight(kind, m, l, A, B, H1, H2, ga,
                             initial_tilt=t.number("initial_tilt", "deg", 0.0) * DEG,
                             initial_angle=t.number("initial_angle", "deg", 0.0) * DEG,
                             initial_tilt_rate=t.number("initial_tilt_rate", "rev/s", 0.0) * TWO_PI,
                             initial_speed=t.number("initial_speed", "rev/s", 0.0) * TWO_PI)
    elif kind == "damper":
        t.allow(("type",) + _DAMPER_KEYS)
        m = t.number("mass", "kg", gt=0)
        l = t.number("arm", "m", gt=0)
        _fits(t, l)
        if "dimensionless" in t:
            s = _sugar(t, kind, m, l, rotor)
            A, H1, ga = s["A"], s["H1"], s["g_a"]
        else:
            A = _inertia(t, "inertia", l, m, m * l * l)
            H1 = t.number("drag", "N*m*s", 0.0, ge=0)
            ga = t.number("axial_gravity", "m/s^2", g_default, ge=0)
        tilt = t.number("initial_tilt", "deg", 0.0, ge=0)
        if tilt >= 180.0:
            raise SceneError(f"{t.name('initial_tilt')} = {_fmt(tilt)}: must be < 180 (deg from "
                             "the downward axis)")
        body = SphericalWeight(m, l, A, H1, ga, tilt * DEG,
                               t.number("initial_angle", "deg", 0.0) * DEG)
    elif kind == "liquid_float":
        t.allow(("type",) + _FLOAT_KEYS)
        m = t.number("liquid_mass", "kg", gt=0)
        r1 = t.number("chamber_radius", "m", gt=0)
        r2 = t.number("float_radius", "m", gt=0)
        if r2 >= r1:
            raise SceneError(f"{t.name('float_radius')} = {_fmt(r2)}: must be < chamber_radius = "
                             f"{_fmt(r1)} (m)")
        body = LiquidWeight(kind, m, r1, r2, height=t.number("chamber_height", "m", 0.0, ge=0))
    else:
        t.allow(("type",) + _CHAMBER_KEYS)
        R = t.number("chamber_radius", "m", gt=0)
        h = t.number("chamber_height", "m", gt=0)
        V = t.number("fill_volume", "m^3", gt=0)
        full = math.pi * R * R * h
        if V >= full:
            raise SceneError(f"{t.name('fill_volume')} = {_fmt(V)}: must be < the chamber's volume "
                             f"pi R^2 h = {full:.6g} (m^3; a full chamber has no free surface)")
        rho = t.number("density", "kg/m^3", 1000.0, gt=0)
        r = math.sqrt(R * R - V / (math.pi * h))
        body = LiquidWeight(kind, rho * V, R, r, height=h,
                            relaxation_time=t.number("relaxation_time", "s", 0.0, ge=0),
                            volume=V, density=rho,
                            viscosity=t.number("viscosity", "m^2/s", 1.0e-6, gt=0))
    return PlaneBody(plane, body)
