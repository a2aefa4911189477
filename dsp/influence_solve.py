"""Correction unbalances from an influence matrix: least squares, weighted, min-max; limits; holes.

The rotor's 1X vibration after corrections ``U`` (P complex unbalances, one per plane) is

    r = V0 + A U                         (R complex residuals)

with ``A`` (R x P) the influence matrix and ``V0`` the reference vibration; R is the number
of (sensor, speed) pairs when several speeds are solved together.  The solvers choose ``U``:

* :func:`least_squares` minimises ``sum_i w_i |r_i|^2`` (``w_i = 1``: ordinary least squares;
  the normal equations ``(A^H W A) U = -A^H W V0`` with ``W = diag(w)``);
* :func:`min_max` minimises ``max_i w_i |r_i|`` over the sensors with ``w_i > 0``, subject to
  caps ``|r_i| <= c_i`` (a second-order cone programme);

both under limits ``|U_j| <= m_j`` per plane.  Constrained problems are solved with cvxpy
(CLARABEL) when it is installed, else with scipy's SLSQP on the real and imaginary parts.
:func:`split_onto_holes` puts a correction onto the two holes next to its angle (an exact
vector sum), :func:`conditioning` names the planes and sensors that make ``A`` ill-conditioned.

Units are the caller's (any consistent set); angles in radians, counter-clockwise from the
reference mark in the sense of the readings.  Plain numpy (scipy, cvxpy where used); imports
nothing from ``stand``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["least_squares", "min_max", "split_onto_holes", "split_onto_weights", "conditioning",
           "Conditioning",
           "ILL_CONDITION", "cvxpy_available"]

#: condition number of the column-normalised influence matrix above which a job is warned
ILL_CONDITION = 10.0


def cvxpy_available() -> bool:
    """True when cvxpy with the CLARABEL solver can be imported."""
    try:
        import cvxpy as cp
    except ImportError:
        return False
    return "CLARABEL" in cp.installed_solvers()


def _arrays(A, V0, weights, max_mass):
    A = np.asarray(A, dtype=complex)
    V0 = np.asarray(V0, dtype=complex).ravel()
    if A.ndim != 2 or A.shape[0] != V0.size:
        raise ValueError(f"influence matrix: shape {A.shape} does not fit {V0.size} reference "
                         f"reading(s)")
    R, P = A.shape
    w = np.ones(R) if weights is None else np.asarray(weights, dtype=float).ravel()
    if w.shape != (R,) or not np.all(np.isfinite(w)) or np.any(w < 0):
        raise ValueError(f"weights: {R} finite values >= 0 expected, got {w.tolist()}")
    m = np.full(P, np.inf) if max_mass is None else np.asarray(max_mass, dtype=float).ravel()
    if m.shape != (P,) or np.any(np.isnan(m)) or np.any(m <= 0):
        raise ValueError(f"max_mass: {P} limits > 0 expected (inf: none), got {m.tolist()}")
    # scales: residuals of order 1, unbalances of order 1 (solver tolerances are absolute)
    sv = max(float(np.max(np.abs(V0))), 1e-300)
    sa = max(float(np.max(np.abs(A))), 1e-300)
    su = sv / sa
    return A / sa, V0 / sv, w, m / su, sv, su


def least_squares(A, V0, weights=None, max_mass=None):
    """Corrections minimising ``sum_i w_i |V0_i + (A U)_i|^2`` with ``|U_j| <= max_mass_j``.

    Parameters
    ----------
    A : (R, P) complex
        Influence matrix [vibration per unbalance].
    V0 : (R,) complex
        Reference vibration [vibration].
    weights : (R,) float >= 0, optional
        Weight of each residual's square (default 1).
    max_mass : (P,) float, optional
        Limit on ``|U_j|`` [unbalance] (``inf``: none).

    Returns
    -------
    (P,) complex ndarray
        U [unbalance].
    """
    a, v, w, m, sv, su = _arrays(A, V0, weights, max_mass)
    sw = np.sqrt(w)
    U = -np.linalg.lstsq(a * sw[:, None], v * sw, rcond=None)[0]
    if np.all(np.abs(U) <= m * (1 + 1e-12)):
        return U * su
    return _constrained(a, v, w, m, None, "ls") * su


def min_max(A, V0, weights=None, caps=None, max_mass=None):
    """Corrections minimising ``max_i w_i |V0_i + (A U)_i|`` (sensors with ``w_i > 0``).

    Parameters
    ----------
    A, V0, max_mass
        As in :func:`least_squares`.
    weights : (R,) float >= 0, optional
        Factor on each residual's magnitude in the objective (default 1; 0 leaves the
        residual out of the objective, its cap still holds).
    caps : (R,) float, optional
        ``|r_i| <= caps_i`` [vibration] (``inf``: none).

    Returns
    -------
    (P,) complex ndarray
        U [unbalance].

    Raises
    ------
    ValueError
        No residual in the objective, or caps and limits that cannot all be met.
    """
    a, v, w, m, sv, su = _arrays(A, V0, weights, max_mass)
    R = a.shape[0]
    c = np.full(R, np.inf) if caps is None else np.asarray(caps, dtype=float).ravel() / sv
    if c.shape != (R,) or np.any(np.isnan(c)) or np.any(c <= 0):
        raise ValueError(f"caps: {R} values > 0 expected (inf: none)")
    if not np.any(w > 0):
        raise ValueError("weights: every sensor has weight 0; min_max needs one in the objective")
    return _constrained(a, v, w, m, c, "minmax") * su


def _constrained(a, v, w, m, c, kind):
    if cvxpy_available():
        return _cvxpy(a, v, w, m, c, kind)
    return _slsqp(a, v, w, m, c, kind)


def _infeasible(kind):
    raise ValueError("the sensor caps (max_vibration) and plane limits (max_mass) cannot all be "
                     "met: raise a cap or a limit" if kind == "minmax" else
                     "the constrained least-squares problem has no solution")


def _cvxpy(a, v, w, m, c, kind):
    import cvxpy as cp

    R, P = a.shape
    U = cp.Variable(P, complex=True)
    r = v + a @ U
    cons = [cp.abs(U[j]) <= m[j] for j in range(P) if np.isfinite(m[j])]
    if kind == "ls":
        obj = cp.Minimize(cp.sum_squares(cp.multiply(np.sqrt(w), r)))
    else:
        t = cp.Variable()
        on = np.flatnonzero(w > 0)
        cons += [cp.multiply(w[on], cp.abs(r[on])) <= t]
        cons += [cp.abs(r[i]) <= c[i] for i in range(R) if np.isfinite(c[i])]
        obj = cp.Minimize(t)
    prob = cp.Problem(obj, cons)
    prob.solve(solver="CLARABEL", tol_gap_abs=1e-10, tol_gap_rel=1e-10, tol_feas=1e-10)
    if prob.status not in ("optimal", "optimal_inaccurate") or U.value is None:
        _infeasible(kind)
    return np.asarray(U.value, dtype=complex)


def _slsqp(a, v, w, m, c, kind):
    """The constrained problems with scipy's SLSQP on x = [Re U, Im U (, t)].

    Least squares: ``sum w |r|^2`` under ``m_j^2 - |U_j|^2 >= 0``.  Min-max: the epigraph
    ``min t`` under ``t - w_i |r_i| >= 0`` (rows with ``w_i > 0``), ``t >= 0``, the caps
    ``c_i^2 - |r_i|^2 >= 0`` and the limits (every constraint with its exact gradient; at
    ``r_i = 0`` the zero subgradient of ``|r_i|``).  A min-max whose weighted residuals can
    all be made zero within the caps and limits (as many independent planes as sensors)
    returns that solution, which SLSQP's cone vertex at ``t = 0`` would not certify.

    Raises
    ------
    ValueError
        SLSQP ends at a point that violates a cap (the caps and limits cannot all be met), or
        does not reach a point that meets the optimality conditions (:func:`_kkt`).
    """
    from scipy.optimize import minimize

    R, P = a.shape
    lim = np.flatnonzero(np.isfinite(m))
    x0 = -np.linalg.lstsq(a, v, rcond=None)[0]
    x0 = x0 * np.minimum(1.0, 0.99 * m / np.maximum(np.abs(x0), 1e-300))

    def U(x):
        return x[:P] + 1j * x[P:2 * P]

    def d_abs2(z, rows):
        """Gradient of |z_i|^2 over [Re U, Im U] for z = rows @ U + const: (n, 2P)."""
        g = np.conj(z)[:, None] * rows
        return 2 * np.hstack([g.real, -g.imag])

    cons = []
    if lim.size:
        eye = np.eye(P, dtype=complex)[lim]
        cons.append({"type": "ineq", "fun": lambda x: m[lim] ** 2 - np.abs(U(x)[lim]) ** 2,
                     "jac": lambda x: _pad(-d_abs2(U(x)[lim], eye), x.size)})
    if kind == "ls":
        fun = lambda x: float(np.sum(w * np.abs(v + a @ U(x)) ** 2))  # noqa: E731
        jac = lambda x: np.sum(w[:, None] * d_abs2(v + a @ U(x), a), axis=0)  # noqa: E731
        z0, bounds = np.concatenate([x0.real, x0.imag]), None
    else:
        on = np.flatnonzero(w > 0)
        cap = np.flatnonzero(np.isfinite(c))
        exact = -np.linalg.lstsq(a[on], v[on], rcond=None)[0]
        r = v + a @ exact
        cancel = 1e-12 * max(1.0, float(np.max(np.abs(a[on]) @ np.abs(exact))))  # round-off
        if (np.max(np.abs(r[on])) <= cancel and np.all(np.abs(exact) <= m)
                and np.all(np.abs(r) <= c)):
            return exact                 # min-max 0: the rows in the objective cancelled

        def mag(x):
            r = v[on] + a[on] @ U(x)
            return r, np.abs(r)

        def epi_jac(x):
            r, ar = mag(x)
            g = np.conj(r)[:, None] * a[on] / np.where(ar > 0, ar, np.inf)[:, None]
            return np.hstack([-w[on, None] * g.real, w[on, None] * g.imag, np.ones((on.size, 1))])

        fun = lambda x: float(x[-1])  # noqa: E731
        jac = lambda x: np.eye(x.size)[-1]  # noqa: E731
        cons.append({"type": "ineq", "fun": lambda x: x[-1] - w[on] * mag(x)[1],
                     "jac": epi_jac})
        if cap.size:
            cons.append({"type": "ineq",
                         "fun": lambda x: c[cap] ** 2 - np.abs(v[cap] + a[cap] @ U(x)) ** 2,
                         "jac": lambda x: _pad(-d_abs2(v[cap] + a[cap] @ U(x), a[cap]), x.size)})
        z0 = np.concatenate([x0.real, x0.imag, [float(np.max(w[on] * np.abs(v + a @ x0)[on]))]])
        bounds = [(None, None)] * (2 * P) + [(0.0, None)]
    out = minimize(fun, z0, jac=jac, method="SLSQP", bounds=bounds, constraints=cons,
                   options={"ftol": 1e-14, "maxiter": 2000})
    x = out.x
    met = [bool(np.all(np.asarray(con["fun"](x)) >= -1e-7)) for con in cons]
    if kind == "minmax" and cap.size and not met[-1]:
        _infeasible(kind)    # only caps can be unmeetable: U = 0 meets the limits, t the rest
    if not (all(met) and (out.success or _kkt(jac(x), cons, x, bounds))):
        raise ValueError(f"{'min-max' if kind == 'minmax' else 'constrained least-squares'} "
                         f"balancing: scipy SLSQP did not converge ({out.message}, "
                         f"{out.nit} iterations); install cvxpy or choose another method")
    return U(x)


def _kkt(grad, cons, x, bounds, active=1e-7, tol=1e-6):
    """Whether ``x`` satisfies the optimality conditions of the convex problem to ``tol``:
    the objective's gradient a combination with multipliers >= 0 of the gradients of the
    constraints within ``active`` of 0 (and of the active bounds).  SLSQP's line search
    often stops at the optimum with "positive directional derivative" (status 8); this
    tells that apart from a stop short of it."""
    from scipy.optimize import nnls

    G = [np.atleast_2d(con["jac"](x))[np.asarray(con["fun"](x)) <= active] for con in cons]
    for k, (lo, _) in enumerate(bounds or []):
        if lo is not None and x[k] - lo <= active:
            G.append(np.eye(x.size)[k:k + 1])
    G = np.vstack(G + [np.zeros((0, x.size))])
    scale = max(float(np.linalg.norm(grad)), 1e-300)
    if G.shape[0] == 0:
        return scale <= tol
    return nnls(G.T, grad)[1] <= tol * scale


def _pad(g, n):
    """Constraint gradient over [Re U, Im U] padded with zero columns to n variables."""
    return np.hstack([g, np.zeros((g.shape[0], n - g.shape[1]))])


def split_onto_holes(U: complex, holes: int, offset_rad: float = 0.0):
    """Split a correction onto the two holes next to its angle (an exact vector sum).

    Hole k is at ``offset_rad + 2 pi k / holes`` (k = 0 .. holes - 1).

    Parameters
    ----------
    U : complex
        The correction (mass e^{i angle}) [mass].
    holes : int >= 3
        Number of equally spaced holes.
    offset_rad : float
        Angle of hole 0 from the reference mark [rad].

    Returns
    -------
    list of (hole, angle_rad, mass)
        Two entries, ``sum(mass e^{i angle}) == U``.
    """
    n = int(holes)
    if n < 3 or n != holes:
        raise ValueError(f"holes = {holes!r}: an integer >= 3 (two adjacent holes must span "
                         f"less than 180 deg)")
    step = 2 * math.pi / n
    th = (np.angle(U) - offset_rad) % (2 * math.pi)
    k = int(th // step) % n
    p1 = k * step
    p2 = p1 + step
    s = math.sin(step)
    mag = abs(U)
    m1 = mag * math.sin(p2 - th) / s
    m2 = mag * math.sin(th - p1) / s
    return [(k, (offset_rad + p1) % (2 * math.pi), m1),
            ((k + 1) % n, (offset_rad + p2) % (2 * math.pi), m2)]


def _multisets(available, max_pieces):
    """``[(total, pieces)]``: every choice of up to ``max_pieces`` of the available masses
    (each usable more than once), the empty choice first."""
    from itertools import combinations_with_replacement

    out = {0.0: ()}
    for n in range(1, max_pieces + 1):
        for c in combinations_with_replacement(sorted(available), n):
            out.setdefault(round(float(sum(c)), 12), tuple(c))
    return sorted(out.items())


def split_onto_weights(U: complex, available, holes=None, offset_rad: float = 0.0,
                       max_pieces: int = 3):
    """Put a correction onto the weights at hand: the choice closest to ``U`` as a vector.

    Parameters
    ----------
    U : complex
        The correction [mass].
    available : sequence of float > 0
        The masses at hand [mass]; each may be used up to ``max_pieces`` times per position.
    holes : int, optional
        Equally spaced holes (hole k at ``offset_rad + 2 pi k / holes``): two holes (or one)
        are chosen; without holes the weights go at the correction's own angle.
    max_pieces : int
        Most pieces stacked at one position.

    Returns
    -------
    (placed, error)
        ``placed``: ``[(hole or None, angle_rad, mass, pieces)]`` (positions with weights),
        ``error``: ``|sum(mass e^{i angle}) - U|`` [mass].
    """
    av = [float(a) for a in available]
    if not av or any(not (math.isfinite(a) and a > 0) for a in av):
        raise ValueError(f"available weights: masses > 0 expected, got {list(available)!r}")
    sets = _multisets(av, int(max_pieces))
    tot = np.array([t for t, _ in sets])
    if holes is None:
        k = int(np.argmin(np.abs(tot - abs(U))))
        ang = float(np.angle(U)) % (2 * math.pi)
        placed = [(None, ang, tot[k], sets[k][1])] if tot[k] > 0 else []
        return placed, float(abs(tot[k] * np.exp(1j * ang) - U))
    n = int(holes)
    if n < 1 or n != holes or n > 360:
        raise ValueError(f"holes = {holes!r}: an integer 1 .. 360")
    phi = (offset_rad + 2 * math.pi * np.arange(n) / n) % (2 * math.pi)
    e = np.exp(1j * phi)
    i1, i2 = np.triu_indices(n, k=1)
    # every pair of distinct holes, every choice in each: |t1 e1 + t2 e2 - U|
    v = (tot[None, :, None] * e[i1][:, None, None] + tot[None, None, :] * e[i2][:, None, None]) - U
    p, a, b = np.unravel_index(int(np.argmin(np.abs(v))), v.shape)
    placed = [(int(h), float(phi[h]), float(tot[c]), sets[c][1])
              for h, c in ((i1[p], a), (i2[p], b)) if tot[c] > 0]
    return placed, float(abs(v[p, a, b]))


@dataclass(frozen=True)
class Conditioning:
    """How well the influence matrix separates the planes.

    Attributes
    ----------
    condition : float
        2-norm condition number of A (its columns scaled to unit length, so that the
        units of the planes do not count).
    ill : bool
        ``condition > ILL_CONDITION``.
    planes, sensors : tuple of str
        The planes (and, with as many sensors as planes, the sensors) that make A
        ill-conditioned: the large entries of the singular vectors of the smallest
        singular value.
    """

    condition: float
    ill: bool
    planes: tuple
    sensors: tuple

    def message(self) -> str:
        """One line for the warning (empty when A is well conditioned)."""
        if not self.ill:
            return ""
        who = f"planes {', '.join(self.planes)}"
        if self.sensors:
            who += f" (sensors {', '.join(self.sensors)})"
        return (f"influence matrix is ill-conditioned (condition {self.condition:.3g} > "
                f"{ILL_CONDITION:g}): {who} act nearly alike; the corrections are sensitive to "
                f"reading errors: move a correction plane or add a sensor")


def conditioning(A, planes, sensors) -> Conditioning:
    """:class:`Conditioning` of A (R x P) with the names of its P planes and R rows."""
    A = np.asarray(A, dtype=complex)
    n = np.linalg.norm(A, axis=0)
    n = np.where(n > 1e-12 * max(float(n.max(initial=0.0)), 1e-300), n, np.inf)  # 0 column: 0
    An = A / n[None, :]
    u, s, vh = np.linalg.svd(An, full_matrices=False)
    cond = float(s[0] / s[-1]) if s[-1] > 1e-12 * s[0] and A.shape[0] >= A.shape[1] else math.inf
    ill = not cond <= ILL_CONDITION
    names_p, names_s = (), ()
    if ill and A.shape[1] > 1:
        vj = np.abs(vh[-1].conj())
        names_p = tuple(str(planes[j]) for j in np.flatnonzero(vj >= 0.5 * vj.max()))
        if A.shape[0] == A.shape[1]:
            ui = np.abs(u[:, -1])
            names_s = tuple(str(sensors[i]) for i in np.flatnonzero(ui >= 0.5 * ui.max()))
    elif ill:
        names_p = (str(planes[0]),)
    return Conditioning(condition=cond, ill=ill, planes=names_p, sensors=names_s)
