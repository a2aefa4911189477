"""Stability of the steady motions from the rotating-frame Jacobian (book section 5.4).

Digest ch5 section 4.5.  The steady motions of :mod:`stand.theories.planar.steady`
(main motions (5.50), side motions (5.51)-(5.75), the e0 > 1 main motion) are
placed in the state of :mod:`stand.theories.rotating`; stability is decided by the
eigenvalues of the Jacobian of :func:`stand.theories.rotating.rotating_rhs` (the
simulator's own equations in the rotating frame, central differences) at the
exact equilibrium.  Dimensionless units as in :mod:`stand.theories.planar.steady`
(R = omega/omega_1, e0 and e_j in units of the capacity, deflections in r*);
the conventions (heavy side on the +real axis, angles alpha_j from it) are
those of :mod:`stand.theories.planar.steady` too.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from stand.model.planar import (BETA, D11, D12, D21, D22, EPS0, FREE, K11, K12, K21, K22,
                      PlanarModel, build_planar_model)
from stand.theories.rotating import _planar_setup, _rhs_and_jacobians_speeds, rotating_jacobian
from stand.model.weights import EPS as W_EPS
from stand.theories.planar.steady import (SideMotion, _wrap, bits_of, identical_side_classes, main_motion_angles,
                     side_motions)

__all__ = [
    "SteadyMotionReport", "steady_state", "steady_eigenvalues", "is_stable",
    "large_unbalance_coefficients", "stable_steady_motions", "stable_steady_motions_at",
]


def _as_model(scene_or_model) -> PlanarModel:
    if isinstance(scene_or_model, PlanarModel):
        return scene_or_model
    return build_planar_model(scene_or_model)


def steady_state(model, s: complex, alphas) -> np.ndarray:
    """Rotating-frame state of :mod:`stand.theories.rotating` for a synchronous steady motion.

    ``s`` and ``alphas`` are in the theory's frame (heavy side at angle 0); the
    model's unbalance angle beta (heavy side from the reference mark) is added:
    u + i v = s e^{i beta}, alpha_j + beta; all velocities zero.
    """
    model = _as_model(model)
    beta = float(model.sp[BETA])
    alphas = np.asarray(alphas, dtype=float)
    if alphas.size != model.n:
        raise ValueError(f"{alphas.size} angles for a model with {model.n} weights")
    w = complex(s) * complex(math.cos(beta), math.sin(beta))
    z = np.zeros(2 * (2 + model.n))
    z[0], z[1] = w.real, w.imag
    z[2:2 + model.n] = alphas + beta
    return z


def steady_eigenvalues(scene_or_model, R: float, state, step: float = 1e-7) -> np.ndarray:
    """Eigenvalues of the rotating-frame Jacobian at a steady state.

    Jacobian of :func:`stand.theories.rotating.rotating_rhs` by central differences
    (:func:`stand.theories.rotating.rotating_jacobian`; error ~1e-7 on the eigenvalues
    with the default step), sorted by decreasing real part.  ``state`` should
    be an exact equilibrium (see :func:`steady_state`).
    """
    model = _as_model(scene_or_model)
    ev = np.linalg.eigvals(rotating_jacobian(model, float(R), np.asarray(state, float), step))
    return ev[np.argsort(-ev.real, kind="stable")]


def is_stable(eigs, tol: float = 1e-6, neutral: int = 0) -> bool:
    """Asymptotic stability from eigenvalues: max Re lambda < -tol.

    ``neutral`` eigenvalues nearest to 0 are ignored first (motion along a
    family of equilibria, e.g. n - 2 of them for the main motions of n >= 3
    weights, digest 4.1 / test T2).
    """
    ev = np.asarray(eigs, dtype=complex).ravel()
    if neutral:
        ev = ev[np.argsort(np.abs(ev), kind="stable")[int(neutral):]]
    if ev.size == 0:
        return True
    return bool(np.max(ev.real) < -tol)


def large_unbalance_coefficients(R: float, e0: float, Rt: float) -> np.ndarray:
    """Coefficients b_0..b_3 of (5.155)-(5.158), conservative case H = h = 0.

    For the e0 > 1 main motion (the book's k = 2^n - 1, n = 2) the
    characteristic polynomial in y = lambda^2 (after the relative mode (5.140)
    splits off) is b_3 y^3 + b_2 y^2 + b_1 y + b_0 with x = R^2:

        b_0 = 2 Rt e0 (x-1)^2 x^2,
        b_1 = (x-1)^3 + 2 Rt x [(x-1)^2 (2 e0 - 1) + (6 e0 + 1)(x-1) + 4(e0-1)],
        b_2 = 2 (1 - Rt)(x^2 - 1) + 2 Rt (e0 - 1) x^2,
        b_3 = (1 - 2 Rt)(x - 1).

    All b_i > 0 for x > 1, e0 > 1; the motion is (conservatively) stable when
    the three roots y are real and negative ((5.160)-(5.161): R~_m << 1 or
    R >> 1).  The tests check the roots against the Jacobian.
    """
    x = float(R) ** 2
    b0 = 2 * Rt * e0 * (x - 1) ** 2 * x * x
    b1 = (x - 1) ** 3 + 2 * Rt * x * ((x - 1) ** 2 * (2 * e0 - 1) + (6 * e0 + 1) * (x - 1)
                                      + 4 * (e0 - 1))
    b2 = 2 * (1 - Rt) * (x * x - 1) + 2 * Rt * (e0 - 1) * x * x
    b3 = (1 - 2 * Rt) * (x - 1)
    return np.array([b0, b1, b2, b3])


@dataclass
class SteadyMotionReport:
    """One synchronous steady motion at a speed, with its stability.

    Attributes
    ----------
    label : str
        "main", "main (maximally balanced)" or "side k=K" (K weights on the
        light end of the weights' common line, i.e. the end away from the heavy
        side; "side k=0" = all weights near the heavy side).
    kind : str
        "main" or "side".
    k : int or None
        K of the label.
    alphas : ndarray
        Weights' angles from the heavy side [rad].
    s : complex
        Shaft deflection [r*], theory frame (heavy side on +real).
    psi : complex
        Total unbalance [capacity].
    gamma, v : float or None
        Side-motion description (5.52), (5.64) (weights with k_j = 0 at gamma).
    state : ndarray
        Rotating-frame state (:func:`steady_state`).
    residual : float
        max |rotating_rhs(state)| -- ~1e-16 R^2 for an exact equilibrium.
    eigenvalues : ndarray
        Sorted by decreasing real part.
    max_re : float
        Largest real part, after dropping ``neutral`` eigenvalues nearest 0.
    neutral : int
        Zero eigenvalues expected from a family of equilibria.
    stable : bool
    family : bool
        The motion is one representative of a family (main, n >= 3).
    """

    label: str
    kind: str
    k: Optional[int]
    alphas: np.ndarray
    s: complex
    psi: complex
    gamma: Optional[float]
    v: Optional[float]
    state: np.ndarray
    residual: float
    eigenvalues: np.ndarray
    max_re: float
    neutral: int
    stable: bool
    family: bool = False


def _model_parameters(model: PlanarModel):
    sp = model.sp
    if sp[FREE] != 0.0:
        raise ValueError("steady motions need a prescribed rotor speed (speed drive)")
    tol = 1e-12
    if (abs(sp[D12]) > tol or abs(sp[D21]) > tol or abs(sp[K12]) > tol or abs(sp[K21]) > tol
            or abs(sp[D11] - sp[D22]) > tol * max(1.0, abs(sp[D11]))
            or abs(sp[K11] - 1.0) > 1e-9 or abs(sp[K22] - 1.0) > 1e-9):
        raise ValueError("steady motions need isotropic supports with K = 1 "
                         "(omega_1 = sqrt(c/M_Sigma)) and no cross terms")
    return float(sp[EPS0]), float(sp[D11]), model.wt[:, W_EPS].copy()


def _order_pair(m1: SideMotion, m2: SideMotion):
    """(nearer the heavy side, nearer the light side) of two roots of one e(k) >= 0.

    Larger cos gamma first; at a tie (R = 1, e0 > e(k)) the root with the
    larger sin gamma first, so that the light-side label follows the branch
    that continues above resonance.
    """
    def key(m):
        return (round(math.cos(m.gamma), 12), math.sin(m.gamma))
    return (m1, m2) if key(m1) >= key(m2) else (m2, m1)


def stable_steady_motions(model, R: float, e0: Optional[float] = None, n: Optional[int] = None,
                          *, tol: float = 1e-6, step: float = 1e-7, main: bool = True) -> list:
    """The synchronous steady motions of identical weights at speed R, with stability.

    Parameters
    ----------
    model : PlanarModel or Scene
        Prescribed speed (any programme: the speed R is imposed here), isotropic
        supports, identical weights.  H, e0, e_j and the unbalance angle are
        read from it.
    R : float
        Speed ratio, > 0.
    e0, n : optional
        If given, checked against the model.
    tol : float
        Stability margin for :func:`is_stable`.
    main : bool
        If False, the main motion's report is left out (the side motions are the same;
        for a caller that decides the main motion's stability from (5.90) itself).

    Returns
    -------
    list of SteadyMotionReport, in this order:
        * "main" (e0 <= 1): the balancing motion (5.50); for n = 2 one of the
          two mirror images (same eigenvalues, they depend on d only, 4.1); for
          n >= 3 one representative of the family (``family=True``; n - 2 zero
          eigenvalues -- n - 1 for e0 = 0 -- are ignored; stability may depend
          on the member through d).
        * "main (maximally balanced)" (e0 > 1, or n = 1 and e0 != 1): all
          weights together on the light side
          (:func:`stand.theories.planar.steady.maximally_balanced_motion`).
        * "side k=K", K = 0..n: for each class of (5.75) the two roots (5.66),
          labelled by the number K of weights at the light end of the common
          line (one motion for the class e_k = 0).  A class inside its
          existence window (5.70) contributes nothing; "side k=n" is omitted
          when e0 > 1 (it is the maximally balanced main motion), and a root
          with psi = 0 is omitted (it is a main motion: e0 = |e_k|, Fig. 5.2 b).

    Each report carries the eigenvalues of the rotating-frame Jacobian and the
    residual of :func:`stand.theories.rotating.rotating_rhs` at the state.

    Raises
    ------
    ValueError
        Torque drive, anisotropic supports, non-identical weights, or e0/n
        inconsistent with the model.
    RuntimeError
        The constructed state is not an equilibrium (residual > 1e-9 max(1, R^2)).
    """
    return stable_steady_motions_at(model, [R], e0, n, tol=tol, step=step, main=main)[0]


def stable_steady_motions_at(model, Rs, e0: Optional[float] = None, n: Optional[int] = None,
                             *, tol: float = 1e-6, step: float = 1e-7, main: bool = True) -> list:
    """:func:`stable_steady_motions` at each speed of ``Rs``: a list of their lists.

    The reports are those of :func:`stable_steady_motions` at each speed, bit for bit: the
    states of all the speeds' motions go through the kernel in one loop
    (:func:`stand.theories.rotating._rhs_and_jacobians_speeds`) and their Jacobians to one
    stacked eigenvalue call.

    Parameters
    ----------
    model, e0, n, tol, step, main
        As in :func:`stable_steady_motions`.
    Rs : sequence of float
        Speed ratios omega / omega_1, each > 0.

    Returns
    -------
    list of list of SteadyMotionReport
        One list per speed, in the order of ``Rs``.

    Raises
    ------
    ValueError, RuntimeError
        As :func:`stable_steady_motions`; a state that is not an equilibrium is reported
        (the first, in the order of the speeds) once the motions of all the speeds are built.
    """
    model = _as_model(model)
    Rs = [float(R) for R in Rs]
    for R in Rs:
        if not math.isfinite(R) or R <= 0:
            raise ValueError(f"R must be > 0, got {R!r}")
    e0, H, e = _checked_parameters(model, e0, n)
    setup = _planar_setup(model)
    # a balanced main motion does not depend on the speed: found once (R = None)
    found = main_motion_angles(e0, e=e, R=None, H=H)
    found = found if found and found[0].balanced else None
    pending = [_steady_motions_pending(model, R, e0, H, e, main, found) for R in Rs]
    # every motion's residual and Jacobian: one kernel loop for all the speeds
    flat = [(R, mo) for R, ps in zip(Rs, pending) for mo in ps]
    fj = iter(_rhs_and_jacobians_speeds(setup, [R for R, _ in flat], [mo[-1] for _, mo in flat],
                                        step))
    for i, ps in enumerate(pending):
        lim = 1e-9 * max(1.0, Rs[i] * Rs[i])
        for j, mo in enumerate(ps):
            f, J = next(fj)
            res = float(np.max(np.abs(f)))
            if res > lim:
                raise RuntimeError(f"{mo[0]}: state is not an equilibrium (residual {res:.3g})")
            ps[j] = mo + (res, J)
    jacs = [p[-1] for ps in pending for p in ps]
    if jacs:
        EV = np.linalg.eigvals(np.stack(jacs))
        # each row sorted by decreasing real part (as steady_eigenvalues), its largest real part
        EV = np.take_along_axis(EV, np.argsort(-EV.real, axis=1, kind="stable"), axis=1)
        top = EV.real.max(axis=1)
    i = 0
    out = []
    for ps in pending:
        reps = []
        for label, kind, k, alphas, s, psi, gamma, v, neutral, family, z, res, _ in ps:
            ev = EV[i].copy()
            if neutral:
                kept = ev[np.argsort(np.abs(ev), kind="stable")[neutral:]]
                max_re, stable = float(np.max(kept.real)), is_stable(ev, tol, neutral)
            else:   # is_stable(ev, tol) without its copies
                max_re = float(top[i])
                stable = bool(max_re < -tol)
            reps.append(SteadyMotionReport(label, kind, k, alphas, s, psi, gamma, v, z, res, ev,
                                           max_re, neutral, stable, family))
            i += 1
        out.append(reps)
    return out


def _checked_parameters(model, e0, n):
    """(e0, H, e_j) of the model, checked against ``e0`` and ``n`` when given (the checks of
    :func:`stable_steady_motions`)."""
    me0, H, e = _model_parameters(model)
    nn = model.n
    if n is not None and int(n) != nn:
        raise ValueError(f"n = {n} but the model has {nn} weights")
    if e0 is not None and abs(float(e0) - me0) > 1e-9 * max(1.0, me0):
        raise ValueError(f"e0 = {e0} but the model has e0 = {me0}")
    if nn == 0 or not np.allclose(e, e[0], rtol=1e-12, atol=0):
        raise ValueError("stable_steady_motions needs n >= 1 identical weights")
    S = float(e.sum())
    if abs(S - 1.0) > 1e-9:
        # the theory's unit is the capacity; the scene builder guarantees sum e_j = 1
        raise ValueError(f"sum of the weights' e_j is {S}, expected 1 (capacity units)")
    return me0, H, e


def _steady_motions_pending(model, R, e0, H, e, main, found) -> list:
    """The motions of :func:`stable_steady_motions` at speed R (checked, > 0) before their
    residuals and eigenvalues: tuples (label, kind, k, alphas, s, psi, gamma, v, neutral,
    family, state).  ``found``: the balanced main motions (speed-independent), or None."""
    nn = model.n
    out = []

    def report(label, kind, k, alphas, s, gamma, v, neutral, family):
        z = steady_state(model, s, alphas)
        psi = complex(e0 + np.sum(e * np.exp(1j * np.asarray(alphas))))
        out.append((label, kind, k, np.array(alphas, float), complex(s), psi, gamma, v,
                    neutral, family, z))

    if H == 0.0 and R == 1.0 and (e0 > 1.0 or (nn == 1 and e0 != 1.0)):
        raise ValueError("H = 0 at R = 1 and the rotor cannot be balanced: undamped "
                         "resonance, no finite steady motion")
    if found is None:
        found = main_motion_angles(e0, e=e, R=R, H=H)
    mm = found[0] if found else None  # none: n = 1, e0 < 1, R inside the window (5.70)
    # balanced: e0 <= 1 for n >= 2; a single weight balances only e0 = 1
    balanced = mm.balanced if mm is not None else False
    if mm is None or not main:
        pass
    elif balanced:
        neutral = max(0, nn - 2) + (1 if (e0 == 0.0 and nn >= 2) else 0)
        report("main", "main", None, mm.alphas, 0j, None, None, neutral, mm.family)
    else:
        report("main (maximally balanced)", "main", nn, mm.alphas, mm.s, mm.gamma, mm.v, 0, False)
    if H == 0.0 and R == 1.0:
        return out  # undamped resonance: no side motion has a finite deflection
    for cl in identical_side_classes(nn):
        b = bits_of(cl.patterns[0], nn)
        sm = side_motions(R, e0, cl.ek, H, bits=b)
        if not sm:
            continue
        if sm[0].family:
            continue  # e0 = 0, H = 0: a family with an arbitrary gamma -- not listed
        near, far = _order_pair(*sm) if len(sm) == 2 else (sm[0], None)
        pairs = [(cl.k, near, b)]
        if far is not None and 2 * cl.k != nn:
            # the far root, described with the complementary pattern (gamma + pi)
            pairs.append((nn - cl.k, far, tuple(1 - x for x in b)))
        for K, m, bb in pairs:
            if K == nn and not balanced:
                continue  # the maximally balanced main motion, reported above
            psi = e0 + cl.ek * complex(math.cos(m.gamma), math.sin(m.gamma))
            if abs(psi) < 1e-12:
                continue  # psi = 0: a main motion (e0 = |e_k|)
            if bb is b:
                g, v = m.gamma, m.v
            else:
                g, v = _wrap(m.gamma + math.pi), -m.v
            alphas = np.array([_wrap(g + x * math.pi) for x in bb])
            report(f"side k={K}", "side", K, alphas, m.s, g, v, 0, False)
    return out
