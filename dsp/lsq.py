"""Uncertainty of a least-squares fit to a complex record (x + i y), one helper per job.

Shared by the fits of :mod:`dsp.response_fit` (the rigid rotor's run-up) and by any
simulation-based fit that stacks a complex residual ``r`` (N,) as ``[Re r; Im r]`` with its
Jacobian ``J`` (2N, P) in the same row order:

* :func:`covariances` -- the parameters' covariance, white (s^2 (J'J)^-1) and correlated
  (batch-means sandwich), the std of a quantity being the larger of the two;
* :func:`propagated_angle` -- what a measured rotor angle's own error adds (a keyphasor's
  timing, a tachometer's quantum: :class:`dsp.held_display.AngleError` modes);
* :func:`runout_part` -- what an unmodelled 1X probe runout of known size adds;
* :func:`std_of` -- sqrt(g' C g) of one quantity;
* :func:`linear_part` -- the coefficients of a model linear in them (variable projection).

Every (J'J)^-1 here is taken with the columns equilibrated (:func:`normal_inverse`): the
parameters' units span many decades (a natural frequency in rad/s, a sensor's lag in ms^2,
coefficients in m), and an unscaled pseudo-inverse cut directions that were only badly
scaled, not undetermined -- their variance then vanished from every std.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["covariances", "linear_part", "normal_inverse", "propagated_angle", "runout_part",
           "std_of"]


def normal_inverse(J, rcond: float = 1e-13):
    """(J'J)^-1 of a Jacobian ``J`` (M, P) whose columns are all non-zero, as
    D (D J'J D)^+ D with D = diag(1 / |J_j|) (Jacobi column equilibration; e.g. Golub & Van
    Loan, *Matrix Computations*, 4th ed., sec. 3.5.2, and Higham, *Accuracy and Stability of
    Numerical Algorithms*, 2nd ed., sec. 7.3, after van der Sluis, Numer. Math. 14 (1969) 14-23): equal to (J'J)^+ in exact arithmetic when J
    has full rank, but the pseudo-inverse's cut at ``rcond`` then drops only directions
    that are undetermined, not those of a parameter in small units.  (Unscaled, the
    run-up fit with a free sensor response had cond(J'J) ~ 1e24: the cut at 1e-13 removed
    the sensor's freedom from the natural frequency's std, which came out 1e-13 Hz.)"""
    d = 1.0 / np.linalg.norm(J, axis=0)
    Js = J * d
    return d[:, None] * np.linalg.pinv(Js.T @ Js, rcond=rcond, hermitian=True) * d[None, :]


def linear_part(B, z):
    """The complex coefficients ``c`` minimising |z - B c| (the all-zero columns of ``B`` left
    out, their coefficients 0) and the residual ``z - B c`` (LAPACK's ``gelsd``; its normal
    equations, Cholesky-factored, were measured no faster over the run-up fit's tests)."""
    keep = np.any(B[:8] != 0, axis=0)       # a live column is almost always so in its first rows
    if not keep.all():
        keep[~keep] = np.any(B[:, ~keep] != 0, axis=0)
    c = np.zeros(B.shape[1], complex)
    # lstsq copies its operand into LAPACK's layout: the same values give the same bits
    Bk = B if keep.all() and B.dtype == complex else B[:, keep].astype(complex)
    c[keep], *_ = np.linalg.lstsq(Bk, z, rcond=None)
    return c, z - B @ c


def std_of(C, i, g) -> float:
    """sqrt(g' C g) over the parameters i, i + 1, ... (len(g) of them)."""
    k = slice(i, i + g.size)
    return float(math.sqrt(max(g @ C[k, k] @ g, 0.0)))


def propagated_angle(J, dr_dphi, w, t, angle_error):
    """Covariance [parameters^2] the angle's own error adds: with ``delta phi = A xi``,
    ``xi ~ N(0, C)``, the estimate moves by ``-(J'J)^-1 J' (dr/dphi) A xi``."""
    A, C = angle_error.modes(t, w)
    n = dr_dphi.size
    live = np.any(J != 0, axis=0)
    G = J[:n, live].T * dr_dphi.real + J[n:, live].T * dr_dphi.imag        # (P, N)
    S = normal_inverse(J[:, live]) @ (A.T @ G.T).T
    out = np.zeros((J.shape[1], J.shape[1]))
    out[np.ix_(live, live)] = S @ C @ S.T
    return out


def runout_part(J, rot, bound):
    """Covariance [parameters^2] of the estimate's shift by an unmodelled runout
    r e^{i gamma} e^{i phi} with |r| = ``bound`` and gamma uniform: the shifts by the real
    and the imaginary unit runout, S_k = (J'J)^-1 J' d_k (d_k the data's change), each
    with variance bound^2 / 2."""
    live = np.any(J != 0, axis=0)
    D = np.column_stack([np.concatenate((d.real, d.imag)) for d in (rot, 1j * rot)])
    S = normal_inverse(J[:, live]) @ (J[:, live].T @ D)
    out = np.zeros((J.shape[1], J.shape[1]))
    out[np.ix_(live, live)] = 0.5 * bound * bound * (S @ S.T)
    return out


def covariances(J, r, n_par, blocks: int = 40, min_block: int = 16):
    """Parameter covariances of the least-squares fit: (white, correlated).

    White: s^2 (J'J)^-1, right when the residuals are independent.  Correlated: the
    sandwich (J'J)^-1 S (J'J)^-1 with S the sum over ``blocks`` contiguous blocks of the
    outer products of the block's score J'r (batch means: the residuals' correlation
    within a block -- noise that is not white, model error that follows the speed --
    is kept, not averaged away).  The std of a quantity is the larger of the two.
    Blocks are at least ``min_block`` samples long.
    """
    n = r.size
    live = np.any(J != 0, axis=0)
    try:
        Ai = normal_inverse(J[:, live])
    except np.linalg.LinAlgError:
        nan = np.full((n_par, n_par), np.nan)
        return nan, nan
    s2 = float(np.sum(np.abs(r) ** 2)) / max(2 * n - n_par, 1)
    white = np.zeros((n_par, n_par))
    white[np.ix_(live, live)] = s2 * Ai
    score = J[:n, live] * r.real[:, None] + J[n:, live] * r.imag[:, None]     # per sample
    nb = int(min(blocks, max(n // min_block, 2)))
    edges = np.linspace(0, n, nb + 1).astype(int)
    sums = np.add.reduceat(score, edges[:-1], axis=0)
    S = sums.T @ sums * (2 * n / max(2 * n - n_par, 1))
    corr = np.zeros((n_par, n_par))
    corr[np.ix_(live, live)] = Ai @ S @ Ai
    return white, corr
