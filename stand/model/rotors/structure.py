"""The generic linear rotor structure: M, G, D, K, planes and unbalances.

Every rotor of the seeds is written once in this form (digest ch2_ch3 section
7.2 item 2; papers digest section 5.1)::

    M q'' + (D + Omega G) q' + K q = f_unbalance(t) + f_gravity + f_weights

with ``q`` the generalised coordinates (n of them, SI: m or rad), ``Omega``
the spin [rad/s] and ``G`` the gyroscopic matrix per unit spin (skew).  Each
**plane** (a balancer plane, an unbalance plane, a probe point) is a point of
the rotor's axis whose fixed-frame transverse translation is ``(x_p, y_p) =
T_p q`` (T_p is 2 x n).  A point mass attached at radius r in plane p pushes
the rotor through ``T_p^T`` (virtual work), which is how the unbalances and
the correction weights couple to any rotor.

Unbalance ``s`` [kg m] in plane p at angle ``beta`` from the reference mark
(rotor angle phi): the generalised force is ::

    T_p^T s [phi'^2 cos(phi + beta) + phi'' sin(phi + beta),
             phi'^2 sin(phi + beta) - phi'' cos(phi + beta)]

At constant spin this is ``Re{ T_p^T s Omega^2 (1, -i) e^{i(Omega t + beta)} }``.

A plane may have a separate **force map** F_p (2 x n, default T_p) when the
forces applied at the plane do not do work through its displacement alone:
the grinding rotor of section 2.5.3, whose y is held by the contact, feels a
transverse force F_y through the friction T = f N as ``F_x + f F_y`` ((2.50)),
so its plane has T_p = [[1], [0]] and F_p = [[1], [f]].  Forces go through
F_p^T, displacements through T_p.

Engineering criterion (2.15)-(2.16): with an elementary unbalance in plane p
the plane's steady deflection, averaged along the unbalance over a
revolution, ``r_bar = Re(X + i Y) / 2`` with ``(X, Y) = T_p Q`` and
``[K - Omega^2 M + i Omega (D + Omega G)] Q = s Omega^2 T_p^T (1, -i)^T``.
Autobalancing needs ``r_bar < 0``.  For two planes (paper 003, the
generalised criterion (1)/(24)) the 2 x 2 real blocks of the averaged
quadratic form must be negative definite (:meth:`LinearRotor.criterion_matrix`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional, Sequence

import numpy as np

from stand.errors import Budget, BudgetExceeded

__all__ = ["LinearRotor", "Unbalance", "working_ranges", "sign_changes", "synchronous_poles",
           "criterion_matrices", "generalised_working_ranges"]


@dataclass(frozen=True)
class Unbalance:
    """A static unbalance s [kg m] in plane ``plane`` at ``angle`` [rad] from the mark."""

    plane: str
    s: float
    angle: float = 0.0


@dataclass(frozen=True)
class LinearRotor:
    """Generic linear rotor (module docstring).

    Attributes
    ----------
    name : str
        Rotor type, e.g. ``"two_mass"`` (with the book's section in ``source``).
    coords : tuple of str
        Names of the generalised coordinates, with units, e.g. ``("x [m]", "alpha [rad]")``.
    M, G, D, K : ndarray (n, n)
        Mass, gyroscopic (per unit spin, skew-symmetric), damping, stiffness
        (SI, consistent with the coordinates).  The rotor's own unbalance masses
        are included in M; the correction weights are NOT (they are added by
        the coupling, :mod:`stand.integrate.coupled`).
    planes : dict of str -> ndarray (2, n)
        T_p for each named plane.
    unbalances : tuple of Unbalance
    gravity : ndarray (n,)
        Constant generalised gravity force [N or N m] on the rotor (zeros for a
        vertical axis: "leave out what a scene does not need").
    gravity_plane : ndarray (2,)
        The gravity acceleration's transverse components (fixed x, y) [m/s^2]
        felt by weights in the balancer planes (zeros for a vertical axis).
    source : str
        Book section / equations this instance implements.
    force_maps : dict of str -> ndarray (2, n)
        F_p for planes whose forces do not act through T_p^T (module docstring).
    """

    name: str
    coords: tuple
    M: np.ndarray
    G: np.ndarray
    D: np.ndarray
    K: np.ndarray
    planes: dict
    unbalances: tuple = ()
    gravity: Optional[np.ndarray] = None
    gravity_plane: np.ndarray = field(default_factory=lambda: np.zeros(2))
    source: str = ""
    force_maps: dict = field(default_factory=dict)

    def __post_init__(self):
        n = len(self.coords)
        for key in ("M", "G", "D", "K"):
            a = np.asarray(getattr(self, key), dtype=float)
            if a.shape != (n, n) or not np.all(np.isfinite(a)):
                raise ValueError(f"{self.name}: {key} must be a finite {n}x{n} matrix "
                                 f"(one row per coordinate {self.coords}), got shape {a.shape}")
            object.__setattr__(self, key, a)
        if not np.allclose(self.G, -self.G.T, atol=1e-12 * (1 + np.abs(self.G).max())):
            raise ValueError(f"{self.name}: G must be skew-symmetric (gyroscopic)")
        planes = {}
        for p, T in self.planes.items():
            T = np.asarray(T, dtype=float)
            if T.shape != (2, n):
                raise ValueError(f"{self.name}: plane {p!r} map must be 2x{n}, got {T.shape}")
            planes[p] = T
        object.__setattr__(self, "planes", planes)
        fmaps = {}
        for p, F in self.force_maps.items():
            F = np.asarray(F, dtype=float)
            if p not in planes or F.shape != (2, n):
                raise ValueError(f"{self.name}: force map {p!r} must be 2x{n} for a known plane")
            fmaps[p] = F
        object.__setattr__(self, "force_maps", fmaps)
        for u in self.unbalances:
            if u.plane not in planes:
                raise ValueError(f"{self.name}: unbalance plane {u.plane!r} is not one of {sorted(planes)}")
        g = np.zeros(n) if self.gravity is None else np.asarray(self.gravity, dtype=float)
        object.__setattr__(self, "gravity", g)
        object.__setattr__(self, "gravity_plane", np.asarray(self.gravity_plane, dtype=float))

    @property
    def n(self) -> int:
        return len(self.coords)

    def force_map(self, plane: str) -> np.ndarray:
        """F_p: the map through which forces at ``plane`` act (default T_p)."""
        return self.force_maps.get(plane, self.planes[plane])

    # ----------------------------------------------------------- frequency domain
    def dynamic_stiffness(self, omega: float, whirl: Optional[float] = None) -> np.ndarray:
        """``K - w^2 M + i w (D + Omega G)`` at whirl w (default: synchronous, w = Omega)."""
        w = omega if whirl is None else whirl
        return self.K - w * w * self.M + 1j * w * (self.D + omega * self.G)

    def unbalance_response(self, omega: float, plane: str, s: float = 1.0, angle: float = 0.0,
                           at: Optional[str] = None) -> np.ndarray:
        """Complex amplitude (X, Y) of plane ``at`` (default: the same plane) for an
        unbalance s [kg m] in ``plane`` at constant spin omega [rad/s]:
        ``x_at(t) = Re(X e^{i omega t})``, ``y_at(t) = Re(Y e^{i omega t})``."""
        T = self.force_map(plane)
        f = s * omega * omega * np.exp(1j * angle) * (T.T @ np.array([1.0, -1j]))
        Q = np.linalg.solve(self.dynamic_stiffness(omega), f)
        return self.planes[at or plane] @ Q

    def criterion(self, omega, plane: str) -> np.ndarray:
        """Engineering criterion (2.15): ``r_bar`` [m per (kg m) of unbalance] of the
        plane under an elementary unbalance in it; autobalancing needs r_bar < 0.

        ``omega`` may be an array [rad/s].  Undamped rotors at a resonance give inf/nan.
        """
        om = np.atleast_1d(np.asarray(omega, dtype=float))
        if om.ndim == 1 and om.size > 1:
            try:            # all speeds in one batched solve (the loop's values, ~50x faster)
                Hs = (self.K - (om * om)[:, None, None] * self.M
                      + 1j * om[:, None, None] * (self.D + om[:, None, None] * self.G))
                f = (om * om)[:, None] * (self.force_map(plane).T @ np.array([1.0, -1j]))
                XY = np.linalg.solve(Hs, f[:, :, None])[:, :, 0] @ self.planes[plane].T
                return 0.5 * (XY[:, 0] + 1j * XY[:, 1]).real
            except np.linalg.LinAlgError:       # a singular speed: the loop marks it nan
                pass
        out = np.empty(om.shape)
        for k, w in enumerate(om):
            try:
                X, Y = self.unbalance_response(w, plane)
                out[k] = 0.5 * (X + 1j * Y).real
            except np.linalg.LinAlgError:
                out[k] = math.nan
        return out if np.ndim(omega) else out[0]

    def criterion_matrix(self, omega: float, planes: Sequence[str]) -> np.ndarray:
        """Generalised criterion (paper 003, (1)/(24)-(26)) for several planes.

        Returns the real symmetric matrix Q (2k x 2k, k = len(planes)) of the
        revolution-averaged form ``f = sum_j <s_j . r_j>`` in the elementary
        unbalance components ``(xi_1, eta_1, ..., xi_k, eta_k)`` (rotor frame);
        the main motion is stable iff Q is negative definite.
        """
        Tm = np.vstack([self.planes[p] for p in planes])            # (2k, n)
        Fm = np.vstack([self.force_map(p) for p in planes])
        Hinv = np.linalg.inv(self.dynamic_stiffness(omega))
        k = len(planes)
        Q = np.zeros((2 * k, 2 * k))
        # unit unbalance along rotor-frame xi (angle 0) / eta (angle pi/2) of plane b
        for b in range(k):
            for c, ang in enumerate((0.0, 0.5 * math.pi)):
                f = omega * omega * np.exp(1j * ang) * (Fm[2 * b:2 * b + 2].T @ np.array([1.0, -1j]))
                R = Tm @ (Hinv @ f)            # responses of all planes
                for a in range(k):
                    X, Y = R[2 * a], R[2 * a + 1]
                    # <e_xi . r> and <e_eta . r> with e_xi = (cos, sin), e_eta = (-sin, cos)
                    Q[2 * a, 2 * b + c] = 0.5 * (X + 1j * Y).real
                    Q[2 * a + 1, 2 * b + c] = 0.5 * (Y - 1j * X).real
        return 0.5 * (Q + Q.T)

    def natural_frequencies(self, omega: float = 0.0) -> np.ndarray:
        """Damped natural frequencies [rad/s] at spin omega: |Im| of the eigenvalues
        of the quadratic problem (lambda^2 M + lambda (D + omega G) + K) q = 0, sorted,
        each conjugate pair once (forward and backward whirls both appear)."""
        lam = self.eigenvalues(omega)
        im = np.abs(lam.imag)
        return np.sort(im[lam.imag >= 0])

    def eigenvalues(self, omega: float = 0.0) -> np.ndarray:
        """Eigenvalues [1/s] of the first-order form at spin omega (Campbell data)."""
        n = self.n
        Minv = np.linalg.inv(self.M)
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        A[n:, :n] = -Minv @ self.K
        A[n:, n:] = -Minv @ (self.D + omega * self.G)
        return np.linalg.eigvals(A)

    def campbell(self, speeds) -> np.ndarray:
        """Natural frequencies [rad/s] (rows: speeds, columns: modes) vs spin.

        A mode that is overdamped at some speeds (a real eigenvalue pair) gives two
        entries there and none where it oscillates: rows are padded with nan to the
        widest."""
        rows = [self.natural_frequencies(w) for w in np.atleast_1d(speeds)]
        width = max((r.size for r in rows), default=0)
        return np.array([np.concatenate([r, np.full(width - r.size, np.nan)]) for r in rows])


#: relative offset of the samples taken on either side of a pole (a synchronous critical speed)
POLE_OFFSET = 1e-10
#: evaluations of the criterion (or of the count of its non-negative eigenvalues) that the
#: root refinement of one scan may spend beyond its grid: a root needs 10-50, a real rotor
#: has tens of them; round-off noise (an ill-conditioned structure) would need millions
MAX_REFINE_EVALUATIONS = 20_000


def synchronous_poles(rotor: LinearRotor, lo: float = 0.0, hi: float = math.inf) -> np.ndarray:
    """Speeds w [rad/s] in (lo, hi) where the undamped synchronous dynamic stiffness
    ``K - w^2 (M - i G)`` is singular: the poles of the criterion's receptance
    (the natural frequencies at synchronous whirl; D is left out, so for a damped
    rotor these are where the criterion is steepest).  Sorted, duplicates (the x / y
    pair of an isotropic rotor) merged to 1e-9 relative."""
    from scipy import linalg

    x = linalg.eigvals(rotor.K.astype(complex), rotor.M - 1j * rotor.G)
    x = x[np.isfinite(x)]
    x = x[(np.abs(x.imag) <= 1e-8 * np.abs(x)) & (x.real > 0)].real
    w = np.sort(np.sqrt(x))
    w = w[(w > lo) & (w < hi)]
    out = []
    for v in w:
        if not out or v > out[-1] * (1 + 1e-9):
            out.append(float(v))
    return np.array(out)


def _samples(lo: float, hi: float, n: int, poles) -> tuple:
    """The scan's points: a geometric grid of n points over [lo, hi] and each pole's
    two sides ``P (1 -+ POLE_OFFSET)``; returns (points, index of the pole each
    point's right-hand interval straddles or -1)."""
    poles = [float(p) for p in np.atleast_1d(np.asarray(poles, dtype=float)) if lo < p < hi]
    x = np.geomspace(lo, hi, n)
    for p in poles:
        x = x[np.abs(x - p) > 2 * POLE_OFFSET * p]
    x = np.sort(np.concatenate([x, [p * (1 - POLE_OFFSET) for p in poles],
                                [p * (1 + POLE_OFFSET) for p in poles]]))
    straddle = np.full(x.size, -1)
    for k, p in enumerate(poles):
        i = int(np.searchsorted(x, p)) - 1
        straddle[i] = k
    return x, np.array(poles), straddle


def sign_changes(f, lo: float, hi: float, n: int = 20000, xtol: float = 1e-13, poles=()):
    """Points in (lo, hi) where the sign of f changes (zeros and poles alike).

    ``poles`` [same unit as lo, hi]: the points where f blows up (a pole of the
    receptance, :func:`synchronous_poles`).  They are sampled on both sides
    (``P (1 -+ 1e-10)``), so a sign change at a pole is reported as the pole itself
    and a zero between a pole and the next grid point is not stepped over (a fixed
    grid alone misses a narrow gap next to a pole whose mode has a node near the
    plane, issue 17 part 6).  Every other sign change between consecutive samples is
    refined by Brent's method on f (continuous there) to ``xtol`` relative."""
    from scipy.optimize import brentq

    x, P, straddle = _samples(lo, hi, n, poles)
    fx = np.asarray(f(x), dtype=float)
    v = np.sign(fx)
    out = []
    budget = Budget("the criterion's sign-change refinement", MAX_REFINE_EVALUATIONS)

    def f1(w):
        budget.spend()
        return float(np.asarray(f(np.array([w])), float)[0])

    for k in np.nonzero(v[:-1] * v[1:] < 0)[0]:
        a, b = x[k], x[k + 1]
        if straddle[k] >= 0:
            out.append(float(P[straddle[k]]))
            continue
        try:
            out.append(brentq(f1, a, b, xtol=1e-300, rtol=max(xtol, 4 * np.finfo(float).eps),
                              maxiter=500))
        except BudgetExceeded:
            raise
        except (ValueError, RuntimeError):      # f not finite inside: bisection on the sign
            sa = v[k]
            while b - a > xtol * b:
                m = 0.5 * (a + b)
                sm = np.sign(f1(m))
                if sm == 0 or not np.isfinite(sm):
                    break
                if sm == sa:
                    a = m
                else:
                    b = m
            out.append(0.5 * (a + b))
    return np.array(out)


def working_ranges(rotor: LinearRotor, plane: str, lo: float, hi: float, n: int = 20000):
    """Critical speeds [rad/s] and the working ranges of a balancer in ``plane``
    by the engineering criterion over (lo, hi).

    The receptance's poles (:func:`synchronous_poles`) are bracketed exactly and
    each other sign change is root-found (:func:`sign_changes`).
    Returns ``(critical_speeds, ranges)``; ranges is a list of (start, end)
    pairs with ``end = inf`` when the last range reaches ``hi``.
    """
    f = lambda w: rotor.criterion(w, plane)        # noqa: E731
    crit = sign_changes(f, lo, hi, n, poles=synchronous_poles(rotor, lo, hi))
    edges = np.concatenate([[lo], crit, [hi]])
    ranges = []
    for a, b in zip(edges[:-1], edges[1:]):
        mid = math.sqrt(a * b)
        if f(np.array([mid]))[0] < 0:
            ranges.append((float(a), math.inf if b == hi else float(b)))
    return crit, ranges


def criterion_matrices(rotor: LinearRotor, omegas, planes: Sequence[str]) -> np.ndarray:
    """:meth:`LinearRotor.criterion_matrix` at every speed of ``omegas`` [rad/s] at once:
    shape (N, 2k, 2k).  A speed where the dynamic stiffness is singular gives nan."""
    om = np.atleast_1d(np.asarray(omegas, dtype=float))
    Tm = np.vstack([rotor.planes[p] for p in planes])            # (2k, n)
    Fm = np.vstack([rotor.force_map(p) for p in planes])
    k = len(planes)
    H = (rotor.K[None] - (om ** 2)[:, None, None] * rotor.M[None]
         + 1j * om[:, None, None] * (rotor.D[None] + om[:, None, None] * rotor.G[None]))
    # right-hand sides: unit unbalance along xi (angle 0) and eta (pi/2) of each plane
    rhs = np.zeros((rotor.n, 2 * k), complex)
    for b in range(k):
        base = Fm[2 * b:2 * b + 2].T @ np.array([1.0, -1j])
        rhs[:, 2 * b] = base
        rhs[:, 2 * b + 1] = 1j * base
    Q = np.full((om.size, 2 * k, 2 * k), np.nan)
    for i in range(om.size):
        try:
            R = Tm @ np.linalg.solve(H[i], rhs) * om[i] ** 2         # (2k, 2k) complex
        except np.linalg.LinAlgError:
            continue
        X, Y = R[0::2], R[1::2]
        q = np.empty((2 * k, 2 * k))
        q[0::2] = 0.5 * (X + 1j * Y).real
        q[1::2] = 0.5 * (Y - 1j * X).real
        Q[i] = 0.5 * (q + q.T)
    return Q


def _positive_count(rotor, planes, om) -> np.ndarray:
    """Number of eigenvalues >= 0 of the criterion matrix at each speed (0: the
    generalised criterion holds); a singular speed counts as -1 (unknown)."""
    Q = criterion_matrices(rotor, om, planes)
    out = np.full(Q.shape[0], -1)
    ok = np.all(np.isfinite(Q), axis=(1, 2))
    if ok.any():
        out[ok] = np.sum(np.linalg.eigvalsh(Q[ok]) >= 0.0, axis=1)
    return out


def generalised_working_ranges(rotor: LinearRotor, planes: Sequence[str], lo: float, hi: float,
                               n: int = 4000, xtol: float = 1e-13):
    """Generalised criterion (paper 003 (1)/(24)-(26); for two distinct planes of a rigid
    rotor: K_xi and K_eta negative definite) over (lo, hi) [rad/s].

    Returns ``(critical_speeds, ranges)`` as :func:`working_ranges`: the critical speeds
    are every speed where an eigenvalue of :meth:`LinearRotor.criterion_matrix` changes
    sign (the count of non-negative eigenvalues changes), the ranges where the matrix
    is negative definite.  The poles (:func:`synchronous_poles`) are bracketed on both
    sides (the count changes there through infinity: for two planes of a rigid rotor the
    onsets are the critical speeds (40)-(41) themselves); every other change of the count
    between samples is located by bisection on the count to ``xtol`` relative (several
    eigenvalues crossing between two samples are all found when the count is monotone
    there, as it is between poles for an undamped rotor with M - iG positive definite).
    """
    planes = list(planes)
    x, P, straddle = _samples(lo, hi, n, synchronous_poles(rotor, lo, hi))
    cnt = _positive_count(rotor, planes, x)
    budget = Budget("the generalised criterion's bisection", MAX_REFINE_EVALUATIONS)

    def count(w):
        budget.spend()
        return int(_positive_count(rotor, planes, np.array([w]))[0])

    def jumps(a, ca, b, cb):
        if ca == cb:
            return []
        if b - a <= xtol * b:
            return [0.5 * (a + b)]
        m = 0.5 * (a + b)
        cm = count(m)
        if cm < 0:                       # a singular speed inside: it is the edge
            return [m]
        return jumps(a, ca, m, cm) + jumps(m, cm, b, cb)

    crit = []
    for k in range(x.size - 1):
        if cnt[k] == cnt[k + 1] or cnt[k] < 0 or cnt[k + 1] < 0:
            continue
        if straddle[k] >= 0:
            crit.append(float(P[straddle[k]]))
        else:
            crit += jumps(x[k], cnt[k], x[k + 1], cnt[k + 1])
    crit = np.array(sorted(crit))
    edges = np.concatenate([[lo], crit, [hi]])
    ranges = []
    for a, b in zip(edges[:-1], edges[1:]):
        if count(math.sqrt(a * b)) == 0:
            if ranges and ranges[-1][1] == a:          # an eigenvalue crossing inside a
                ranges[-1] = (ranges[-1][0], math.inf if b == hi else float(b))  # working range
            else:                                      # cannot happen (count 0 on both sides)
                ranges.append((float(a), math.inf if b == hi else float(b)))
    return crit, ranges
