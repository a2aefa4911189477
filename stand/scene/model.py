"""The scene: one experiment on the virtual stand, in SI units.

These dataclasses are what the rest of the stand consumes.  They are built
from TOML files by :func:`stand.scene.parse.load_scene` (which validates every
field) or directly in code.  Units are SI everywhere here: kg, m, s, rad,
rad/s, N/m, N*s/m, N*m*s.  Conversions from rev/s and degrees happen once, in
the scene-file reader.

The map to the book's dimensionless parameters (Filimonikhin 2004, (5.12)-(5.15); digest ch5
section 2.2): :func:`stand.scene.dimensionless.dimensionless`, :func:`stand.scene.parse.scene_from_dimensionless`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional, Union

import numpy as np


#: integration methods accepted by ``run.method`` and :func:`stand.integrate.simulate.simulate`
METHODS = ("auto", "DOP853", "Radau", "BDF", "LSODA", "numpy-DOP853")
#: the scene-file language this reader writes and reads by default: 2 = every angle of a scene
#: file in degrees (a unit string may say otherwise).  Language 1 (recordings written before;
#: their root attribute ``scene_language`` is missing) gave the ``[structure]`` angles in rad.
SCENE_LANGUAGE = 2


from stand.errors import SceneError  # noqa: E402 (re-exported: the scene's error)


@dataclass(frozen=True)
class Rotor:
    """Rigid rotor (disk) carried by the shaft.

    Parameters
    ----------
    mass : float
        M, mass of all rotating parts except the correction weights [kg].
    eccentricity : float
        e, distance of the rotor's centre of mass from the shaft axis [m].
    unbalance_angle : float
        Angle of the heavy side from the rotor's reference mark (keyphasor) [rad].
    inertia : float or None
        J_C, moment of inertia about the rotor's own central axis [kg*m^2].
        Needed only when the speed is not prescribed (torque drive).
    """

    mass: float
    eccentricity: float = 0.0
    unbalance_angle: float = 0.0
    inertia: Optional[float] = None

    @property
    def unbalance(self) -> float:
        """Static unbalance M*e [kg*m]."""
        return self.mass * self.eccentricity

    @property
    def inertia_about_shaft(self) -> Optional[float]:
        """J_0 = J_C + M e^2 [kg*m^2] (book, after (5.9))."""
        if self.inertia is None:
            return None
        return self.inertia + self.mass * self.eccentricity ** 2


@dataclass(frozen=True)
class Supports:
    """Linear viscoelastic supports of the shaft point K, (5.1).

    X and Y are fixed axes; stiffness [N/m], damping [N*s/m].
    """

    stiffness_x: float
    stiffness_y: float
    damping_x: float = 0.0
    damping_y: float = 0.0


@dataclass(frozen=True)
class Balancer:
    """Correction weights (CWs) in one plane: balls or pendulums.

    Arrays have one entry per weight.

    Parameters
    ----------
    type : {"balls", "pendulums", "none"}
    mass : ndarray
        m_j [kg].
    radius : ndarray
        l_j [m]: track radius (balls, distance from the shaft axis to the
        ball centre) or pendulum length (pivot to centre of mass).
    drag : ndarray
        Viscous resistance to motion relative to the rotor.  Balls: force
        coefficient c_b [N*s/m] on the speed along the track; pendulums:
        moment coefficient H_j [N*m*s].
    inertia : ndarray
        J_j, moment of inertia about the shaft axis [kg*m^2].  Point balls:
        m_j l_j^2 (the book neglects ball spin, digest ch5 section 1).
    initial_angles : ndarray
        Initial angles relative to the rotor's reference mark [rad].
    initial_speeds : ndarray
        Initial speeds relative to the rotor [rad/s].
    rolling : bool
        Balls rolling without slip (``inertia`` = 7/5 m l^2, :attr:`spin_inertia`).
    ball_radius, contact_stiffness, contact_damping, race_eccentricity, race_eccentricity_angle
        Balls only (stand.model.rotors.weight_table): contact (off when ``ball_radius`` is
        0) r [m], k [N/m], c [N*s/m]; the race's centre off the shaft [m] at [rad]; its
        radius l [1 + eps cos k (a - theta_o)]: ``race_out_of_roundness`` eps [-], ``race_lobes``
        k, ``race_out_of_roundness_angle`` theta_o [rad].
    """

    type: str = "none"
    mass: np.ndarray = field(default_factory=lambda: np.zeros(0))
    radius: np.ndarray = field(default_factory=lambda: np.zeros(0))
    drag: np.ndarray = field(default_factory=lambda: np.zeros(0))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros(0))
    initial_angles: np.ndarray = field(default_factory=lambda: np.zeros(0))
    initial_speeds: np.ndarray = field(default_factory=lambda: np.zeros(0))
    rolling: bool = False
    ball_radius: float = 0.0
    contact_stiffness: float = 0.0
    contact_damping: float = 0.0
    race_eccentricity: float = 0.0
    race_eccentricity_angle: float = 0.0
    race_out_of_roundness: float = 0.0
    race_lobes: int = 2
    race_out_of_roundness_angle: float = 0.0

    @property
    def count(self) -> int:
        return int(np.size(self.mass))

    @property
    def capacity(self) -> float:
        """Balancing capacity S = sum m_j l_j [kg*m] (2.1)."""
        return float(np.sum(self.mass * self.radius))

    @property
    def moment_drag(self) -> np.ndarray:
        """H_j: moment coefficient about the shaft axis [N*m*s]; balls: H_j = c_b l_j^2 (digest
        ch5 section 1: the book's (5.9) mixes the force and moment conventions; the moment one)."""
        if self.type == "balls":
            return self.drag * self.radius ** 2
        return np.asarray(self.drag, dtype=float)

    @property
    def spin_inertia(self) -> np.ndarray:
        """J_s,j [kg*m^2]: the part of J_j that turns with the weight's angle relative to the
        rotor, J_j - m_j l_j^2 = 2/5 m_j l_j^2 for rolling balls, 0 otherwise (a pendulum's
        J is about the shaft, absolute; stand.model.weights)."""
        if not self.rolling:
            return np.zeros(self.count)
        return np.asarray(self.inertia, float) - self.mass * self.radius ** 2


@dataclass(frozen=True)
class SpeedDrive:
    """Prescribed rotor speed (drive model 4 of the book).

    Parameters
    ----------
    programme : ndarray, shape (k, 2)
        Piecewise-linear speed programme: columns time [s] and speed [rad/s].
        Before the first point the speed is the first value; after the last
        point it is held constant (unless a coast-down starts).
    coast_down_start : float or None
        Time [s] from which the speed decays exponentially,
        omega(t) = omega(t0) exp(-(t - t0)/T).
    coast_down_time_constant : float or None
        T [s] of the exponential coast-down.
    rotor_drag : float
        H_0 [N*m*s]; has no effect on the motion when the speed is prescribed.
    initial_angle : float
        The rotor's angle at t = 0 [rad] (0: the reference mark starts at the X axis); set
        when a simulation is driven by a recorded rotor angle (:mod:`stand.fitting`).
    """

    programme: np.ndarray
    coast_down_start: Optional[float] = None
    coast_down_time_constant: Optional[float] = None
    rotor_drag: float = 0.0
    kind: str = "speed"
    initial_angle: float = 0.0


@dataclass(frozen=True)
class TorqueDrive:
    """Drive torque on a free rotor, the book's models 1-3 (section 5.1.1).

    model "constant":        M_rot = torque
    model "speed_feedback":  M_rot = c1 (omega - phi')
    model "angle_feedback":  M_rot = c1 (omega - phi') + c2 (omega t - phi)

    Parameters
    ----------
    torque : float  [N*m]
    c1 : float      [N*m*s]
    c2 : float      [N*m] (per radian)
    target_speed : float
        omega [rad/s].
    rotor_drag : float
        H_0 [N*m*s], drag on the rotor's rotation.
    initial_speed : float
        Rotor speed at t = 0 [rad/s].
    """

    model: str = "constant"
    torque: float = 0.0
    c1: float = 0.0
    c2: float = 0.0
    target_speed: float = 0.0
    rotor_drag: float = 0.0
    initial_speed: float = 0.0
    kind: str = "torque"


@dataclass(frozen=True)
class RotorTorqueDrive(TorqueDrive):
    """A torque drive (:class:`TorqueDrive`, the book's models 1-3) on a ``[structure]``
    scene, with the rotor's polar moment of inertia about the shaft ``inertia`` [kg m^2]
    (the planar scenes take it from ``rotor.inertia``)."""

    inertia: float = None


Drive = Union[SpeedDrive, TorqueDrive]


@dataclass(frozen=True)
class RunSettings:
    """How to integrate.

    Parameters
    ----------
    duration : float
        Simulated time [s].
    sample_rate : float
        Output samples per second [Hz] (exact sampling via dense output).
    rtol, atol : float
        Tolerances applied to the dimensionless state (shaft displacement in
        units of the length scale r*, angles in rad, speeds in units of
        omega_1); see docs/scene.md.
    method : str
        "auto" (default), "DOP853" (compiled explicit), "Radau" or "BDF"
        (stiff, scipy with a compiled right-hand side), "numpy-DOP853"
        (pure-numpy reference path, slow).
    max_steps : int
        Step budget; the run stops with a clear message when exceeded.
    """

    duration: float
    sample_rate: float
    rtol: float = 1e-8
    atol: float = 1e-10
    method: str = "auto"
    max_steps: int = 10_000_000


@dataclass(frozen=True)
class UnbalanceChange:
    """Change of the rotor's unbalance (table 4.5): discrete (duration 0) or continuous.

    From ``start`` [s] the unbalance moves linearly, over ``duration`` [s], to
    ``eccentricity`` [m] at ``unbalance_angle`` [rad] (of the rotor mass M).
    The shaft equations include the e' terms of the moving centre of mass; for
    a free rotor the polar inertia J_0 is kept constant (a small correction mass).
    """

    start: float
    duration: float
    """The change starts at ``start`` and takes ``duration`` [s] (0: discrete)."""
    eccentricity: float
    unbalance_angle: float
    """The new eccentricity [m] and angle [rad] of the rotor's heavy side."""
    mass: Optional[float] = None
    kind: str = "unbalance"


@dataclass(frozen=True)
class Impulse:
    """A blow to the housing at ``start`` [s]: the shaft velocity jumps by
    (velocity_x, velocity_y) [m/s] (table 4.6)."""

    start: float
    velocity_x: float
    velocity_y: float
    kind: str = "impulse"


@dataclass(frozen=True)
class SideForce:
    """One-directional pressure on the shaft from ``start`` to ``end`` [s] (table 4.6):
    a constant force (force_x, force_y) [N] plus extra stiffness (stiffness_x,
    stiffness_y) [N/m] (e.g. a spring rail pressing on the housing)."""

    start: float
    end: float
    """The pressure acts for start <= t < end [s]."""
    force_x: float = 0.0
    force_y: float = 0.0
    """Constant force [N]."""
    stiffness_x: float = 0.0
    stiffness_y: float = 0.0
    """Extra stiffness [N/m]."""
    kind: str = "side_force"


@dataclass(frozen=True)
class InitialState:
    """Initial shaft state: displacement [m] and velocity [m/s]."""

    x: float = 0.0
    y: float = 0.0
    vx: float = 0.0
    vy: float = 0.0


@dataclass(frozen=True)
class PlaneWeights:
    """Correction weights in one named plane of the rotor (a :class:`Balancer`).

    Attributes
    ----------
    plane : str
        A plane of the rotor (:attr:`Scene.planes`).
    balancer : Balancer
        The weights (balls or pendulums), SI.
    friction : stand.model.balancers.friction.Friction or None
        Dry friction of the weights on their track (None: viscous drag only).
    """

    plane: str
    balancer: Balancer
    friction: Optional["Friction"] = None    # noqa: F821 (stand.model.balancers.friction)


@dataclass(frozen=True)
class RotorStructure:
    """Any rotor of the family as a generic linear structure (chapter 2, papers 003/004).

    Attributes
    ----------
    type : str
        Rotor type (a key of :data:`stand.scene.structure_tables.ROTOR_TYPES`), e.g. ``"two_mass"``.
    params : dict
        The builder's keyword arguments as the scene gave them (SI).
    rotor : stand.model.rotors.structure.LinearRotor
        M, G, D, K, plane maps, unbalances, gravity.
    source : str
        Book section the builder implements.
    """

    type: str
    params: dict
    rotor: object
    source: str = ""

    @property
    def planes(self) -> tuple:
        return tuple(self.rotor.planes)


@dataclass(frozen=True)
class BookModel:
    """A weight model of the books in its own dimensionless form (``[weight_model]`` scenes).

    The model brings its own rotor (ch. 6 two-axis pendulum, ch. 7.1 coupled pair,
    ch. 7.2 autobalancer-damper, paper 001 liquid float, thesis 002 liquid chamber;
    :mod:`stand.model.balancers`).  Until these weights are coupled to the generic
    structures they run through their own right-hand sides; the run still gives
    the common :class:`stand.integrate.result.Run` and recording.

    Attributes
    ----------
    type : str
        ``two_axis``, ``gravity_pair``, ``damper``, ``liquid_float`` or ``liquid_chamber``.
    params : object
        The module's parameter dataclass.
    source : str
        Book chapter / paper.
    options : dict
        The scene's ``[run]`` table as given (``duration``, ``samples``, ``initial``, ``rtol``).
    """

    type: str
    params: object
    source: str = ""
    options: dict = field(default_factory=dict)

    @property
    def planes(self) -> tuple:
        return ("balancer",)


#: smallest unbalance-based length scale [m] (below it the rotor counts as balanced)
MIN_LENGTH_SCALE = 1e-12


@dataclass(frozen=True)
class Scene:
    """One experiment: structure x weights x drive x perturbations x instruments x run settings.

    Every scene file form builds this one class (:func:`stand.load`):

    * the planar rotor of chapter 5 on its supports (``[rotor]``, ``[supports]``,
      ``[balancer]`` tables, the book's ``[dimensionless]`` form, or ``[structure] type =
      "planar"`` with ``[[weights]]``: :func:`stand.scene.parse.planar_structure`): ``rotor`` and
      ``supports`` are set, the weights are ``balancer`` in the plane
      ``"balancer"``; ``kind == "planar"``;
    * any rotor of the family (``[structure]`` + ``[[weights]]``): ``structure`` is a
      :class:`RotorStructure`, the weights are ``plane_weights`` in named planes;
      ``kind == "rotor"``;
    * a book weight model (``[weight_model]``): ``structure`` is a :class:`BookModel`;
      ``kind == "book"``.

    :attr:`weights` gives the weights in their planes for every kind,
    :meth:`linear_rotor` the generic structure (M, G, D, K, plane maps) where one exists.
    """

    rotor: Optional[Rotor] = None
    supports: Optional[Supports] = None
    balancer: Balancer = Balancer()
    drive: Optional["Drive"] = None
    run: Optional[RunSettings] = None
    initial: InitialState = InitialState()
    name: str = ""
    text: str = ""  #: the original TOML text, stored in recordings
    #: instrument name ("screen", "stroboscope", ...) -> settings; empty: nothing is rendered
    instruments: dict = field(default_factory=dict)
    #: UnbalanceChange / Impulse / SideForce events (tables 4.5-4.6)
    perturbations: tuple = ()
    description: str = ""
    #: None for the planar rotor; a RotorStructure or a BookModel otherwise
    structure: Union[RotorStructure, BookModel, None] = None
    #: weights in named planes of ``structure`` (:class:`PlaneWeights`)
    plane_weights: tuple = ()
    #: dry friction of the planar rotor's ``[balancer]`` weights
    #: (:class:`stand.model.balancers.friction.Friction`; None: viscous drag only)
    friction: Optional["Friction"] = None    # noqa: F821 (stand.model.balancers.friction)
    #: the scene-file language ``text`` was read in (:data:`SCENE_LANGUAGE`)
    language: int = SCENE_LANGUAGE

    def __post_init__(self):
        if self.structure is None and (self.rotor is None or self.supports is None):
            raise SceneError("a scene needs a structure: [rotor] and [supports] (planar), "
                             "[structure] (rotor family) or [weight_model]")

    @property
    def kind(self) -> str:
        """``"planar"``, ``"rotor"`` (family structure) or ``"book"`` (book weight model)."""
        if self.structure is None:
            return "planar"
        return "rotor" if isinstance(self.structure, RotorStructure) else "book"

    @property
    def structure_type(self) -> str:
        """Name of the structure: ``"planar"`` for the chapter-5 rotor, the family's rotor
        type (``"two_mass"``, ...) or ``"book:<model>"``."""
        if self.structure is None:
            return "planar"
        if isinstance(self.structure, RotorStructure):
            return self.structure.type
        return f"book:{self.structure.type}"

    @property
    def planes(self) -> tuple:
        """Names of the planes where weights, unbalances and instruments may sit."""
        return ("balancer",) if self.structure is None else self.structure.planes

    @property
    def weights(self) -> tuple:
        """The correction weights in their planes: a tuple of
        :class:`PlaneWeights` (empty without weights)."""
        if self.structure is None:
            if not self.balancer.count:
                return ()
            return (PlaneWeights("balancer", self.balancer, self.friction),)
        return tuple(w for w in self.plane_weights if hasattr(w, "balancer"))

    @property
    def generic_kernel(self) -> str:
        """Why the scene runs on the generic kernel (:mod:`stand.model.rotors.coupled_kernel`),
        ``""`` when it does not: every ``[structure]`` rotor; a planar scene with what its own
        kernel (:mod:`stand.model.planar`) does not have -- body weights, dry friction of the
        ``[balancer]`` weights.  A book weight model runs its own right-hand side (``""``)."""
        if self.kind == "rotor":
            return f"rotor type {self.structure_type}"
        if self.kind != "planar":
            return ""
        why = []
        if self.bodies:
            why.append("body weights (" + ", ".join(dict.fromkeys(b.kind for b in self.bodies))
                       + ")")
        if self.friction is not None:
            why.append("dry friction of the balancer's weights")
        why += [what for key, what in (("ball_radius", "ball-ball contact"), ("race_eccentricity",
                "race eccentricity"), ("race_out_of_roundness", "race out-of-roundness"))
                if getattr(self.balancer, key) > 0]
        return " and ".join(why)

    @property
    def bodies(self) -> tuple:
        """The body weights (two-axis pendulums, coupled pairs, dampers, liquids) in their
        planes: a tuple of :class:`stand.model.rotors.bodies.PlaneBody` (empty without)."""
        return tuple(w for w in self.plane_weights if not hasattr(w, "balancer"))

    def weights_capacity(self, plane: Optional[str] = None) -> float:
        """Capacity S [kg m] of ``plane``'s weights (None: all): balls' sum m l (2.1) + bodies'."""
        return float(sum(w.balancer.capacity for w in self.weights if plane in (None, w.plane))
                     + sum(b.body.capacity for b in self.bodies if plane in (None, b.plane)))

    @property
    def n_weights(self) -> int:
        return int(sum(w.balancer.count for w in self.weights))

    @property
    def main_plane(self) -> str:
        """The plane recorded as ``shaft/x|y``: the first plane with weights, else
        ``"balancer"`` when the structure has one, else its first plane."""
        for w in self.weights + self.bodies:
            return w.plane
        planes = self.planes
        return "balancer" if "balancer" in planes else planes[0]

    def linear_rotor(self):
        """The generic structure (:class:`stand.model.rotors.structure.LinearRotor`): M, G, D, K,
        plane maps, unbalances; None for a book weight model.

        For the planar rotor this is model 2.5.1 (:func:`stand.model.rotors.planar_supports.planar_rotor`)
        with the rotor's mass, the supports and the unbalance M e; the weights are not
        included (they are coupled by :mod:`stand.integrate.coupled`).
        """
        if isinstance(self.structure, RotorStructure):
            return self.structure.rotor
        if self.structure is not None:
            return None
        from stand.model.rotors.planar_supports import planar_rotor

        r, s = self.rotor, self.supports
        return planar_rotor(r.mass, s.stiffness_x, s.stiffness_y, s.damping_x, s.damping_y,
                            unbalance=r.unbalance, unbalance_angle=r.unbalance_angle)

    @property
    def operating_speed(self) -> float:
        """The speed the run ends at or aims for [rad/s]: the speed programme's last speed, or
        a torque drive's target speed (its initial speed without a target)."""
        d = self.drive
        if d is None:
            return 0.0
        if d.kind == "speed":
            return float(d.programme[-1, 1])
        return float(d.target_speed or d.initial_speed)

    @property
    def top_speed(self) -> float:
        """The largest speed of the drive [rad/s] (programme maximum; a torque drive's
        larger of target and initial speed)."""
        d = self.drive
        if d is None:
            return 0.0
        if d.kind == "speed":
            return float(np.max(np.abs(d.programme[:, 1])))
        return float(max(abs(d.target_speed), abs(d.initial_speed)))

    @property
    def total_mass(self) -> float:
        """M_Sigma = M + sum m_j [kg] (planar rotor; body weights included)."""
        return (self._planar("total_mass").mass + float(np.sum(self.balancer.mass))
                + sum(b.mass for b in self.bodies))

    @property
    def natural_frequency(self) -> float:
        """omega_1 = sqrt(c_x / M_Sigma) [rad/s], (5.12) (planar rotor)."""
        return float(np.sqrt(self._planar("natural_frequency", "supports").stiffness_x
                             / self.total_mass))

    def _planar(self, what: str, part: str = "rotor"):
        v = getattr(self, part)
        if v is None:
            raise SceneError(f"{what}: defined for the planar rotor of chapter 5; this scene's "
                             f"structure is {self.structure_type}")
        return v

    @property
    def length_scale(self) -> float:
        """L [m] used to make displacements dimensionless.

        r* = S / M_Sigma (5.13) when there are weights; otherwise the rotor's
        static unbalance M e / M_Sigma when it is at least :data:`MIN_LENGTH_SCALE`
        (a picometre: smaller is no unbalance, and would put ordinary initial
        displacements out of floating-point range); otherwise 1 mm.
        """
        S = self.balancer.capacity
        if S > 0:
            return S / self.total_mass
        if self.rotor.unbalance / self.total_mass >= MIN_LENGTH_SCALE:
            return self.rotor.unbalance / self.total_mass
        return 1e-3

