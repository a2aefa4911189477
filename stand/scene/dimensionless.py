"""The book's dimensionless parameters of the planar rotor, both ways.

:func:`dimensionless` maps a planar scene to the parameters of chapter 5
(Filimonikhin 2004, (5.12)-(5.15), (5.19)-(5.20), (5.88); shared physics digest
ch5 section 2.2); :func:`scene_from_dimensionless` builds a ball-balancer scene
from them (the ``[dimensionless]`` form of a scene file).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from stand.io.validate import _Table
from stand.scene.limits import MAX_WEIGHTS
from stand.scene.model import Balancer, InitialState, Rotor, Scene, SceneError, Supports, TorqueDrive

__all__ = ["Dimensionless", "dimensionless", "scene_from_dimensionless"]

TWO_PI = 2.0 * math.pi
DIMENSIONLESS_KEYS = ("n", "Rt", "h", "H", "e0", "R_omega2", "unbalance_angle",
                      "initial_angles", "natural_frequency", "total_mass",
                      "track_radius", "rotor_inertia")


def _dimensionless_params(t: _Table, angle_unit: str) -> dict:
    """Validated [dimensionless] values (angles still in ``angle_unit``)."""
    t.allow(DIMENSIONLESS_KEYS)
    n = t.integer("n", minimum=1, maximum=MAX_WEIGHTS)  # like balancer.count (memory)
    return dict(
        n=n,
        Rt=t.number("Rt", "dimensionless, R~_m, 0 < Rt < 0.5", gt=0, lt=0.5),
        h=t.number("h", "dimensionless", ge=0),
        H=t.number("H", "dimensionless", ge=0),
        e0=t.number("e0", "dimensionless", ge=0),
        R_omega2=t.number("R_omega2", "dimensionless", 1.0, gt=0),
        unbalance_angle=t.number("unbalance_angle", angle_unit, 0.0),
        initial_angles=t.per_weight("initial_angles", n, t.name("n"), angle_unit, None,
                                    scalar=False),
        natural_frequency=t.number("natural_frequency", "Hz", 1.0 / TWO_PI, gt=0),
        total_mass=t.number("total_mass", "kg", 1.0, gt=0),
        track_radius=t.number("track_radius", "m", 1.0, gt=0),
        rotor_inertia=t.number("rotor_inertia", "kg*m^2", None, gt=0),
    )


@dataclass(frozen=True)
class Dimensionless:
    """The book's dimensionless parameters (5.14), (5.19)-(5.20).

    Attributes
    ----------
    n : int
    R_m : float        sum m_j / M_Sigma
    Rt : float         R~_m = (1/(2 M_Sigma)) sum m_j^2 l_j^2 / J_j  (5.88)
    e0 : float         M e / S (unbalance in units of the capacity); nan if S = 0
    e : ndarray        e_j = m_j l_j / S
    j : ndarray        j_j = m_j l_j l* / J_j
    h : ndarray        h_j = H_j / (omega_1 J_j)
    H_x, H_y : float   support damping / (omega_1 M_Sigma)  (= 2 zeta)
    R_omega2 : float   sqrt(c_y / c_x)
    h0 : float or nan  H_0 / (J_0 omega_1)
    j0 : float or nan  M e l* / J_0
    omega_1 : float    [rad/s]
    r_star : float     S / M_Sigma [m]
    l_star : float     sum m_j l_j / sum m_j [m]
    """

    n: int
    R_m: float
    Rt: float
    e0: float
    e: np.ndarray
    j: np.ndarray
    h: np.ndarray
    H_x: float
    H_y: float
    R_omega2: float
    h0: float
    j0: float
    omega_1: float
    r_star: float
    l_star: float

    @property
    def H(self) -> float:
        """Isotropic support damping H (= H_x)."""
        return self.H_x


def dimensionless(scene: Scene) -> Dimensionless:
    """Map a scene to the book's dimensionless parameters, (5.12)-(5.14), (5.88).

    Inverse: :func:`stand.scene.parse.scene_from_dimensionless`.
    """
    b, r, s = scene.balancer, scene.rotor, scene.supports
    Ms = scene.total_mass
    w1 = scene.natural_frequency
    S = b.capacity
    n = b.count
    m, l, J = (np.asarray(a, dtype=float) for a in (b.mass, b.radius, b.inertia))
    msum = float(np.sum(m))
    l_star = S / msum if msum > 0 else float("nan")
    r_star = S / Ms if S > 0 else float("nan")
    if n:
        e = m * l / S
        j = m * l * l_star / J
        h = b.moment_drag / (w1 * J)
        Rt = float(np.sum(m ** 2 * l ** 2 / J)) / (2.0 * Ms)
    else:
        e = j = h = np.zeros(0)
        Rt = 0.0
    J0 = r.inertia_about_shaft
    drag0 = getattr(scene.drive, "rotor_drag", 0.0)
    return Dimensionless(
        n=n,
        R_m=msum / Ms,
        Rt=Rt,
        e0=r.unbalance / S if S > 0 else float("nan"),
        e=e,
        j=j,
        h=h,
        H_x=s.damping_x / (w1 * Ms),
        H_y=s.damping_y / (w1 * Ms),
        R_omega2=float(np.sqrt(s.stiffness_y / s.stiffness_x)),
        h0=drag0 / (J0 * w1) if J0 else float("nan"),
        j0=r.unbalance * l_star / J0 if (J0 and n) else float("nan"),
        omega_1=w1,
        r_star=r_star,
        l_star=l_star,
    )


def scene_from_dimensionless(n, Rt, h, H, e0, *, drive, run, R_omega2=1.0,
                             unbalance_angle=0.0, natural_frequency=1.0 / TWO_PI,
                             total_mass=1.0, track_radius=1.0, initial_angles=None,
                             initial=None, rotor_inertia=None, name="") -> Scene:
    """Build a ball-balancer scene from the book's dimensionless parameters.

    Identical point balls (j = 1) on one track, supports with equal damping;
    the inverse of :func:`stand.scene.dimensionless.dimensionless` (5.12)-(5.14), (5.19)-(5.20).

    Parameters
    ----------
    n : int
        Number of balls.
    Rt : float
        R~_m = n m / (2 M_Sigma), 0 < Rt < 0.5.
    h : float
        Ball drag h = H_j / (omega_1 J_j) = c_b / (omega_1 m).
    H : float
        Support damping H = H_x / (omega_1 M_Sigma) (= 2 zeta); H_y = H_x.
    e0 : float
        Rotor unbalance in units of the capacity, M e / (n m l).
    drive : SpeedDrive or TorqueDrive
        In SI units.
    run : RunSettings
    R_omega2 : float
        sqrt(c_y / c_x).
    unbalance_angle : float
        Heavy side from the reference mark [rad].
    natural_frequency : float
        omega_1 / (2 pi) [Hz]; the default makes tau = t in seconds.
    total_mass : float
        M_Sigma [kg].
    track_radius : float
        l [m].
    initial_angles : array_like or None
        Ball angles from the reference mark [rad]; default evenly spaced.
    initial : InitialState or None
    rotor_inertia : float or None
        J_C [kg*m^2]; required with a torque drive.
    name : str

    Returns
    -------
    Scene

    Raises
    ------
    SceneError
        A parameter is out of range, or a torque drive lacks rotor_inertia.
    """
    raw = dict(n=n, Rt=Rt, h=h, H=H, e0=e0, R_omega2=R_omega2,
               unbalance_angle=unbalance_angle, natural_frequency=natural_frequency,
               total_mass=total_mass, track_radius=track_radius,
               initial_angles=None if initial_angles is None else list(initial_angles),
               rotor_inertia=rotor_inertia)
    p = _dimensionless_params(_Table({k: v for k, v in raw.items() if v is not None},
                                     "dimensionless"), "rad")
    if isinstance(drive, TorqueDrive) and p["rotor_inertia"] is None:
        raise SceneError("dimensionless.rotor_inertia: missing; required with a torque "
                         "drive (kg*m^2, rotor inertia about its own centre of mass)")
    n, Ms, l = p["n"], p["total_mass"], p["track_radius"]
    w1 = TWO_PI * p["natural_frequency"]
    m = 2.0 * p["Rt"] * Ms / n            # R_m = 2 Rt (j = 1)
    M = Ms - n * m
    c_x = Ms * w1 * w1  # float ** raises OverflowError; * gives inf (check_derived reports it)
    damping = p["H"] * w1 * Ms
    angles = p["initial_angles"]
    if angles is None:
        angles = TWO_PI * np.arange(n) / n
    return Scene(
        rotor=Rotor(mass=M, eccentricity=p["e0"] * n * m * l / M,
                    unbalance_angle=p["unbalance_angle"], inertia=p["rotor_inertia"]),
        supports=Supports(stiffness_x=c_x, stiffness_y=p["R_omega2"] * p["R_omega2"] * c_x,
                          damping_x=damping, damping_y=damping),
        balancer=Balancer(type="balls", mass=np.full(n, m), radius=np.full(n, l),
                          drag=np.full(n, p["h"] * w1 * m), inertia=np.full(n, m * l * l),
                          initial_angles=np.asarray(angles, float), initial_speeds=np.zeros(n)),
        drive=drive,
        run=run,
        initial=initial if initial is not None else InitialState(),
        name=name,
    )
