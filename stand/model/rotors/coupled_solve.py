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
  elimination (Cramer's rule for one plane), instead of O(n^3); the plane accelerations ``T x`` that the weights' own
  equations need come out in the plane space too.  phi'' by block elimination: a second
  right-hand side ``C S b`` of the same 2P system.

The rotor's matrices are applied by :func:`rotor_forces` according to their packed kind
(:func:`matrix_kind`: zero, diagonal or dense), so the modal models' diagonal K and D cost
O(n).  Everything works in a flat buffer at given offsets and allocates nothing (called from
the right-hand side, millions of times); the loops run over views of it, so it is compiled
without numba's reference counting (``_nrt=False``, as :mod:`stand.model.kernels` does),
which would count every view.  Called, not inlined at numba's IR level: inlining the right-
hand side and its helpers into each of the compiled loops (DOP853 three times, RK4 four,
Jacobian, evaluation) cost minutes of compilation per install for no measurable speed.
"""
from __future__ import annotations

import numpy as np

from stand._jit import njit

__all__ = ["ZERO", "DIAGONAL", "DENSE", "matrix_kind", "row_ranges", "plane_parts", "rotor_forces",
           "solve_small", "solve_general", "solve_planes"]

ZERO, DIAGONAL, DENSE = 0, 1, 2


def matrix_kind(a: np.ndarray) -> int:
    """:data:`ZERO`, :data:`DIAGONAL` or :data:`DENSE` for a square matrix (exact zeros)."""
    if not np.any(a):
        return ZERO
    return DIAGONAL if not np.any(a - np.diag(np.diag(a))) else DENSE


def row_ranges(T: np.ndarray) -> np.ndarray:
    """Per row of T, the first and one past the last nonzero column (0, 0 for a zero row),
    flattened: the ranges :func:`t_dot` sums over."""
    out = np.zeros((T.shape[0], 2))
    for r, row in enumerate(T):
        nz = np.flatnonzero(row)
        if nz.size:
            out[r] = nz[0], nz[-1] + 1
    return out.ravel()


def plane_parts(M: np.ndarray, T: np.ndarray, F: np.ndarray) -> tuple:
    """``(M^-1, kind of M^-1, W = M^-1 F^T, S = T W)`` for :func:`solve_planes` (T, F: the
    stacked 2P x n plane and force maps)."""
    kind = matrix_kind(M)
    Minv = np.diag(1.0 / np.diag(M)) if kind == DIAGONAL else np.linalg.inv(M)
    W = Minv @ F.T
    return Minv, kind, W, T @ W


@njit(cache=True, error_model="numpy", _nrt=False)
def dot(sp, oa, buf, ov, lo, hi):
    """``sum_k sp[oa + k] buf[ov + k]`` over lo <= k < hi, in four partial sums: without
    fast-math the compiler keeps a sum's order, so one accumulator is a chain of dependent
    multiply-adds; four run in parallel.  Through views indexed from 0: an index the
    compiler cannot prove non-negative costs five instructions of negative-index handling
    per access (here and in the other hot loops of the generic kernel)."""
    a = sp[oa + lo:oa + hi]
    b = buf[ov + lo:ov + hi]
    a0 = a1 = a2 = a3 = 0.0
    m = hi - lo
    for k in range(0, m - 3, 4):
        a0 += a[k] * b[k]
        a1 += a[k + 1] * b[k + 1]
        a2 += a[k + 2] * b[k + 2]
        a3 += a[k + 3] * b[k + 3]
    for k in range(m - m % 4, m):
        a0 += a[k] * b[k]
    return (a0 + a1) + (a2 + a3)


@njit(cache=True, error_model="numpy", _nrt=False)
def t_dot(sp, oT, oTr, r, n, buf, ov):
    """Row r of the stacked plane maps times the vector at ``buf[ov:]``, over the row's
    nonzero columns (``sp[oTr + 2 r]`` to ``sp[oTr + 2 r + 1]``, :func:`row_ranges`: a
    modal model's x rows touch the x modes only)."""
    lo, hi = int(sp[oTr + 2 * r]), int(sp[oTr + 2 * r + 1])
    return dot(sp, oT + r * n, buf, ov, lo, hi)


@njit(cache=True, error_model="numpy", _nrt=False)
def mat_row(sp, oa, kind, i, n, buf, ov):
    """Row i of the n x n matrix at ``sp[oa:]`` (of the given kind) times the vector at
    ``buf[ov:]``."""
    if kind == DIAGONAL:
        return sp[oa + i * (n + 1)] * buf[ov + i]
    if kind == DENSE:
        return dot(sp, oa + i * n, buf, ov, 0, n)
    return 0.0


@njit(cache=True, error_model="numpy", _nrt=False)
def rotor_forces(sp, buf, n, oGR, oK, kK, oD, kD, oG, kG, Om, oq, oqd, of):
    """The rotor's own forces ``f_s = g - K q - (D + Omega G) q'`` [N] at ``buf[of:]`` (K, D, G
    applied by their kinds; q, q' at ``buf[oq:]``, ``buf[oqd:]``)."""
    f = buf[of:of + n]
    grav = sp[oGR:oGR + n]
    for i in range(n):
        f[i] = grav[i] - mat_row(sp, oK, kK, i, n, buf, oq) - mat_row(sp, oD, kD, i, n, buf, oqd) \
            - Om * mat_row(sp, oG, kG, i, n, buf, oqd)


@njit(cache=True, error_model="numpy", _nrt=False)
def minv_apply(sp, oa, kind, n, buf, of, ou):
    """``u = M^-1 f`` (M^-1 at ``sp[oa:]``, diagonal or dense) into ``buf[ou:]``."""
    u = buf[ou:ou + n]
    for i in range(n):
        u[i] = mat_row(sp, oa, kind, i, n, buf, of)


@njit(cache=True, error_model="numpy", _nrt=False)
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


@njit(cache=True, error_model="numpy", _nrt=False)
def solve_general(sp, buf, n, npl, oM, oT, oTr, oF, of, ofp, oC, oA, ox, otx, free, ob, og, fn, jp):
    """Assemble ``A = M + F^T C T`` (and the phi'' row and column when ``free``) and
    eliminate; f_s at ``buf[of:]`` (overwritten), f_p, C (P blocks of 4, row-major), b,
    gamma at the given offsets.  Writes x at ``ox`` (phi'' at ``ox + n`` when free) and the
    plane accelerations T x (2P) at ``otx`` of the planes with weights (C_p != 0; the others'
    are not needed); returns phi'' (0 without a torque drive)."""
    ld = n + 1 if free else n
    A = buf[oA:oA + ld * ld]
    f = buf[of:of + ld]
    Mv = sp[oM:oM + n * n]
    for i in range(n):
        for k in range(n):
            A[i * ld + k] = Mv[i * n + k]
    if free:
        for i in range(ld):
            A[i * ld + n] = 0.0
            A[n * ld + i] = 0.0
        A[n * ld + n] = jp
        f[n] = fn
    for p in range(npl):
        c0, c1, c2, c3 = buf[oC + 4 * p], buf[oC + 4 * p + 1], buf[oC + 4 * p + 2], buf[oC + 4 * p + 3]
        fx, fy = buf[ofp + 2 * p], buf[ofp + 2 * p + 1]
        bx, by = buf[ob + 2 * p], buf[ob + 2 * p + 1]
        gx, gy = buf[og + 2 * p], buf[og + 2 * p + 1]
        Tx, Ty = sp[oT + 2 * p * n:oT + 2 * p * n + n], sp[oT + 2 * p * n + n:oT + 2 * p * n + 2 * n]
        Fx, Fy = sp[oF + 2 * p * n:oF + 2 * p * n + n], sp[oF + 2 * p * n + n:oF + 2 * p * n + 2 * n]
        active = c0 != 0.0 or c1 != 0.0 or c2 != 0.0 or c3 != 0.0
        for i in range(n):
            f[i] += Fx[i] * fx + Fy[i] * fy
            if active:
                ax = Fx[i] * c0 + Fy[i] * c2
                ay = Fx[i] * c1 + Fy[i] * c3
                for k in range(n):
                    A[i * ld + k] += ax * Tx[k] + ay * Ty[k]
            if free:
                A[i * ld + n] += Fx[i] * bx + Fy[i] * by
                A[n * ld + i] += Tx[i] * gx + Ty[i] * gy
    solve_small(buf, oA, of, ox, ld)
    for p in range(npl):
        if buf[oC + 4 * p] != 0.0 or buf[oC + 4 * p + 1] != 0.0 or buf[oC + 4 * p + 2] != 0.0 \
                or buf[oC + 4 * p + 3] != 0.0:
            buf[otx + 2 * p] = t_dot(sp, oT, oTr, 2 * p, n, buf, ox)
            buf[otx + 2 * p + 1] = t_dot(sp, oT, oTr, 2 * p + 1, n, buf, ox)
    return buf[ox + n] if free else 0.0


@njit(cache=True, error_model="numpy", _nrt=False)
def solve_planes(sp, buf, n, npl, oMi, kMi, oT, oTr, oW, oS, of, ofp, oC, oE, ou, ox, otx, free, ob, og,
                 fn, jp):
    """The same solution by the Woodbury identity (module docstring): M^-1 (kind ``kMi``),
    W, S packed at ``oMi``, ``oW``, ``oS``; scratch: the 2P x (2P + 2) system at ``oE``, u
    (n) at ``ou``.  Other arguments and results as :func:`solve_general`'s (f_s is kept;
    f_p is overwritten)."""
    m = 2 * npl
    w = m + 2                       # columns of the small system: I + C S | r0 | r1
    nr = 2 if free else 1
    E = buf[oE:oE + m * w]
    S = sp[oS:oS + m * m]
    fp, b, g, tx = buf[ofp:ofp + m], buf[ob:ob + m], buf[og:og + m], buf[otx:otx + m]
    minv_apply(sp, oMi, kMi, n, buf, of, ou)       # u = M^-1 f_s
    u = buf[ou:ou + n]
    for r in range(m):              # T u (kept in tx); T u + S f_p and S b: columns m, m + 1
        acc = t_dot(sp, oT, oTr, r, n, buf, ou)
        tx[r] = acc
        sb = 0.0
        for c in range(m):
            acc += S[r * m + c] * fp[c]
            sb += S[r * m + c] * b[c]
        E[r * w + m] = acc
        E[r * w + m + 1] = sb
    for p in range(npl):            # rows of plane p: E = I + C_p S, right-hand sides C_p (.)
        c0, c1, c2, c3 = buf[oC + 4 * p], buf[oC + 4 * p + 1], buf[oC + 4 * p + 2], buf[oC + 4 * p + 3]
        rx, ry = 2 * p * w, (2 * p + 1) * w
        for c in range(m + nr):
            if c < m:
                sx, sy = S[2 * p * m + c], S[(2 * p + 1) * m + c]
            else:
                sx, sy = E[rx + c], E[ry + c]
            E[rx + c] = c0 * sx + c1 * sy
            E[ry + c] = c2 * sx + c3 * sy
        E[rx + 2 * p] += 1.0
        E[ry + 2 * p + 1] += 1.0
    if m == 2:      # one plane: Cramer's rule (E is the identity plus the weights' small part)
        det = E[0] * E[w + 1] - E[1] * E[w]
        for c in range(m, m + nr):
            r0, r1 = E[c], E[w + c]
            E[c] = (E[w + 1] * r0 - E[1] * r1) / det
            E[w + c] = (E[0] * r1 - E[w] * r0) / det
    else:           # Gaussian elimination with partial pivoting, one or two right-hand sides
        for k in range(m):
            piv_row = k
            big = abs(E[k * w + k])
            for i in range(k + 1, m):
                if abs(E[i * w + k]) > big:
                    big = abs(E[i * w + k])
                    piv_row = i
            if piv_row != k:
                for j in range(k, m + nr):
                    tmp = E[k * w + j]
                    E[k * w + j] = E[piv_row * w + j]
                    E[piv_row * w + j] = tmp
            piv = E[k * w + k]
            for i in range(k + 1, m):
                r = E[i * w + k] / piv
                if r != 0.0:
                    for j in range(k + 1, m + nr):
                        E[i * w + j] -= r * E[k * w + j]
        for c in range(m, m + nr):
            for k in range(m - 1, -1, -1):
                acc = E[k * w + c]
                for j in range(k + 1, m):
                    acc -= E[k * w + j] * E[j * w + c]
                E[k * w + c] = acc / E[k * w + k]
    # d = f_p - z0 (in f_p's place; it is spent), d1 = b - z1 (column m + 1); phi'';
    # d -= phi'' d1
    for c in range(m):
        fp[c] -= E[c * w + m]
        E[c * w + m + 1] = b[c] - E[c * w + m + 1]
    phid = 0.0
    if free:
        num = fn
        den = jp
        for r in range(m):
            t0 = tx[r]
            t1 = 0.0
            for c in range(m):
                t0 += S[r * m + c] * fp[c]
                t1 += S[r * m + c] * E[c * w + m + 1]
            num -= g[r] * t0
            den -= g[r] * t1
        phid = num / den
        for c in range(m):
            fp[c] -= phid * E[c * w + m + 1]
        buf[ox + n] = phid
    x = buf[ox:ox + n]
    Wm = sp[oW:oW + n * m]
    for i in range(n):      # x = u + W d
        acc = u[i]
        for c in range(m):
            acc += Wm[i * m + c] * fp[c]
        x[i] = acc
    for r in range(m):      # T x = T u + S d
        acc = tx[r]
        for c in range(m):
            acc += S[r * m + c] * fp[c]
        tx[r] = acc
    return phid
