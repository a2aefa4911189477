"""One run result for every scene: :class:`Run` (and the solver's :class:`SolverStats`).

Whatever the structure (planar rotor, any rotor of the family, a book weight
model) and the weights, :func:`stand.run` returns a :class:`Run`: the sample
times, every plane's fixed-frame translation, the rotor's angle and speed,
each weight's coordinates by name, the solver statistics shaped like SciPy's
``OdeResult`` (``status``, ``message``, ``success``, ``nfev``, ``njev``,
``nlu``), and the scene.  A run is a result (:class:`stand.io.result.Result`,
docs/results.md): :meth:`Run.to_frame` gives a pandas DataFrame with SI columns (units in
the names), ``to_dict()`` its summary.  ``stand.save(run, path)`` writes the one HDF5
recording (:mod:`stand.recording.write`), which :func:`stand.read` turns back into a
:class:`stand.recording.read.Recording` with the same fields.

Weights are named ``<kind><j>`` (``ball1``, ``pendulum2``; numbered across the
whole scene) with their plane in :attr:`Run.weight_planes`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Optional

import numpy as np

from stand.io.result import Result

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

__all__ = ["Run", "SolverStats", "weight_names", "column_unit", "whirl_about_centre"]

#: units of the weights' standard coordinates
WEIGHT_UNITS = {"angle": "rad", "speed": "rad/s", "relative_angle": "rad", "tilt": "rad",
                "tilt_rate": "rad/s", "n_x": "1", "n_y": "1", "n_z": "1", "liquid_x": "m",
                "liquid_y": "m", "surface_x": "m", "surface_y": "m"}


class SolverStats(Result):
    """Solver statistics shaped like SciPy's ``OdeResult``: a :class:`stand.io.result.Result`
    (a dict whose keys are also attributes, ``to_dict()``, ``to_frame()``, ``plot(ax=)``).

    Attributes
    ----------
    method : str
        Integration method (``"DOP853"``, ``"Radau"``, ...).
    rtol, atol : float
        Tolerances on the integrated (scaled) state.
    n_steps, n_rejected : int
        Accepted and rejected steps.
    nfev, njev, nlu : int
        Right-hand-side and Jacobian evaluations, LU decompositions (as SciPy's).
    wall_time : float
        Integration time [s] (compilation excluded).
    status : int
        0: reached the end; -1 step-size collapse or solver failure; -2 non-finite or
        diverged state; -3 step budget.
    message : str
    success : bool
    stiffness_ratio : float
        Fastest decay rate / fastest frequency of the model (auto picks Radau above 30).
    method_reason : str
        Why the method was chosen.
    """

    _title = "solver statistics"
    _summary_keys = ("method", "status", "message", "n_steps", "nfev", "wall_time")

    FIELDS = dict(method="", rtol=float("nan"), atol=float("nan"), n_steps=0, n_rejected=0,
                  nfev=0, njev=0, nlu=0, wall_time=0.0, status=0, message="", success=True,
                  stiffness_ratio=0.0, method_reason="")

    def __init__(self, method: str = "", rtol: float = float("nan"), atol: float = float("nan"),
                 **fields):
        unknown = sorted(set(fields) - set(self.FIELDS))
        if unknown:
            raise TypeError(f"SolverStats: unknown field(s) {', '.join(unknown)}; valid: "
                            f"{', '.join(self.FIELDS)}")
        super().__init__({**self.FIELDS, "method": method, "rtol": rtol, "atol": atol, **fields})


def column_unit(units: str) -> str:
    """Units as the end of a table column's name: ``"rad/s"`` -> ``"rad_s"``, ``"kg*m"`` ->
    ``"kgm"``, ``""`` -> ``"1"`` (:meth:`Run.to_frame`, the instruments' tables)."""
    return units.replace("/", "_").replace("*", "").replace(" ", "").replace("^", "") or "1"


def weight_names(weights) -> tuple:
    """``(names, planes)`` of the weights of a scene's ``weights`` (PlaneWeights), numbered
    across the scene: ``ball1, ball2, ...`` / ``pendulum1, ...``."""
    names, planes = [], []
    counter: dict = {}
    for w in weights:
        kind = {"balls": "ball", "pendulums": "pendulum"}.get(w.balancer.type, "weight")
        for _ in range(w.balancer.count):
            counter[kind] = counter.get(kind, 0) + 1
            names.append(f"{kind}{counter[kind]}")
            planes.append(w.plane)
    return tuple(names), tuple(planes)


@dataclass(eq=False, repr=False)
class Run(Result):
    """Sampled motion of the stand, SI units (module docstring): a result
    (:class:`stand.io.result.Result`) whose document is the run's summary.

    The arrays are attributes; the mapping (``run["final"]``, ``run.final``,
    ``run.to_dict()``) holds the run's summary, kept up to date when a field is set:
    ``scene_name``, ``structure``, ``samples``, ``duration_s``, ``main_plane``, ``planes``,
    ``weight_planes``, ``solver`` (:attr:`stats`), ``final`` (the state at
    the end: speed, whirl radius, residual unbalance, weights' angles) and ``notes``.
    ``to_frame()`` is the samples table (also ``to_frame("samples")``); ``plot(ax=,
    kind="time" | "orbit")``.  ``len(run)`` is the number of samples; two runs are equal
    only when they are the same object.

    Attributes
    ----------
    t : ndarray (N,)
        Sample times [s].
    planes : dict of str -> ndarray (N, 2)
        Fixed-frame translation (x, y) of each plane [m].
    main_plane : str
        The plane recorded as ``shaft/x|y`` (the instrumented or only plane).
    rotor_angle, rotor_speed : ndarray (N,)
        Angle of the reference mark [rad] and spin [rad/s].
    weights : dict of str -> dict of str -> ndarray (N,)
        Each weight's coordinates by name (balls and pendulums: ``angle``,
        ``speed`` absolute [rad, rad/s]).
    weight_planes : dict of str -> str
        The plane each weight sits in.
    stats : SolverStats
    scene : stand.scene.model.Scene or None
    coordinates : dict of str -> (ndarray (N,), units)
        Further channels: the structure's generalised coordinates, a book
        model's state.
    truth : dict of str -> (ndarray, units)
        Model quantities an instrument cannot see (e.g. each plane's residual
        unbalance in the rotor frame [kg m]).
    state : ndarray, optional
        The integrator's (scaled) state at the samples.
    extra : Run, optional
        Samples at extra times requested by the instruments.
    notes : tuple of str
        What a reader should know (e.g. a book model's units); a
        :class:`stand.recording.read.Recording` adds what the reader filled in.
    instruments : mapping of str -> instrument output
        What the scene's instruments output, in memory: frames rendered on demand, readings,
        truth (:class:`stand.instruments.outputs.InstrumentOutputs`); empty without
        instruments.  ``stand.save(run, path)`` stores them.
    """

    t: np.ndarray
    planes: dict
    main_plane: str
    rotor_angle: np.ndarray
    rotor_speed: np.ndarray
    weights: dict
    weight_planes: dict
    stats: Optional[SolverStats] = None
    scene: Any = None
    coordinates: dict = field(default_factory=dict)
    truth: dict = field(default_factory=dict)
    state: Optional[np.ndarray] = field(repr=False, default=None)
    extra: Optional["Run"] = field(repr=False, default=None)
    notes: tuple = ()
    instruments: Any = field(repr=False, default_factory=dict)

    _title = "run"
    _summary_keys = ("scene_name", "samples", "duration_s", "planes", "weight_planes")
    #: the pictures of :meth:`plot`
    PLOT_KINDS = ("time", "orbit")

    # ------------------------------------------------------------ the result's document
    # the fields are plain attributes (not keys of the document): Result's attribute
    # routing is for documents whose keys are the attributes
    __hash__ = object.__hash__
    __eq__ = object.__eq__
    __ne__ = object.__ne__
    __delattr__ = object.__delattr__

    def __setattr__(self, name, value) -> None:
        object.__setattr__(self, name, value)
        if self.__dict__.get("_ready") and name in self.__dataclass_fields__:
            self._refresh()

    def __post_init__(self) -> None:
        object.__setattr__(self, "_ready", True)
        self._refresh()

    def _refresh(self) -> None:
        dict.clear(self)
        dict.update(self, self._document())

    def _document(self) -> dict:
        """The summary the mapping holds (class docstring)."""
        t = np.asarray(self.t)
        if self.main_plane not in self.planes:
            raise ValueError(f"Run.main_plane = {self.main_plane!r}: not one of the planes "
                             f"{', '.join(map(str, self.planes)) or '(none)'}")
        return {"scene_name": str(getattr(self.scene, "name", "") or ""),
                "structure": str(getattr(self.scene, "structure_type", "") or ""),
                "samples": len(self),
                "duration_s": float(t[-1] - t[0]) if t.size else 0.0,
                "main_plane": self.main_plane, "planes": list(self.planes),
                "weight_planes": dict(self.weight_planes),
                "solver": self.stats if self.stats is not None else {},
                "final": self._final(), "notes": list(self.notes)}

    # ------------------------------------------------------------ views
    @property
    def success(self) -> bool:
        return bool(self.stats.success) if self.stats is not None else True

    @property
    def x(self) -> np.ndarray:
        """Main plane's fixed-frame X translation [m] (``shaft/x``)."""
        return self.planes[self.main_plane][:, 0]

    @property
    def y(self) -> np.ndarray:
        """Main plane's fixed-frame Y translation [m] (``shaft/y``)."""
        return self.planes[self.main_plane][:, 1]

    def _stack(self, coord: str) -> np.ndarray:
        """(N, n) ``coord`` of every weight with an angle (NaN where one lacks ``coord``, e.g.
        a damaged recording), so that angles and speeds always have the same columns."""
        nan = np.full(len(self.t), np.nan)
        cols = [np.asarray(w.get(coord, nan)) for w in self.weights.values() if "angle" in w]
        if not cols:
            return np.zeros((len(self.t), 0))
        return np.column_stack(cols)

    @property
    def weight_angle(self) -> np.ndarray:
        """(N, n) absolute angles of the balls / pendulums [rad] (n = 0 without)."""
        return self._stack("angle")

    @property
    def weight_speed(self) -> np.ndarray:
        """(N, n) absolute speeds of the balls / pendulums [rad/s]."""
        return self._stack("speed")

    @property
    def relative_angle(self) -> np.ndarray:
        """Weight angles relative to the rotor's reference mark, wrapped to (-pi, pi] [rad]."""
        a = self.weight_angle - self.rotor_angle[:, None]
        return np.angle(np.exp(1j * a))

    def whirl_radius(self) -> np.ndarray:
        """Distance of the main plane from the origin, sqrt(x^2 + y^2) [m], sample by sample
        (a static offset included; the whirl about the orbit's centre over a window is
        :func:`whirl_about_centre`)."""
        return np.hypot(self.x, self.y)

    def residual_unbalance(self) -> np.ndarray:
        """Static residual unbalance of the whole rotor (rotor + weights), complex, rotor
        frame [kg m]: the vector sum over every plane of the unbalances and the weights'
        static moments (:func:`stand.integrate.residual.static_residual`).

        Planar rotor: psi = M e e^{i beta} + sum m_j l_j e^{i alpha_j} ((5.76)-(5.77)
        times S), following the scene's unbalance changes.  Rotors of the family: the sum of
        every plane's residual in :attr:`truth` (``residual/<plane>``), so an unbalance in a
        plane of its own (grinding, spatial) counts with the balls that cancel it.
        """
        from stand.integrate.residual import static_residual

        psi = static_residual(self)
        if psi is None:
            raise ValueError(f"run of {getattr(self.scene, 'name', '?')!r}: no residual unbalance "
                             "(neither truth/residual/<plane> nor a planar scene whose weights "
                             "match the recording)")
        return np.asarray(psi)

    def capacity(self, every_plane: bool = False) -> float:
        """Balancing capacity S = sum m_l of the main plane's weights [kg m] (0 without);
        ``every_plane=True``: of the weights of all planes (what the static residual is
        measured against)."""
        if self.scene is None:
            return 0.0
        return self.scene.weights_capacity(None if every_plane else self.main_plane)

    def tables(self) -> list:
        """``"samples"`` (:meth:`to_frame`) and the document's tables."""
        return ["samples"] + super().tables()

    def to_frame(self, table: Optional[str] = None) -> "pd.DataFrame":
        """The samples as a pandas DataFrame, one row per sample, SI units in the names
        (``table=None`` or ``"samples"``; another name: a table of the document).

        Columns: ``t_s``; ``x_m``, ``y_m`` (main plane, as ``shaft/x|y``);
        ``<plane>_x_m``, ``<plane>_y_m`` for every other plane; ``rotor_angle_rad``,
        ``rotor_speed_rad_s``; ``<weight>_<coordinate>_<unit>`` for each weight
        (``ball1_angle_rad``, ...); ``<coordinate>_<unit>`` for further channels.
        """
        import pandas as pd

        if table not in (None, "samples"):
            return super().to_frame(table)
        unit = column_unit
        cols = {"t_s": self.t, "x_m": self.x, "y_m": self.y}
        for p, xy in self.planes.items():
            if p != self.main_plane:
                cols[f"{p}_x_m"], cols[f"{p}_y_m"] = xy[:, 0], xy[:, 1]
        cols["rotor_angle_rad"] = self.rotor_angle
        cols["rotor_speed_rad_s"] = self.rotor_speed
        for name, coords in self.weights.items():
            for c, a in coords.items():
                cols[f"{name}_{c}_{unit(WEIGHT_UNITS.get(c, '1'))}"] = a
        for name, (a, u) in self.coordinates.items():
            cols[f"{name}_{unit(u)}"] = a
        return pd.DataFrame({k: np.array(v, dtype=np.float64) for k, v in cols.items()})

    def plot(self, ax=None, kind: str = "time"):
        """Draw the main plane's motion; returns the matplotlib Axes (as every result's
        ``plot``; the figure is ``ax.figure``).

        ``kind="time"``: x and y [mm] against t [s]; ``"orbit"``: y against x [mm].
        ``ax``: draw into these axes (default: a new backend-free figure).
        """
        from stand.io.result import axes_of

        if kind not in self.PLOT_KINDS:
            raise ValueError(f"kind = {kind!r}: one of {', '.join(self.PLOT_KINDS)}")
        ax = axes_of(ax, figsize=(7, 4) if kind == "time" else (5, 5))
        name = getattr(self.scene, "name", "") or "run"
        if kind == "time":
            ax.plot(self.t, self.x * 1e3, lw=0.8, label="x")
            ax.plot(self.t, self.y * 1e3, lw=0.8, label="y")
            ax.set_xlabel("time [s]")
            ax.set_ylabel(f"plane {self.main_plane} [mm]")
            ax.legend(loc="upper right")
        else:
            ax.plot(self.x * 1e3, self.y * 1e3, lw=0.6)
            ax.set_aspect("equal", adjustable="datalim")
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("y [mm]")
        ax.set_title(f"{name}: plane {self.main_plane}")
        return ax

    def __len__(self) -> int:
        return int(np.shape(self.t)[0])

    # ------------------------------------------------------------ summary
    def _final(self) -> Optional[dict]:
        """The state at the end (the document's ``final``; None without samples): speed,
        the main plane's whirl radius -- the mean distance from the orbit's centre (the
        mean position over the last rotor revolution, or the last 5 % of the run when the
        rotor is at rest), so that a static offset such as a gravity sag is not counted as
        whirl; the offset itself is ``static_offset_m`` -- the static residual unbalance
        relative to the capacity of all planes, its couple where the loaded planes differ in
        axial position (planar rotor and rotor family,
        :mod:`stand.integrate.residual`), the weights' angles from the reference mark."""
        N = len(self.t)
        if N == 0:
            return None
        w = abs(self.rotor_speed[-1])
        window = 2 * np.pi / w if w > 0 and np.isfinite(w) else 0.05 * self.t[-1]
        sel = self.t >= self.t[-1] - window
        final = {"time_s": float(self.t[-1]),
                 "rotor_speed_rev_per_s": float(self.rotor_speed[-1] / (2 * np.pi)),
                 "main_plane": self.main_plane}
        if getattr(self.scene, "kind", None) in ("planar", "rotor"):
            from stand.integrate.residual import couple_residual, static_residual

            S = self.capacity(every_plane=True)
            last = slice(N - 1, N)
            psi = static_residual(self, last)
            psi = float(abs(psi[0])) if psi is not None else None
            cpl = couple_residual(self, last) if psi is not None else None
            final.update({
                "residual_unbalance": psi / S if S > 0 and psi is not None else None,
                "residual_unbalance_g_mm": psi * 1e6 if psi is not None else None,
                "capacity_g_mm": float(S * 1e6),
            })
            if cpl is not None:
                final["residual_couple_g_mm2"] = float(abs(cpl[0])) * 1e9
        last = [w["angle"][-1] for w in self.weights.values() if "angle" in w]
        rel = np.degrees(np.angle(np.exp(1j * (np.asarray(last, float) - self.rotor_angle[-1]))))
        final["weights_relative_angle_deg"] = [float(a) for a in rel]
        r, centre = whirl_about_centre(self.x[sel], self.y[sel])
        final["whirl_radius_m"] = float(np.mean(r))
        final["whirl_radius_last_m"] = float(r[-1])
        final["static_offset_m"] = float(abs(centre))
        if len(self.planes) > 1:
            final["plane_radius_m"] = {p: float(np.hypot(*xy[-1])) for p, xy in self.planes.items()}
        return final


def whirl_about_centre(x, y) -> tuple:
    """``(r, centre)``: the distance [m] of each sample of an orbit (x, y) [m] from the
    orbit's centre, and that centre (the mean position, complex x + i y [m]).

    The whirl radius is the motion about the centre, not the distance from the origin: a
    rotor sagging under gravity (a static offset) but not whirling has r = 0.  Over a
    whole revolution of a synchronous whirl the centre is the static offset and r the 1X
    amplitude.
    """
    z = np.asarray(x, float) + 1j * np.asarray(y, float)
    centre = complex(np.mean(z)) if z.size else 0j
    return np.abs(z - centre), centre
