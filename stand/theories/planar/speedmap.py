"""A scene's theory: speed bands with their stable motions, critical speeds, QP law.

This answers a designer's first questions -- *from which speed does the
balancer balance, what can go wrong below and above, what will the laser spot
show?* -- for a scene, from the theory of :mod:`stand.theories.planar.main_motion`
(main motion, (5.90)), :mod:`stand.theories.planar.steady` (side motions and the e0 > 1
main motion) with :mod:`~stand.theories.planar.steady_stability` (rotating-frame Jacobian) and :mod:`stand.theories.planar.qp`
(quasi-periodic motions, (5.181)-(5.237)).

Scope (the book's chapter 5 model): identical weights with a common relative
drag h, isotropic supports.  For anisotropic supports only the engineering
criterion of section 2.5.1 is reported (digest ch2_ch3 section 2.1); the
rotating-frame steady motions do not exist there.
"""
from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import asdict, dataclass, field

import numpy as np

from stand.model.planar import build_planar_model
from stand.scene.dimensionless import dimensionless
from stand.scene.model import Scene, SpeedDrive
from stand.theories.planar import main_motion as mm
from stand.theories.planar.main_charpoly import _check_params, _is_stable_batch
from stand.theories.planar import qp
from stand.theories.planar import steady, steady_stability

#: side motions are evaluated (finite-difference Jacobians) only up to this many weights
MAX_WEIGHTS_FOR_SIDE = 8


class TheoryError(ValueError):
    """The scene is outside the scope of the theory; the message says why."""


@dataclass
class CriticalSpeedReport:
    """A speed where a motion gains or loses stability (or starts/stops existing)."""

    R: float
    hz: float
    motion: str
    kind: str  #: "gains" / "loses" stability on increasing speed
    source: str = "numeric"


@dataclass
class Band:
    """A speed band and the motions stable throughout it."""

    R_from: float
    R_to: float
    from_hz: float
    to_hz: float
    motions: list


@dataclass
class SceneTheory:
    """Everything :func:`scene_theory` finds; ``to_dict()`` is the JSON of ``stand theory``."""

    scene: str
    natural_frequency_hz: float
    parameters: dict
    critical_speeds: list
    bands: list
    qp: dict
    closed_forms: dict
    conservative: dict
    anisotropic: dict | None
    operating_speed_R: float
    warnings: list = field(default_factory=list)

    def to_dict(self) -> dict:
        f0 = self.natural_frequency_hz
        return {
            "scene": self.scene,
            "natural_frequency_hz": f0,
            "parameters": self.parameters,
            "operating_speed_hz": self.operating_speed_R * f0,
            "critical_speeds_hz": [asdict(c) for c in self.critical_speeds],
            "stable_bands": [{"from_hz": b.from_hz, "to_hz": b.to_hz, "motions": b.motions,
                              "R_from": b.R_from, "R_to": b.R_to} for b in self.bands],
            "qp": self.qp,
            "closed_forms": self.closed_forms,
            "conservative": self.conservative,
            "anisotropic": self.anisotropic,
            "warnings": self.warnings,
        }


def _operating_speed(scene: Scene) -> float:
    """The scene's final (held) rotor speed [rad/s]."""
    d = scene.drive
    if d.kind == "speed":
        if d.coast_down_start is not None:
            return float(np.max(d.programme[:, 1]))
        return float(d.programme[-1, 1])
    return float(d.target_speed)


def anisotropic_ranges(scene: Scene) -> dict:
    """Engineering criterion for anisotropic supports, (2.29)-(2.30) (digest ch2_ch3 2.1).

    Autobalancing for omega in (omega_min, omega_2) U (omega_max, inf) with
    omega_2 = sqrt((c_min + c_max) / (2 M_Sigma)); the m/M -> 0 limit.
    """
    s = scene.supports
    Ms = scene.total_mass
    cmin, cmax = sorted((s.stiffness_x, s.stiffness_y))
    w = [math.sqrt(cmin / Ms), math.sqrt((cmin + cmax) / (2 * Ms)), math.sqrt(cmax / Ms)]
    hz = [x / (2 * math.pi) for x in w]
    return {"critical_speeds_hz": hz,
            "balancing_bands_hz": [[hz[0], hz[1]], [hz[2], None]],
            "source": "engineering criterion (2.29)-(2.30), m/M -> 0"}


def _check_scope(scene: Scene, p) -> list:
    b = scene.balancer
    notes = []
    if b.count == 0:
        raise TheoryError("theory: the scene has no weights ([balancer] type = \"none\")")
    for name, arr in (("mass", b.mass), ("radius", b.radius), ("drag", b.drag), ("inertia", b.inertia)):
        a = np.asarray(arr, float)
        if np.ptp(a) > 1e-12 * max(np.max(np.abs(a)), 1e-300):
            raise TheoryError(f"theory: balancer.{name} differs between weights ({a.tolist()}); the "
                              "steady-motion theory of chapter 5 needs identical weights")
    if scene.drive.kind != "speed":
        notes.append("torque drive: the theory assumes the prescribed speed drive.target_speed")
    return notes


def scene_theory(scene: Scene, R_max: float | None = None, n_grid: int = 240, *,
                 closed_forms: bool = True) -> SceneTheory:
    """Speed bands, critical speeds and the QP law of a scene.

    Parameters
    ----------
    scene : Scene
        Identical weights (balls or pendulums), isotropic supports.  A torque
        drive is analysed at its steady speed (target speed, or torque / H0
        for a constant torque).
    R_max : float, optional
        Upper end of the speed map (units of omega_1); default covers the
        operating speed, the QP escape speed and the main motion's last
        critical speed.
    n_grid : int
        Log-grid intervals over the map before the band edges are refined.
    closed_forms : bool
        Compute the ``closed_forms`` section ((5.96), (5.125)-(5.127), (5.182), the
        unbalance-independent threshold: ~50 scans of (5.90), about half the map's time).
        False leaves it empty, for a caller that reads the bands and critical speeds only
        (the balancing report's dynamics section); nothing else changes.
    """
    p = dimensionless(scene)
    notes = _check_scope(scene, p)
    f0 = p.omega_1 / (2 * math.pi)
    n, Rt, e0 = p.n, p.Rt, p.e0
    h = float(p.h[0])
    s = scene.supports
    iso_k = s.stiffness_x == s.stiffness_y
    H = p.H_x if p.H_x == p.H_y else 0.5 * (p.H_x + p.H_y)
    if iso_k and p.H_x != p.H_y:
        notes.append(f"support damping differs between axes (H = {p.H_x:.4g}, {p.H_y:.4g}): the "
                     f"theory uses their mean {H:.4g}")
    R_op = _operating_speed(scene) / p.omega_1
    if scene.drive.kind == "torque":
        d0 = scene.drive
        if d0.model == "constant":
            R_op = (d0.torque / d0.rotor_drag / p.omega_1) if d0.rotor_drag > 0 else 3.0
            notes.append("constant torque: operating speed = torque / rotor_drag" if d0.rotor_drag > 0
                         else "constant torque without rotor drag: no steady speed; the map is drawn to 3 f0")
        scene = dataclasses.replace(scene, drive=SpeedDrive(np.array([[0.0, R_op * p.omega_1]])))
    params = {"n": n, "R_m": p.R_m, "Rt": Rt, "h": h, "H": H, "e0": e0,
              "R_omega2": p.R_omega2, "r_star_m": p.r_star, "operating_R": R_op}
    if not iso_k:
        return _anisotropic_theory(scene, f0, params, R_op, notes)

    # --- main motion: configuration parameter d
    d = None
    if e0 <= 1:
        configs = [c for c in steady.main_motion_angles(e0, n) if getattr(c, "balanced", True)]
        if configs:
            d = mm.d_from_angles(configs[0].alphas)
            if n >= 3 and not (n == 3 and e0 == 1):
                notes.append("n >= 3: the main motions form a family; d is that of one member "
                             f"(d = {d:.4g}); other members may have other critical speeds -- see "
                             "closed_forms.unbalance_independent_threshold_R")
        else:
            notes.append(f"no main (balancing) motion: {n} weight(s) cannot balance e0 = {e0:.4g} "
                         "(polygon condition (5.50))")
    params["d"] = d
    qp_ok = h > 0 and H > 0
    if not qp_ok:
        notes.append("h = 0 or H = 0: the quasi-periodic theory ((5.181), R* = 1 + 2Rt/(hH)) needs "
                     "both dampings > 0; no QP motion is reported")
    if n > MAX_WEIGHTS_FOR_SIDE:
        notes.append(f"n = {n} > {MAX_WEIGHTS_FOR_SIDE}: side motions (and the e0 > 1 main motion) "
                     "are not evaluated")

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        R_star = qp.escape_speed(Rt, h, H) if qp_ok else math.inf
        main_crit = mm.critical_speeds(Rt, h, H, d, R_min=0.05, R_max=1000.0) if d is not None else []
    notes += sorted({str(w.message) for w in caught})
    last = max([c.R for c in main_crit], default=1.0)
    R_min = 0.1
    if R_max is None:
        R_max = max(3.0, 1.5 * R_op, 1.3 * last, 1.2 * R_star if math.isfinite(R_star) else 0.0)
        R_max = min(R_max, 1000.0)
    if not R_max > 1.5 * R_min:
        raise TheoryError(f"upper end of the speed map = {R_max * f0:.4g} rev/s: must be above "
                          f"{1.5 * R_min * f0:.4g} rev/s (0.15 f0)")
    model = build_planar_model(scene)

    def motions_at(Rs) -> list:
        """The sorted labels of the motions stable at each speed of ``Rs``."""
        Rs = np.asarray(Rs, dtype=float)
        main_ok = ([False] * Rs.size if d is None
                   else _is_stable_batch(Rs, *_check_params(Rt, h, H, d)))
        # the main motion's report only when (5.90) does not decide it (d is None)
        side = (steady_stability.stable_steady_motions_at(model, Rs, main=d is None)
                if n <= MAX_WEIGHTS_FOR_SIDE else [[]] * Rs.size)
        out = []
        for R, ok, reps in zip(Rs, main_ok, side):
            labels = ["main"] if ok else []
            labels += [rep.label for rep in reps if rep.stable and (rep.kind == "side" or d is None)]
            if qp_ok and R < R_star:
                labels.append("quasi-periodic")
            out.append(tuple(sorted(set(labels))))
        return out

    # intervals between grid points and exact thresholds; each is classified at its
    # geometric midpoint, so two close thresholds never hide the band between them
    exact = sorted({c.R for c in main_crit if R_min < c.R < R_max}
                   | ({R_star} if R_min < R_star < R_max else set()))
    pts = np.unique(np.concatenate([np.geomspace(R_min, R_max, n_grid + 1), exact]))
    mids = np.sqrt(pts[:-1] * pts[1:])
    sets = motions_at(mids)
    exact_set = set(exact)
    edges = []  # (R, left_set, right_set), or for a bisected edge [a, b, left_set, right_set]
    for i in range(len(mids) - 1):
        if sets[i] == sets[i + 1]:
            continue
        p_i = pts[i + 1]
        if p_i in exact_set:
            edges.append((p_i, sets[i], sets[i + 1]))
        else:
            edges.append([mids[i], mids[i + 1], sets[i], sets[i + 1]])
    # every edge's bisection (<= 60 halvings to b/a - 1 < 1e-9, in log R), all edges in step:
    # one batch of speeds per halving; each edge's sequence of speeds is its own
    active = [e for e in edges if isinstance(e, list)]
    for _ in range(60):
        if not active:
            break
        ms = [math.sqrt(e[0] * e[1]) for e in active]
        for e, mid, sm in zip(active, ms, motions_at(ms)):
            if sm == e[2]:
                e[0] = mid
            else:
                e[1] = mid
        active = [e for e in active if not e[1] / e[0] - 1 < 1e-9]
    edges = [(math.sqrt(e[0] * e[1]), e[2], e[3]) if isinstance(e, list) else e for e in edges]
    bounds = [R_min] + [e[0] for e in edges] + [R_max]
    band_sets = [sets[0]] + [e[2] for e in edges]
    bands = [Band(bounds[i], bounds[i + 1], bounds[i] * f0, bounds[i + 1] * f0, list(band_sets[i]))
             for i in range(len(band_sets)) if bounds[i + 1] > bounds[i]]
    bands = _merge_bands(bands, f0)

    crit = [CriticalSpeedReport(c.R, c.R * f0, "main", c.kind, "(5.90) spectral abscissa"
                                if (h > 0 or H > 0) else "(5.98) conservative") for c in main_crit]
    if math.isfinite(R_star):
        crit.append(CriticalSpeedReport(R_star, R_star * f0, "quasi-periodic", "loses",
                                        "escape speed R* = 1 + 2Rt/(hH) (5.182)/(5.226)"))
    for R, sa, sb in edges:
        if any(abs(R - c.R) < 1e-9 * R for c in crit):
            continue
        if set(sa) ^ set(sb) == {"side k=0", "main (maximally balanced)"}:
            # e0 > 1: one stable branch runs through resonance (weights together); below R = 1
            # it is the heavy-side side motion, above it the maximally balanced main motion --
            # a change of name, not of stability
            continue
        for label in sorted(set(sa) ^ set(sb)):
            if label in ("main", "quasi-periodic"):
                continue
            crit.append(CriticalSpeedReport(R, R * f0, label, "gains" if label in sb else "loses"))
    crit.sort(key=lambda c: c.R)

    qp_sec = (_qp_section(R_op, Rt, h, H, e0, p, f0, R_star) if qp_ok
              else _qp_section(R_op, Rt, 0.0, 0.0, e0, p, f0, math.inf))
    return SceneTheory(scene.name, f0, params, crit, bands, qp_sec,
                       _closed_forms(Rt, h, H, d, e0, n, f0) if closed_forms else {},
                       _conservative(Rt, d, f0), None, R_op, notes)


def _anisotropic_theory(scene, f0, params, R_op, notes) -> SceneTheory:
    """Anisotropic supports: the engineering criterion (2.29)-(2.30) as the speed map."""
    an = anisotropic_ranges(scene)
    w1, w2, w3 = (x / f0 for x in an["critical_speeds_hz"])
    notes.append("anisotropic supports: the steady motions of chapter 5 need isotropic supports; the "
                 "bands are the engineering criterion of section 2.5.1 (m/M -> 0), the weights' "
                 "finite mass shifts them")
    R_max = max(3.0, 1.5 * R_op, 1.3 * w3)
    label = "main (engineering criterion)"
    cuts = [0.1, w1, w2, w3, R_max]
    sets = [[], [label], [], [label]]
    bands = [Band(cuts[i], cuts[i + 1], cuts[i] * f0, cuts[i + 1] * f0, sets[i])
             for i in range(4) if cuts[i + 1] > cuts[i]]
    crit = [CriticalSpeedReport(w1, w1 * f0, label, "gains", "(2.29) omega_min"),
            CriticalSpeedReport(w2, w2 * f0, label, "loses", "(2.29) sqrt((c_min + c_max)/(2 M))"),
            CriticalSpeedReport(w3, w3 * f0, label, "gains", "(2.29) omega_max")]
    qp_sec = {"escape_speed_hz": None, "speed_hz": R_op * f0, "roots_hz": [], "stable_root_hz": None,
              "precession_amplitude_m": None, "nutation_amplitude_m": None, "petals": None,
              "shape": None, "note": "quasi-periodic theory (5.181) assumes isotropic supports"}
    return SceneTheory(scene.name, f0, params, crit, bands, qp_sec, {}, {}, an, R_op, notes)


def _merge_bands(bands, f0):
    out = []
    for b in bands:
        if out and out[-1].motions == b.motions:
            out[-1].R_to, out[-1].to_hz = b.R_to, b.R_to * f0
        else:
            out.append(b)
    return out


def _qp_section(R, Rt, h, H, e0, p, f0, R_star) -> dict:
    out = {"escape_speed_hz": R_star * f0 if math.isfinite(R_star) else None,
           "escape_speed_R": R_star if math.isfinite(R_star) else None,
           "speed_hz": R * f0, "roots_hz": [], "stable_root_hz": None,
           "precession_amplitude_m": None, "nutation_amplitude_m": None, "petals": None, "shape": None}
    if not (h > 0 and H > 0) or R <= 0:
        return out
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        roots = qp.qp_roots(R, Rt, h, H)
        out["roots_hz"] = [float(r * f0) for r in roots]
        stable = [r for r in roots if qp.qp_stability(r, R, Rt, h, H, n=p.n).stable]
    if stable:
        Om = float(stable[0])
        law = qp.spot_law(Om, R, e0, H, p.R_m)
        closed = law.petals is not None
        out.update({"stable_root_hz": Om * f0, "stable_root_R": Om,
                    "precession_amplitude_m": law.A_P * p.r_star,
                    "nutation_amplitude_m": law.A_N * p.r_star,
                    "k": law.k,
                    # k = omega/Omega integer -> k - 1 petals; otherwise the nearest count and
                    # the pattern turns slowly on the screen (digest 5.3 items 2-4)
                    "petals": law.petals if closed else max(int(round(law.k)) - 1, 0),
                    "pattern_closed": closed, "shape": law.shape})
    return out


def _closed_forms(Rt, h, H, d, e0, n, f0) -> dict:
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if h > 0 and H > 0:
            out["R1_max_5_127"] = mm.R1_max_closed_form(Rt, h, H)
            out["R1_max_5_127_hz"] = out["R1_max_5_127"] * f0
            out["R1_max_5_127_valid"] = bool(mm.R1_max_validity(Rt, h, H))
            if d is not None:
                out["R1_first_order_5_125"] = mm.R1_first_order(Rt, h, H, d)
                out["R1_refined_5_126"] = mm.R1_refined(Rt, h, H, d)
            hc = mm.high_speed_h_crit(Rt, H)
            out["high_speed_h_crit_5_96"] = hc
            out["balances_at_high_speed"] = bool(h > hc)
            try:
                thr = mm.unbalance_independent_threshold(Rt, h, H)
                out["unbalance_independent_threshold_R"] = thr
                out["unbalance_independent_threshold_hz"] = None if thr is None else thr * f0
            except Exception as exc:  # pragma: no cover - reported, not fatal
                out["unbalance_independent_threshold_R"] = None
                out["unbalance_independent_threshold_error"] = str(exc)
            out["escape_speed_R_5_182"] = qp.escape_speed(Rt, h, H)
            thr = qp.qp_thresholds(Rt, h, H)
            out["qp_three_roots_from_R"] = thr.one_to_three
            out["qp_one_root_above_R"] = thr.three_to_one
        windows = {}
        for c in steady.identical_side_classes(n):
            if abs(c.ek) > e0 and e0 > 0:
                w = steady.side_window(e0, c.ek, H)
                if w is not None:
                    windows[f"side k={c.k}"] = {"R1": w[0], "R2": w[1], "hz": [w[0] * f0, w[1] * f0]}
        out["side_motion_gap_5_70"] = windows
    return out


def _conservative(Rt, d, f0) -> dict:
    """Conservative (h = H = 0) critical speeds, the digest's section 6.5 comparison."""
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for key, dd in (("scene_configuration", d), ("small_or_large_unbalance_d1", 1.0),
                        ("balls_90deg_apart_d0", 0.0)):
            if dd is None:
                continue
            cs = mm.critical_speeds(Rt, 0.0, 0.0, dd, R_min=0.5, R_max=1000.0)
            out[key] = {"d": dd, "R": [c.R for c in cs], "hz": [c.R * f0 for c in cs],
                        "kinds": [c.kind for c in cs]}
    return out


def plot_speed_map(th: SceneTheory, path=None, ax=None):
    """Draw the speed map: bands of stable motions over speed, criticals marked.

    Parameters
    ----------
    th : SceneTheory
    path : str or os.PathLike, optional
        Also write the figure (PNG) there, atomically.
    ax : matplotlib.axes.Axes, optional
        Draw into these axes (default: a new backend-free figure).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib import rcParams

    from stand.io.figures import figure_and_axes, save_figure

    labels = sorted({m for b in th.bands for m in b.motions},
                    key=lambda s: (s != "main", s != "main (maximally balanced)", s))
    fig, ax = figure_and_axes(ax, figsize=(9, 1.2 + 0.45 * max(len(labels), 1)))
    colors = rcParams["axes.prop_cycle"].by_key()["color"]
    for i, lab in enumerate(labels):
        for b in th.bands:
            if lab in b.motions:
                ax.barh(i, b.to_hz - b.from_hz, left=b.from_hz, height=0.6,
                        color=colors[i % len(colors)], alpha=0.8)
    for c in th.critical_speeds:
        ax.axvline(c.hz, color="k", lw=0.8, ls="--" if c.kind == "loses" else "-")
    ax.axvline(th.operating_speed_R * th.natural_frequency_hz, color="tab:red", lw=1.5,
               label="operating speed")
    ax.axvline(th.natural_frequency_hz, color="gray", lw=0.8, ls=":", label="natural frequency f0")
    ax.set_yticks(range(len(labels)))
    ax.set_yticklabels(labels)
    ax.set_xscale("log")
    ax.set_xlabel("rotor speed [rev/s]")
    ax.set_title(f"{th.scene or 'scene'}: stable motions (critical speeds: solid = gained, dashed = lost)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    fig.tight_layout()
    if path is not None:
        save_figure(fig, path)
    return fig
