"""The generic kernel's acceleration system, solved in the planes' space.

The weights and body weights of :mod:`stand.model.rotors.coupled_kernel` couple to the rotor
only through their planes: with the stacked plane maps ``T`` (2P x n: T_p's rows, plane by
plane) and force maps ``F`` (likewise) the system for the rotor accelerations ``x = q''`` is ::

    A x = f_s + F^T f_p,        A = M + F^T C T,

where ``f_s`` [N] are the rotor's own forces (stiffness, damping, gyroscopic, gravity),
``f_p`` (2P) the forces the weights and unbalances exert in their planes [N] and ``C``
(2P x 2P, block-diagonal: one 2 x 2 block per plane, [kg]) the weights' plane inertia:
``C_p = sum_j (m_j I - (m_j^2 l_j^2 / J_j) n_j n_j^T) - sum_b R_b`` (R_b: a body's reaction
matrix, :mod:`stand.model.rotors.bodies_kernel`).  Under a torque drive the rotor's angular
acceleration phi'' is one more unknown: ``A x + F^T b phi'' = f``, ``gamma . T x + J_p phi'' =
f_n`` (b, gamma: plane vectors of the unbalances' and the liquids' phi''-terms).

Two ways to solve it, equal to round-off (tests/test_rotors_coupled.py):

* :func:`solve_general`: assemble the n x n (n + 1 with phi'') matrix and eliminate
  (:func:`solve_small`): O(n^3 / 3) per call.  Used when the planes' space is not smaller
  than the rotor's (2P >= n: the planar and spatial rotors).
* :func:`solve_planes`: the Woodbury identity on the constant ``M``.  With ``W = M^-1 F^T``
  (n x 2P) and ``S = T M^-1 F^T`` (2P x 2P) packed once, ``u = M^-1 f_s`` and ::

      (I + C S) z = C (T u + S f_p),      x = u + W (f_p - z),      T x = T u + S (f_p - z)

  (substitute x in A x: the F^T-terms cancel exactly when z solves the 2P system; ``C`` is
  never inverted, so a plane without weights, C_p = 0, or a single point ball, rank one,
  is no special case).  ``det A = det M det(I + C S)``: the small system is singular exactly
  when A is.  Cost O(P n) with a diagonal M (modal models: the flexible shaft) plus a 2P x 2P
  elimination, instead of O(n^3); the plane accelerations ``T x`` that the weights' own
  equations need come out in the plane space too.  phi'' by block elimination: a second
  right-hand side ``C S b`` of the same 2P system.

The rotor's matrices are applied by :func:`matvec_sub` according to their packed kind
(:func:`matrix_kind`: zero, diagonal or dense), so the modal models' diagonal K and D cost
O(n).  Everything works in a flat buffer at given offsets and allocates nothing (inlined into
the right-hand side, called millions of times).
"""
from __future__ import annotations

import numpy as np

from stand._jit import njit

__all__ = ["ZERO", "DIAGONAL", "DENSE", "matrix_kind", "plane_parts", "matvec_sub", "solve_small",
           "solve_general", "solve_planes"]

ZERO, DIAGONAL, DENSE = 0, 1, 2


def matrix_kind(a: np.ndarray) -> int:
    """:data:`ZERO`, :data:`DIAGONAL` or :data:`DENSE` for a square matrix (exact zeros)."""
    if not np.any(a):
        return ZERO
    return DIAGONAL if not np.any(a - np.diag(np.diag(a))) else DENSE


def plane_parts(M: np.ndarray, T: np.ndarray, F: np.ndarray) -> tuple:
    """``(M^-1, kind of M^-1, W = M^-1 F^T, S = T W)`` for :func:`solve_planes` (T, F: the
    stacked 2P x n plane and force maps)."""
    kind = matrix_kind(M)
    Minv = np.diag(1.0 / np.diag(M)) if kind == DIAGONAL else np.linalg.inv(M)
    W = Minv @ F.T
    return Minv, kind, W, T @ W


@njit(cache=True, inline="always", error_model="numpy")
def matvec_sub(buf, ov, sp, oa, kind, c, of, n):
    """``f -= c * (A v)`` (A: n x n row-major at ``sp[oa:]`` of the given kind; v at
    ``buf[ov:]``, f at ``buf[of:]``)."""
    if kind == DIAGONAL:
        for i in range(n):
            buf[of + i] -= c * sp[oa + i * n + i] * buf[ov + i]
    elif kind == DENSE:
        for i in range(n):
            acc = 0.0
            for k in range(n):
                acc += sp[oa + i * n + k] * buf[ov + k]
            buf[of + i] -= c * acc


@njit(cache=True, inline="always", error_model="numpy")
def solve_small(buf, oA, of, ox, n):
    """Solve ``A x = f`` held in the flat buffer (A row-major at ``oA``, f at ``of``, x
    written at ``ox``; A and f overwritten): Gaussian elimination with partial pivoting,
    in place, allocating nothing.  At the stand's sizes LAPACK's call and copy overhead
    (np.linalg.solve) costs more than the arithmetic.  A singular A gives non-finite x (the
    integrator stops)."""
    if n == 2:      # Cramer's rule (the planar rotor, the liquid's paper-001 stand)
        a, b, c, d = buf[oA], buf[oA + 1], buf[oA + 2], buf[oA + 3]
        det = a * d - b * c
        buf[ox] = (d * buf[of] - b * buf[of + 1]) / det
        buf[ox + 1] = (a * buf[of + 1] - c * buf[of]) / det
        return
    for k in range(n):
        p = k
        big = abs(buf[oA + k * n + k])
        for i in range(k + 1, n):
            if abs(buf[oA + i * n + k]) > big:
                big = abs(buf[oA + i * n + k])
                p = i
        if p != k:
            for j in range(k, n):
                tmp = buf[oA + k * n + j]
                buf[oA + k * n + j] = buf[oA + p * n + j]
                buf[oA + p * n + j] = tmp
            tmp = buf[of + k]
            buf[of + k] = buf[of + p]
            buf[of + p] = tmp
        piv = buf[oA + k * n + k]
        for i in range(k + 1, n):
            r = buf[oA + i * n + k] / piv
            if r != 0.0:
                for j in range(k + 1, n):
                    buf[oA + i * n + j] -= r * buf[oA + k * n + j]
                buf[of + i] -= r * buf[of + k]
    for k in range(n - 1, -1, -1):
        acc = buf[of + k]
        for j in range(k + 1, n):
            acc -= buf[oA + k * n + j] * buf[ox + j]
        buf[ox + k] = acc / buf[oA + k * n + k]


@njit(cache=True, inline="always", error_model="numpy")
def solve_general(sp, buf, n, npl, oM, oT, oF, of, ofp, oC, oA, ox, otx, free, ob, og, fn, jp):
    """Assemble ``A = M + F^T C T`` (and the phi'' row and column when ``free``) and
    eliminate; f_s at ``buf[of:]`` (overwritten), f_p, C (P blocks of 4, row-major), b,
    gamma at the given offsets.  Writes x at ``ox`` (phi'' at ``ox + n`` when free) and the
    plane accelerations T x (2P) at ``otx``; returns phi'' (0 without a torque drive)."""
    ld = n + 1 if free else n
    for i in range(n):
        for k in range(n):
            buf[oA + i * ld + k] = sp[oM + i * n + k]
    if free:
        for i in range(ld):
            buf[oA + i * ld + n] = 0.0
            buf[oA + n * ld + i] = 0.0
        buf[oA + n * ld + n] = jp
        buf[of + n] = fn
    for p in range(npl):
        c0, c1, c2, c3 = buf[oC + 4 * p], buf[oC + 4 * p + 1], buf[oC + 4 * p + 2], buf[oC + 4 * p + 3]
        fx, fy = buf[ofp + 2 * p], buf[ofp + 2 * p + 1]
        tb = oT + p * 2 * n
        fb = oF + p * 2 * n
        for i in range(n):
            Fx, Fy = sp[fb + i], sp[fb + n + i]
            buf[of + i] += Fx * fx + Fy * fy
            ax = Fx * c0 + Fy * c2
            ay = Fx * c1 + Fy * c3
            if ax != 0.0 or ay != 0.0:
                for k in range(n):
                    buf[oA + i * ld + k] += ax * sp[tb + k] + ay * sp[tb + n + k]
            if free:
                buf[oA + i * ld + n] += Fx * buf[ob + 2 * p] + Fy * buf[ob + 2 * p + 1]
                buf[oA + n * ld + i] += sp[tb + i] * buf[og + 2 * p] + sp[tb + n + i] * buf[og + 2 * p + 1]
    solve_small(buf, oA, of, ox, ld)
    for r in range(2 * npl):
        acc = 0.0
        for k in range(n):
            acc += sp[oT + r * n + k] * buf[ox + k]
        buf[otx + r] = acc
    return buf[ox + n] if free else 0.0


@njit(cache=True, inline="always", error_model="numpy")
def solve_planes(sp, buf, n, npl, oMi, kMi, oT, oW, oS, of, ofp, oC, oE, ou, ox, otx, free, ob, og,
                 fn, jp):
    """The same solution by the Woodbury identity (module docstring): M^-1 (kind ``kMi``),
    W, S packed at ``oMi``, ``oW``, ``oS``; scratch: the 2P x (2P + 2) system at ``oE``, u
    (n) at ``ou``.  Other arguments and results as :func:`solve_general`'s (f_s is kept)."""
    m = 2 * npl
    w = m + 2                       # columns of the small system: I + C S | r0 | r1
    nr = 2 if free else 1
    for i in range(n):              # u = M^-1 f_s
        buf[ou + i] = 0.0
    matvec_sub(buf, of, sp, oMi, kMi, -1.0, ou, n)
    for r in range(m):              # T u (kept at otx); T u + S f_p and S b: columns m, m + 1
        acc = 0.0
        for k in range(n):
            acc += sp[oT + r * n + k] * buf[ou + k]
        buf[otx + r] = acc
        sb = 0.0
        for c in range(m):
            acc += sp[oS + r * m + c] * buf[ofp + c]
            sb += sp[oS + r * m + c] * buf[ob + c]
        buf[oE + r * w + m] = acc
        buf[oE + r * w + m + 1] = sb
    for p in range(npl):            # rows of plane p: E = I + C_p S, right-hand sides C_p (.)
        c0, c1, c2, c3 = buf[oC + 4 * p], buf[oC + 4 * p + 1], buf[oC + 4 * p + 2], buf[oC + 4 * p + 3]
        rx, ry = oE + 2 * p * w, oE + (2 * p + 1) * w
        for c in range(m + nr):
            if c < m:
                sx, sy = sp[oS + 2 * p * m + c], sp[oS + (2 * p + 1) * m + c]
            else:
                sx, sy = buf[rx + c], buf[ry + c]
            buf[rx + c] = c0 * sx + c1 * sy
            buf[ry + c] = c2 * sx + c3 * sy
        buf[rx + 2 * p] += 1.0
        buf[ry + 2 * p + 1] += 1.0
    # Gaussian elimination with partial pivoting, one or two right-hand sides
    for k in range(m):
        piv_row = k
        big = abs(buf[oE + k * w + k])
        for i in range(k + 1, m):
            if abs(buf[oE + i * w + k]) > big:
                big = abs(buf[oE + i * w + k])
                piv_row = i
        if piv_row != k:
            for j in range(k, m + nr):
                tmp = buf[oE + k * w + j]
                buf[oE + k * w + j] = buf[oE + piv_row * w + j]
                buf[oE + piv_row * w + j] = tmp
        piv = buf[oE + k * w + k]
        for i in range(k + 1, m):
            r = buf[oE + i * w + k] / piv
            if r != 0.0:
                for j in range(k + 1, m + nr):
                    buf[oE + i * w + j] -= r * buf[oE + k * w + j]
    for c in range(m, m + nr):
        for k in range(m - 1, -1, -1):
            acc = buf[oE + k * w + c]
            for j in range(k + 1, m):
                acc -= buf[oE + k * w + j] * buf[oE + j * w + c]
            buf[oE + k * w + c] = acc / buf[oE + k * w + k]
    # d0 = f_p - z0, d1 = b - z1 (columns m, m + 1); phi''; d = d0 - phi'' d1
    for c in range(m):
        buf[oE + c * w + m] = buf[ofp + c] - buf[oE + c * w + m]
        buf[oE + c * w + m + 1] = buf[ob + c] - buf[oE + c * w + m + 1]
    phid = 0.0
    if free:
        num = fn
        den = jp
        for r in range(m):
            t0 = buf[otx + r]
            t1 = 0.0
            for c in range(m):
                t0 += sp[oS + r * m + c] * buf[oE + c * w + m]
                t1 += sp[oS + r * m + c] * buf[oE + c * w + m + 1]
            num -= buf[og + r] * t0
            den -= buf[og + r] * t1
        phid = num / den
        for c in range(m):
            buf[oE + c * w + m] -= phid * buf[oE + c * w + m + 1]
        buf[ox + n] = phid
    for i in range(n):      # x = u + W d
        acc = buf[ou + i]
        for c in range(m):
            acc += sp[oW + i * m + c] * buf[oE + c * w + m]
        buf[ox + i] = acc
    for r in range(m):      # T x = T u + S d
        acc = buf[otx + r]
        for c in range(m):
            acc += sp[oS + r * m + c] * buf[oE + c * w + m]
        buf[otx + r] = acc
    return phid
