"""Model 2.8: a flexible rotor, the uniform hinged-hinged (simply supported)
Euler-Bernoulli shaft, by modal truncation; digest ch2_ch3 section 2.9,
equations (2.161)-(2.166).

Shaft of length l [m], mass per length m [kg/m], bending stiffness EJ [N m^2]
on rigid hinged supports; gyroscopic effects neglected as in the book.  The
modes (2.162) are ``phi_j(z) = sin(pi j z / l)`` with ``w_j = (pi j / l)^2
sqrt(EJ/m)``.  The deflections in x and y are expanded as ``x(z, t) = sum_j
qx_j(t) phi_j(z)``, same for y.  The coordinates are the modal amplitudes
(qx_1..qx_J, qy_1..qy_J) [m], so

    M = (m l / 2) I,   K = (m l / 2) diag(w_j^2),   D = (m l / 2) diag(2 zeta_j w_j),

per direction.  A plane at axial position z_p has ``T_p = [[phi(z_p), 0], [0, phi(z_p)]]``,
where ``phi(z_p)`` is the row of the J mode shapes.  An unbalance s there therefore
gives the modal forces ``s w^2 phi_j(z_p)``, which is the expansion (2.163).  The steady
deflection at the plane is then the corrected (2.164)-(2.165), with the book's missing
1/m restored::

    v(a) = (2 s / (m l)) sum_j w^2 sin^2(pi j a / l) / (w_j^2 - w^2).

Closed form (no truncation).  The series is the driving-point receptance of
the pinned-pinned beam.  Because D^4 - k^4 = (D^2 - k^2)(D^2 + k^2) and both
factors have the Dirichlet eigenfunctions sin(pi j z / l), it sums to ::

    EJ G(a, a; w) = [sin(ka) sin(k(l-a)) / sin(kl) - sinh(ka) sinh(k(l-a)) / sinh(kl)] / (2 k^3),

with k^4 = m w^2 / EJ.  The criterion is ``r_bar = s w^2 G(a, a)`` (the deflection
lies in the rotating plane of the unbalance, so no averaging is needed).  The modal
sum converges to it like J^-3.
"""
from __future__ import annotations

import math
from typing import Optional, Sequence

import numpy as np

from stand.model.rotors._build import axis_planes, finite, per_coordinate, positive, transverse_gravity
from stand.model.rotors.structure import LinearRotor, Unbalance, sign_changes

__all__ = ["flexible_shaft", "shaft_natural_frequencies", "shaft_receptance", "shaft_criterion",
           "shaft_working_ranges", "optimal_positions"]


def _position(name: str, z: float, l: float) -> float:
    """An axial position z [m] strictly between the supports of a shaft of length l."""
    v = finite(name, z, "m")
    if not 0.0 < v < l:
        raise ValueError(f"{name} must lie strictly between the supports, 0 < z < l = {l} m, "
                         f"got {z!r} m")
    return v


def _n_modes(n) -> int:
    if int(n) != n or n < 1:
        raise ValueError(f"n_modes must be a positive integer [-], got {n!r}")
    return int(n)


def shaft_natural_frequencies(length: float, mass_per_length: float, EJ: float,
                              n_modes: int) -> np.ndarray:
    """(2.162): ``w_j = (pi j / l)^2 sqrt(EJ/m)`` [rad/s], j = 1..n_modes."""
    l = positive("length", length, "m")
    m = positive("mass_per_length", mass_per_length, "kg/m")
    ej = positive("EJ", EJ, "N m^2")
    j = np.arange(1, _n_modes(n_modes) + 1)
    return (math.pi * j / l) ** 2 * math.sqrt(ej / m)


def flexible_shaft(length: float, mass_per_length: float, EJ: float, n_modes: int = 20,
                   damping_ratio: "float | Sequence[float] | None" = None,
                   planes: Optional[dict] = None,
                   unbalances: Sequence = (), g=(0.0, 0.0)) -> LinearRotor:
    """Simply supported uniform shaft (model 2.8) truncated to ``n_modes`` modes.

    Parameters
    ----------
    length : float
        l [m].
    mass_per_length : float
        m [kg/m].
    EJ : float
        Bending stiffness [N m^2].
    n_modes : int, optional
        J, the number of modes per direction (2J coordinates).  The criterion's
        critical speeds converge like J^-3.  J = 30 gives about 4 significant digits
        of the table-6.2 edges below 25 w_1, and J = 100 about 6.
    damping_ratio : float or sequence of J floats, optional
        Modal viscous damping ratios zeta_j [-] (not in the book; default None = 0);
        a scene file takes a number or a list of J numbers.
    planes : dict of str -> float, optional
        Named planes at axial positions z [m], 0 < z < l; default ``{"balancer": l/2}``.
    unbalances : sequence of Unbalance or (plane, s [kg m], angle [rad]) tuples, optional
        The shaft's unbalances, each in one of the named planes; a dict
        ``{plane: s}`` or ``{plane: [s, angle]}`` is accepted too (scene files).
    g : (float, float), optional
        Transverse gravity (g_x, g_y) [m/s^2] (horizontal shaft).  The distributed
        weight's modal forces are ``m g l (1 - cos(pi j)) / (pi j)``.

    Returns
    -------
    LinearRotor
        Coordinates ``qx_j [m]`` then ``qy_j [m]``; the planes as given.
    """
    l = positive("length", length, "m")
    m = positive("mass_per_length", mass_per_length, "kg/m")
    J = _n_modes(n_modes)
    w = shaft_natural_frequencies(l, m, EJ, J)
    zeta = per_coordinate("damping_ratio", 0.0 if damping_ratio is None else damping_ratio, J, "-")
    mj = 0.5 * m * l                                   # modal mass of sin(pi j z / l)
    two = np.eye(2)
    M = mj * np.eye(2 * J)
    K = np.kron(two, np.diag(mj * w * w))
    D = np.kron(two, np.diag(2.0 * zeta * mj * w))
    j = np.arange(1, J + 1)
    maps = axis_planes({"balancer": 0.5 * l} if planes is None else planes,
                       lambda z: np.kron(two, np.sin(math.pi * j * z / l)[None, :]),
                       lambda name, z: _position(f"planes[{name!r}]", z, l))
    if isinstance(unbalances, dict):        # scene-file form {plane: s} or {plane: [s, angle]}
        unbalances = [(p, *np.atleast_1d(np.asarray(v, dtype=float)).tolist())
                      for p, v in unbalances.items()]
    unb = tuple(u if isinstance(u, Unbalance) else Unbalance(str(u[0]), float(u[1]),
                                                             float(u[2]) if len(u) > 2 else 0.0)
                for u in unbalances)
    gx, gy = transverse_gravity(g)
    gm = m * l * (1.0 - np.cos(math.pi * j)) / (math.pi * j)
    return LinearRotor(
        name="flexible_shaft",
        coords=tuple(f"qx{k} [m]" for k in j) + tuple(f"qy{k} [m]" for k in j),
        M=M, G=np.zeros((2 * J, 2 * J)), D=D, K=K,
        planes=maps, unbalances=unb,
        gravity=np.concatenate([gx * gm, gy * gm]),
        gravity_plane=np.array([gx, gy]),
        source=f"Filimonikhin (2004) 2.8, eqs. (2.161)-(2.165) with 1/m, J = {J} modes",
    )


def _sinh_ratio(A, B):
    """sinh(A) sinh(B) / sinh(A + B) for A, B >= 0 without overflow."""
    return 0.5 * np.expm1(-2 * A) * np.expm1(-2 * B) / (-np.expm1(-2 * (A + B)))


def shaft_receptance(omega, a: float, length: float, mass_per_length: float, EJ: float,
                     n_modes: Optional[int] = None):
    """Driving-point receptance G(a, a; w) [m/N] of the undamped shaft.

    ``n_modes=None`` uses the closed form of the module docstring (exact); an integer
    uses the truncated modal sum ``(2/(m l)) sum_j sin^2(pi j a/l) / (w_j^2 - w^2)``.
    ``omega`` [rad/s] may be an array; G is infinite at a resonance not at a node.
    """
    l = positive("length", length, "m")
    m = positive("mass_per_length", mass_per_length, "kg/m")
    ej = positive("EJ", EJ, "N m^2")
    a = _position("a", a, l)
    om = np.abs(np.asarray(omega, dtype=float))
    if n_modes is not None:
        w = shaft_natural_frequencies(l, m, ej, n_modes)
        s2 = np.sin(math.pi * np.arange(1, len(w) + 1) * a / l) ** 2
        x = om[..., None] ** 2
        return 2.0 / (m * l) * np.sum(s2 / (w * w - x), axis=-1)
    k = (m * om * om / ej) ** 0.25
    static = a * a * (l - a) ** 2 / (3.0 * ej * l)
    with np.errstate(divide="ignore", invalid="ignore"):
        kk = np.where(k * l < 1e-2, 1.0, k)      # placeholder where the static value is used
        trig = np.sin(kk * a) * np.sin(kk * (l - a)) / np.sin(kk * l)
        hyp = _sinh_ratio(kk * a, kk * (l - a))
        g = (trig - hyp) / (2.0 * ej * kk ** 3)
    # below k l = 1e-2 (w < 1e-5 w_1) the dynamic correction is ~1e-10 relative
    return np.where(k * l < 1e-2, static, g)


def shaft_criterion(omega, a: float, length: float, mass_per_length: float, EJ: float,
                    n_modes: Optional[int] = None, unbalance: float = 1.0):
    """Criterion (2.165) with the 1/m restored [m]: ``r_bar = v(a) = s w^2 G(a, a; w)``."""
    om = np.asarray(omega, dtype=float)
    return unbalance * om * om * shaft_receptance(om, a, length, mass_per_length, EJ, n_modes)


def shaft_working_ranges(a: float, length: float, mass_per_length: float, EJ: float, hi: float,
                         lo: Optional[float] = None, n_modes: Optional[int] = None,
                         n: int = 20000):
    """``(critical_speeds, ranges)`` [rad/s] of a balancer at z = a [m] over (lo, hi).

    The critical speeds are the sign changes of (2.165): the resonances w_j whose
    mode has no node at a, plus one speed w_j* in (w_j, w_{j+1}) after each.
    Exact closed form by default, or the J-mode truncation (``n_modes``).  ``lo``
    defaults to ``w_1 / 10``.  The poles w_j are bracketed exactly and each zero is
    root-found, so no gap narrower than the grid spacing is stepped over.  Returns the format of
    :func:`stand.model.rotors.structure.working_ranges`.
    """
    w1 = shaft_natural_frequencies(length, mass_per_length, EJ, 1)[0]
    lo = 0.1 * w1 if lo is None else float(lo)
    f = lambda w: shaft_criterion(w, a, length, mass_per_length, EJ, n_modes)   # noqa: E731
    # the poles: every natural frequency in the scan (a mode with a node exactly at a
    # has no pole; sampling around it does no harm).  A mode with a node *near* a has a
    # tiny residue, so the zero after its pole lies very close to it: bracketing the
    # pole is what keeps such a narrow gap (issue 17 part 6).  Between two poles the
    # receptance is increasing in w^2 (a sum of positive residues over w_j^2 - w^2),
    # so there is at most one zero there and the sign check at the samples finds it.
    J = n_modes if n_modes is not None else int(math.sqrt(hi / w1)) + 1
    crit = sign_changes(f, lo, hi, n, poles=shaft_natural_frequencies(length, mass_per_length,
                                                                      EJ, J))
    edges = np.concatenate([[lo], crit, [hi]])
    ranges = []
    for x0, x1 in zip(edges[:-1], edges[1:]):
        if f(math.sqrt(x0 * x1)) < 0:
            ranges.append((float(x0), math.inf if x1 == hi else float(x1)))
    return crit, ranges


def optimal_positions(n: int, length: float) -> np.ndarray:
    """(2.166): balancer positions ``a_k = l k / (n + 1)``, k = 1..n [m], the nodes of
    mode n + 1, for balancing between w_n and w_{n+1} (and through w_{n+1})."""
    if int(n) != n or n < 1:
        raise ValueError(f"n must be a positive integer (number of balancers) [-], got {n!r}")
    l = positive("length", length, "m")
    return l * np.arange(1, int(n) + 1) / (int(n) + 1)
