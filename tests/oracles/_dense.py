"""A dense linear solve on plain Python floats for the oracles' small mass matrices.

``numpy.linalg.solve`` on a 3x3 .. 6x6 system costs ~10 us of call overhead in an oracle's
right-hand side, called ~10^4-10^5 times a run; Gaussian elimination with partial pivoting
on lists of floats costs a fraction of that at this size.  No import of ``stand``.
"""
from __future__ import annotations

import numpy as np

__all__ = ["solve"]


def solve(A, f) -> list:
    """``x`` with ``A x = f``: Gaussian elimination with partial pivoting.

    Parameters
    ----------
    A : list of lists of float, shape (n, n)
        The matrix (any units); not changed.
    f : list of float, length n
        The right-hand side; not changed.

    Returns
    -------
    list of float, length n

    Raises
    ------
    numpy.linalg.LinAlgError
        If a pivot is exactly zero (a singular matrix), as ``numpy.linalg.solve`` does.
    """
    n = len(f)
    A = [list(row) for row in A]
    f = list(f)
    for c in range(n):
        r = max(range(c, n), key=lambda i: abs(A[i][c]))
        if A[r][c] == 0.0:
            raise np.linalg.LinAlgError("Singular matrix")
        if r != c:
            A[c], A[r] = A[r], A[c]
            f[c], f[r] = f[r], f[c]
        piv = A[c]
        for i in range(c + 1, n):
            k = A[i][c] / piv[c]
            if k != 0.0:
                row = A[i]
                for j in range(c + 1, n):
                    row[j] -= k * piv[j]
                f[i] -= k * f[c]
    x = [0.0] * n
    for i in range(n - 1, -1, -1):
        row = A[i]
        acc = f[i]
        for j in range(i + 1, n):
            acc -= row[j] * x[j]
        x[i] = acc / row[i]
    return x
