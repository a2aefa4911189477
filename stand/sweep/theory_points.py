"""The ``theory.*`` columns of a sweep's points.

* planar rotor (chapter 5): main-motion stability (vectorised over the speeds
  of a line), quasi-periodic (stuck-ball) stability and escape speed, the
  main motion's critical speeds (cached per line), optionally the side
  motions -- :func:`planar_theory_rows`;
* any rotor of the family (``[structure]``): the engineering criterion (2.15)
  of :func:`stand.theory` (weights locked, the m/M -> 0 limit): the operating
  speed inside a working range of every plane with weights counts as a stable
  main motion; critical speeds in Hz and in units of the lowest natural
  frequency at rest -- :func:`structure_theory_rows`.

Both fill the rows in place and turn a failing point into ``status = "error"``
(the others go on).
"""
from __future__ import annotations

import dataclasses
import functools
import math
import warnings

import numpy as np

from stand.io.executor import error_text
from stand.io.jsonable import dumps

__all__ = ["planar_theory_rows", "structure_theory_rows"]


def _fail(row: dict, exc: BaseException) -> None:
    row["status"], row["error"] = "error", error_text(exc)


# ================================================================ planar rotor
@functools.lru_cache(maxsize=4096)
def _main_d(n: int, e0: float):
    """Configuration parameter d of the main motion (as :func:`scene_theory`); None if none."""
    from stand.theories.planar import main_motion as mm
    from stand.theories.planar.steady import main_motion_angles

    if not e0 <= 1:
        return None
    configs = [c for c in main_motion_angles(e0, n) if getattr(c, "balanced", True)]
    return mm.d_from_angles(configs[0].alphas) if configs else None


@functools.lru_cache(maxsize=4096)
def _critical(Rt: float, h: float, H: float, d: float, R_max: float):
    """Critical speeds of the main motion (R, kind) on (0.05, R_max), cached per worker."""
    from stand.theories.planar import main_motion as mm

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cs = mm.critical_speeds(Rt, h, H, d, R_min=0.05, R_max=R_max)
    return tuple((float(c.R), c.kind) for c in cs)


def _q(x: float) -> float:
    """``x`` rounded to 12 significant digits: parameters recomputed from SI scene fields
    (e.g. e0 = M e / S) carry round-off in the last digits; rounding lets the points of
    one curve share their critical speeds and their vectorised stability batch."""
    return float(f"{x:.12g}")


def _main_stable_batch(R: np.ndarray, Rt: float, h: float, H: float, d: float):
    """(abscissa, stable) at the speeds ``R``: :func:`main_motion.is_stable`, vectorised."""
    from stand.theories.planar import main_motion as mm

    if h == 0.0 and H == 0.0:
        marg = mm._conservative_margin_batch(R, Rt, d)
        return marg, marg <= mm._conservative_tol(R)
    a = mm._abscissa_batch(R, Rt, h, H, d)
    if h == 0.0 or H == 0.0:
        return a, np.zeros(R.shape, bool)
    return a, a <= mm._abscissa_tol(R)


def _main_and_qp(row: dict, sc, groups: dict, i: int) -> None:
    """Scope checks, d, the QP verdict; the point joins its (Rt, h, H, d) group."""
    from stand.theories.planar import qp
    from stand.theories.planar.speedmap import TheoryError, _check_scope

    _check_scope(sc, None)
    s = sc.supports
    if s.stiffness_x != s.stiffness_y:
        raise TheoryError("theory: anisotropic supports (stiffness_x != stiffness_y); the "
                          "steady motions of chapter 5 need isotropic supports")
    n, Rt, h, H, e0, R = (row[k] for k in ("p.n", "p.Rt", "p.h", "p.H", "p.e0", "p.R"))
    if not (math.isfinite(R) and R > 0):
        raise TheoryError(f"theory: no steady operating speed (R = {R})")
    Rt, h, H, e0 = _q(Rt), _q(h), _q(H), _q(e0)
    d = _main_d(int(n), e0)
    d = None if d is None else _q(d)
    row["theory.d"] = math.nan if d is None else d
    qp_ok = h > 0 and H > 0
    R_star = qp.escape_speed(Rt, h, H) if qp_ok else math.inf
    row["theory.escape_speed_R"] = R_star
    row["theory.qp_stable"] = bool(qp_ok and R < R_star)
    if d is None:
        row["theory.main_stable"] = False
        row["theory.main_abscissa"] = math.nan
    else:
        groups.setdefault((Rt, h, H, d), []).append(i)


def _motions(row: dict, sc, opts: dict) -> None:
    """Stable motions (with the side motions when asked) and the critical speeds."""
    from stand.model.planar import build_planar_model
    from stand.theories.planar.steady_stability import stable_steady_motions
    from stand.theories.planar.speedmap import MAX_WEIGHTS_FOR_SIDE
    from stand.scene.model import SpeedDrive

    motions = []
    if row["theory.main_stable"]:
        motions.append("main")
    if row["theory.qp_stable"]:
        motions.append("quasi-periodic")
    d = row["theory.d"]
    if opts.get("side") and int(row["p.n"]) <= MAX_WEIGHTS_FOR_SIDE:
        R = row["p.R"]
        sc_speed = sc if sc.drive.kind == "speed" else dataclasses.replace(
            sc, drive=SpeedDrive(np.array([[0.0, R * sc.natural_frequency]])))
        model = build_planar_model(sc_speed)
        for rep in stable_steady_motions(model, R):
            if rep.stable and (rep.kind == "side" or not math.isfinite(d)):
                motions.append(rep.label)
    row["theory.stable_motions"] = ";".join(sorted(set(motions)))
    if opts.get("critical_speeds", True) and math.isfinite(d):
        cs = _critical(_q(row["p.Rt"]), _q(row["p.h"]), _q(row["p.H"]), float(d),
                       float(opts.get("R_max", 1000.0)))
        row["theory.critical_speeds_R"] = dumps([c[0] for c in cs])
        row["theory.critical_kinds"] = dumps([c[1] for c in cs])
        row["theory.n_critical"] = len(cs)


def planar_theory_rows(rows: list, scenes: list, opts: dict) -> None:
    """Fill the theory columns of planar points (in place); vectorised over speeds per group.

    Parameters
    ----------
    rows : list of dict
        The points' rows, with their ``p.*`` columns; rows not "ok" are skipped.
    scenes : list of stand.scene.model.Scene
        The points' validated scenes.
    opts : dict
        ``[theory]`` options: ``side``, ``critical_speeds``, ``R_max``.
    """
    groups: dict = {}
    for i, (row, sc) in enumerate(zip(rows, scenes)):
        if row["status"] == "ok":
            try:
                _main_and_qp(row, sc, groups, i)
            except Exception as exc:  # a failing point must not stop the others
                _fail(row, exc)
    for (Rt, h, H, d), idx in groups.items():
        try:
            R = np.array([rows[i]["p.R"] for i in idx], float)
            a, st = _main_stable_batch(R, Rt, h, H, d)
            for i, ai, si in zip(idx, a, st):
                rows[i]["theory.main_abscissa"] = float(ai)
                rows[i]["theory.main_stable"] = bool(si)
        except Exception as exc:
            for i in idx:
                _fail(rows[i], exc)
    for row, sc in zip(rows, scenes):
        if row["status"] == "ok":
            try:
                _motions(row, sc, opts)
            except Exception as exc:
                _fail(row, exc)


# ================================================================ rotor family
def structure_theory_rows(rows: list, scenes: list, opts: dict) -> None:
    """Fill the theory columns of ``[structure]`` points (in place), from :func:`stand.theory`.

    Parameters
    ----------
    rows : list of dict
        The points' rows, with ``p.R`` and ``p.f0_hz``; rows not "ok" are skipped.
    scenes : list of stand.scene.model.Scene
        The points' validated scenes.
    opts : dict
        ``[theory]`` options: ``critical_speeds`` (``side`` and ``R_max`` are the
        planar rotor's).
    """
    from stand.theories.scene import theory

    for row, sc in zip(rows, scenes):
        if row["status"] != "ok":
            continue
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                doc = theory(sc, floquet=False)
            f0, speed_hz = row["p.f0_hz"], row["p.R"] * row["p.f0_hz"]
            ranges = doc["engineering_criterion"]
            working = all(any(a <= speed_hz and (b is None or speed_hz <= b)
                              for a, b in ranges[p]["working_ranges_hz"]) for p in ranges)
            if sc.bodies and not sc.n_weights:
                # the engineering criterion (2.15) is that of point weights; a body weight's
                # main motion needs its own theory (stand theory on the scene)
                row["theory.main_stable"] = None
                row["theory.stable_motions"] = ""
            else:
                row["theory.main_stable"] = bool(working and sc.n_weights)
                row["theory.stable_motions"] = "main" if row["theory.main_stable"] else ""
            row["theory.natural_frequencies_hz"] = dumps(doc["natural_frequencies_hz_at_rest"])
            if opts.get("critical_speeds", True):
                main = ranges.get(sc.main_plane) or next(iter(ranges.values()))
                crit = main["critical_speeds_hz"]
                starts = [a for a, _ in main["working_ranges_hz"]]
                row["theory.critical_speeds_hz"] = dumps(crit)
                row["theory.critical_speeds_R"] = dumps([c / f0 for c in crit])
                row["theory.critical_kinds"] = dumps(["gains" if c in starts else "loses"
                                                      for c in crit])
                row["theory.n_critical"] = len(crit)
        except Exception as exc:  # a failing point must not stop the others
            _fail(row, exc)
