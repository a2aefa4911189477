"""Body weights in SI: two-axis pendulum, coupled pair, autobalancer-damper, liquid balancers.

A *body weight* is a correction device with its own orientation or shape,
hung at the point of a rotor plane (the balls and pendulums of chapter 5 are
the point weights of :mod:`stand.model.rotors.coupled_kernel`).  This module holds
the SI parameter classes, their packing for the compiled equations
(:mod:`stand.model.rotors.bodies_kernel`, where the equations are written once, in
the fixed frame) and the SI channels of a run (coordinates and the body's
unbalance in the rotor frame).

=====================  ==============================  ============================
weight kind            class                           source
=====================  ==============================  ============================
``two_axis_pendulum``  :class:`TiltingWeight`          monograph ch. 6, (6.15)
``coupled_pair``       :class:`TiltingWeight` (g_a=0)  monograph ch. 7.1, (7.34)
``damper``             :class:`SphericalWeight`        monograph ch. 7.2, (7.47)
``liquid_float``       :class:`LiquidWeight`           paper 001, model M1, (3)-(4)
``liquid_chamber``     :class:`LiquidWeight`           thesis 002, l.668, (2.10)-(2.13)
=====================  ==============================  ============================

The liquid chamber is a dynamic model: the liquid's free surface is a circle
(radius ``r = sqrt(R^2 - V/(pi h))``, the cylindrical fill of the thesis,
l.1787) whose centre relaxes to the bearing axis with the time constant
``relaxation_time`` in the liquid's rotating frame (0: at once -- the
quasi-static assumption of the thesis, section 2.2); the liquid's centre of
mass is then at ``kappa = r^2/(R^2 - r^2)`` times the offset (l.668).  Its
steady state puts the liquid's centre of mass in the direction of the
deflection, the equilibrium condition (2.10b) of the thesis, so the steady
angle solves (2.12); which root of l.814 the rotor reaches is decided by the
dynamics (digest thesis_002 section 2.5, "branch ambiguity"): the corrected
(2.13) above the critical speed of the liquid-loaded rotor, the other root
(the liquid near the unbalance, l.806) below it.  Tested in
``tests/test_body_weights.py``.  The model holds while the free surface stays
inside the chamber (sufficiency condition (3.4), ``|Z| <= R - r``); beyond
it the run's notes say so.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from stand.model.rotors import bodies_kernel as bk

__all__ = ["TiltingWeight", "SphericalWeight", "LiquidWeight", "PlaneBody", "BODY_KINDS",
           "body_rows", "body_initial", "body_channels", "body_names", "liquid_notes"]

G_STANDARD = 9.80665

#: weight kind -> short name of its bodies in a run (``two_axis1``, ...)
BODY_KINDS = {"two_axis_pendulum": "two_axis", "coupled_pair": "coupled_pair",
              "damper": "damper", "liquid_float": "liquid", "liquid_chamber": "liquid"}


@dataclass(frozen=True)
class TiltingWeight:
    """A weight on a two-axis hinge (ch. 6 two-axis pendulum; ch. 7.1 coupled pair).

    Parameters
    ----------
    kind : {"two_axis_pendulum", "coupled_pair"}
    mass : float
        m [kg] (the pair's total for a coupled pair).
    arm : float
        l [m], hinge to centre of mass.
    inertia_tilt : float
        A [kg m^2], about the tilt axis through the hinge (>= m l^2).
    inertia_axial : float
        B [kg m^2], about the shaft axis through the hinge.
    tilt_drag, turn_drag : float
        H1, H2 [N m s]: viscous moments on the tilt rate and on the turn rate
        relative to the rotor.
    axial_gravity : float
        g_a [m/s^2] acting on the tilt (centre of mass below the hinge); 0 for
        the coupled pair (gravity does no work) and on a horizontal shaft.
    initial_tilt, initial_angle : float
        phi(0) [rad] and the azimuth relative to the rotor's mark [rad].
    initial_tilt_rate, initial_speed : float
        phi'(0) and the turn rate relative to the rotor [rad/s].
    """

    kind: str
    mass: float
    arm: float
    inertia_tilt: float
    inertia_axial: float
    tilt_drag: float = 0.0
    turn_drag: float = 0.0
    axial_gravity: float = 0.0
    initial_tilt: float = 0.0
    initial_angle: float = 0.0
    initial_tilt_rate: float = 0.0
    initial_speed: float = 0.0

    @property
    def capacity(self) -> float:
        """Balancing capacity S = m l [kg m] (the largest unbalance it can carry)."""
        return self.mass * self.arm


@dataclass(frozen=True)
class SphericalWeight:
    """The autobalancer-damper's weight (ch. 7.2): free rotation about a point on the axis.

    Parameters
    ----------
    mass, arm : float
        m [kg], l [m] (point to centre of mass).
    inertia : float
        A [kg m^2], spherical about the point (>= m l^2).
    drag : float
        H1 [N m s] on the angular velocity relative to the rotor.
    axial_gravity : float
        g_a [m/s^2] along the axis (centre of mass below the point at rest).
    initial_tilt, initial_angle : float
        Angle of the centre of mass from the downward axis [rad] and its azimuth
        relative to the rotor's mark [rad]; it starts turning with the rotor.
    constraint_gain : float
        k_c [-] of the book's constraint stabilisation (per unit of the scaled time).
    """

    mass: float
    arm: float
    inertia: float
    drag: float = 0.0
    axial_gravity: float = 0.0
    initial_tilt: float = 0.0
    initial_angle: float = 0.0
    constraint_gain: float = 1.0
    kind: str = "damper"

    @property
    def capacity(self) -> float:
        return self.mass * self.arm


@dataclass(frozen=True)
class LiquidWeight:
    """Liquid in a chamber around the shaft (paper 001 float balancer; thesis 002 chamber).

    Parameters
    ----------
    kind : {"liquid_float", "liquid_chamber"}
    mass : float
        Liquid mass [kg].
    chamber_radius : float
        Chamber radius [m] (r1 of paper 001, R of thesis 002).
    surface_radius : float
        Radius of the free surface [m]: the float's radius r2 (paper 001) or
        ``sqrt(R^2 - V/(pi h))`` (thesis 002).
    height : float
        Chamber height [m] (drawing and the theory; 0 when not given).
    relaxation_time : float
        Time constant [s] of the free surface (0: at once; chamber only).
    volume, density : float
        Fill volume [m^3] and density [kg/m^3] as given (chamber).
    """

    kind: str
    mass: float
    chamber_radius: float
    surface_radius: float
    height: float = 0.0
    relaxation_time: float = 0.0
    volume: float = 0.0
    density: float = 1000.0
    viscosity: float = 1.0e-6

    @property
    def kappa(self) -> float:
        """r^2/(R^2 - r^2) [-]: liquid centre-of-mass offset per unit free-surface offset (l.668)."""
        r2, R2 = self.surface_radius ** 2, self.chamber_radius ** 2
        return r2 / (R2 - r2)

    @property
    def lever(self) -> float:
        """lambda = R^2/(R^2 - r^2) [-]: the liquid's centre of mass from the axis per unit
        shaft offset (paper 001 (3))."""
        return 1.0 + self.kappa

    @property
    def gap(self) -> float:
        """R - r [m]: the largest offset with the free surface inside the chamber (3.4)."""
        return self.chamber_radius - self.surface_radius

    @property
    def capacity(self) -> float:
        """Largest liquid unbalance in the annulus regime, m kappa (R - r) [kg m]."""
        return self.mass * self.kappa * self.gap


Body = (TiltingWeight, SphericalWeight, LiquidWeight)


@dataclass(frozen=True)
class PlaneBody:
    """A body weight in a named plane of the rotor."""

    plane: str
    body: object

    @property
    def kind(self) -> str:
        return self.body.kind

    @property
    def mass(self) -> float:
        return float(self.body.mass)


def body_names(bodies: Sequence[PlaneBody], start: Optional[dict] = None) -> tuple:
    """``(names, planes)``: ``two_axis1``, ``damper1``, ``liquid1``, ... numbered per kind."""
    counter = dict(start or {})
    names, planes = [], []
    for pb in bodies:
        k = BODY_KINDS[pb.kind]
        counter[k] = counter.get(k, 0) + 1
        names.append(f"{k}{counter[k]}")
        planes.append(pb.plane)
    return tuple(names), tuple(planes)


def _kind_code(pb: PlaneBody) -> int:
    b = pb.body
    if isinstance(b, TiltingWeight):
        return bk.TILT
    if isinstance(b, SphericalWeight):
        return bk.SPHERE
    return bk.LAG if b.relaxation_time > 0 else bk.LEVER


def body_rows(bodies: Sequence[PlaneBody], plane_names: Sequence[str], first_state: int,
              length: float) -> tuple:
    """The packed table (nb, N_BCOL) and the number of body states.

    ``first_state``: index in the state vector of the first body state; ``length``:
    the length scale [m] of the ``LAG`` offsets.
    """
    rows = []
    off = first_state
    for pb in bodies:
        b = pb.body
        row = np.zeros(bk.N_BCOL)
        code = _kind_code(pb)
        row[bk.B_KIND] = code
        row[bk.B_PLANE] = list(plane_names).index(pb.plane)
        row[bk.B_OFF] = off
        row[bk.B_M] = b.mass
        row[bk.B_KC] = 1.0
        row[bk.B_LS] = length
        if code == bk.TILT:
            row[bk.B_L], row[bk.B_A], row[bk.B_B] = b.arm, b.inertia_tilt, b.inertia_axial
            row[bk.B_H1], row[bk.B_H2], row[bk.B_GA] = b.tilt_drag, b.turn_drag, b.axial_gravity
        elif code == bk.SPHERE:
            row[bk.B_L], row[bk.B_A], row[bk.B_H1] = b.arm, b.inertia, b.drag
            row[bk.B_GA], row[bk.B_KC] = b.axial_gravity, b.constraint_gain
        elif code == bk.LEVER:
            row[bk.B_LAM] = b.lever
        else:
            row[bk.B_LAM], row[bk.B_TAU] = b.kappa, b.relaxation_time
        rows.append(row)
        off += bk.N_STATES[code]
    table = np.array(rows, dtype=float).reshape(-1, bk.N_BCOL)
    return table, off - first_state


def body_initial(table: np.ndarray, bodies: Sequence[PlaneBody], y: np.ndarray, omega_ref: float,
                 omega0: float, q0_planes: dict) -> None:
    """Write the bodies' initial states into the scaled state ``y``.

    ``omega0``: rotor speed at t = 0 [rad/s]; ``q0_planes``: plane -> (2,) initial
    displacement [m] (the ``LAG`` free surface starts at the axis).
    """
    for row, pb in zip(table, bodies):
        o, code, b = int(row[bk.B_OFF]), int(row[bk.B_KIND]), pb.body
        if code == bk.TILT:
            y[o] = b.initial_tilt
            y[o + 1] = b.initial_angle
            y[o + 2] = b.initial_tilt_rate / omega_ref
            y[o + 3] = (omega0 + b.initial_speed) / omega_ref
        elif code == bk.SPHERE:
            th, az = b.initial_tilt, b.initial_angle
            y[o:o + 3] = [math.sin(th) * math.cos(az), math.sin(th) * math.sin(az), -math.cos(th)]
            y[o + 5] = omega0 / omega_ref
        elif code == bk.LAG:
            z = np.asarray(q0_planes.get(pb.plane, (0.0, 0.0)), float)
            y[o:o + 2] = -z / row[bk.B_LS]


def body_channels(table: np.ndarray, bodies: Sequence[PlaneBody], out: np.ndarray,
                  omega_ref: float, rotor_angle: np.ndarray, planes: dict) -> tuple:
    """SI channels of each body and its unbalance in the rotor frame.

    Returns ``(coords, unbalance)``: ``coords[i]`` a dict coordinate -> array
    (``angle``/``speed`` absolute azimuth [rad, rad/s] where the body has one,
    ``tilt`` [rad], ``n_x, n_y, n_z`` [-], ``liquid_x, liquid_y`` [m]: the liquid's
    centre of mass from the chamber centre, fixed frame); ``unbalance[i]`` (N, 2)
    [kg m] in the rotor frame (mass times the centre-of-mass offset from the plane point).
    """
    coords, unb = [], []
    c, s = np.cos(rotor_angle), np.sin(rotor_angle)
    for row, pb in zip(table, bodies):
        o, code, b = int(row[bk.B_OFF]), int(row[bk.B_KIND]), pb.body
        if code == bk.TILT:
            ph, al = out[:, o], out[:, o + 1]
            d = b.arm * np.sin(ph)[:, None] * np.column_stack([-np.sin(al), np.cos(al)])
            ch = {"angle": al, "speed": out[:, o + 3] * omega_ref, "tilt": ph,
                  "tilt_rate": out[:, o + 2] * omega_ref}
        elif code == bk.SPHERE:
            n = out[:, o:o + 3]
            n = n / np.linalg.norm(n, axis=1)[:, None]
            d = b.arm * n[:, :2]
            W = out[:, o + 3:o + 6] * omega_ref
            ch = {"angle": np.unwrap(np.arctan2(n[:, 1], n[:, 0])) if len(n) else n[:, 0],
                  "speed": W[:, 2], "tilt": np.arccos(np.clip(-n[:, 2], -1.0, 1.0)),
                  "n_x": n[:, 0], "n_y": n[:, 1], "n_z": n[:, 2]}
        elif code == bk.LEVER:
            d = (row[bk.B_LAM] - 1.0) * planes[pb.plane]
            ch = {"liquid_x": d[:, 0], "liquid_y": d[:, 1]}
        else:
            sig = out[:, o:o + 2] * row[bk.B_LS]
            d = -row[bk.B_LAM] * sig
            ch = {"liquid_x": d[:, 0], "liquid_y": d[:, 1], "surface_x": sig[:, 0],
                  "surface_y": sig[:, 1]}
        coords.append(ch)
        mdx, mdy = b.mass * d[:, 0], b.mass * d[:, 1]
        unb.append(np.column_stack([c * mdx + s * mdy, -s * mdx + c * mdy]))
    return coords, unb


def liquid_notes(bodies: Sequence[PlaneBody], planes: dict) -> tuple:
    """Notes for liquids whose free surface left the chamber (sufficiency condition (3.4))."""
    notes = []
    for pb in bodies:
        b = pb.body
        if isinstance(b, LiquidWeight) and b.kind == "liquid_chamber" and len(planes[pb.plane]):
            f = float(np.max(np.hypot(*planes[pb.plane].T)))
            if f > b.gap:
                notes.append(f"liquid chamber in plane {pb.plane!r}: the shaft offset reached "
                             f"{f:.3g} m > R - r = {b.gap:.3g} m: the free surface touched the wall "
                             "(sufficiency condition (3.4) of thesis 002); the annulus model "
                             "is outside its validity there")
    return tuple(notes)
