"""The numpy twin of :mod:`vision._blur_kernel`, for when numba is missing or disabled.

:func:`_normal_equations_numpy` gives the same numbers as the compiled loops
(:func:`vision._blur_kernel._normal_equations_loops`, to rounding:
``tests/test_video_track.py``) by the separable sums as matrix products over the
patch -- about 5-10x slower, numpy's per-call overhead dominating on small blobs.
:func:`python_fit` is :func:`vision._blur_kernel.fit_loops` as plain Python bound
to it (the ``engine="numpy"`` of :func:`vision.blur.fit_blurred_spot`).
:func:`_profile` is also the dense model image of :mod:`vision.blur`.
"""
from __future__ import annotations

import functools
import math
import types

import numpy as np

from . import _blur_kernel as _k
from ._blur_kernel import NP, _SQRT2PI

__all__ = ["python_fit"]


def _profile(d, s):
    """Pixel-integrated 1-D profile sqrt(2 pi) s [Phi((d+1/2)/s) - Phi((d-1/2)/s)] at offsets
    ``d`` = pixel - point [px], its derivative with respect to the point, and to ``s``."""
    from scipy.special import ndtr

    a = (d + 0.5) / s
    b = (d - 0.5) / s
    ea = np.exp(-0.5 * a * a)
    eb = np.exp(-0.5 * b * b)
    g = _SQRT2PI * s * (ndtr(a) - ndtr(b))
    return g, eb - ea, g / s - (ea * a - eb * b)


def _normal_equations_numpy(patch, pi, pj, clipped, level, sat_eff, p, n, want_jac, want_meat):
    """The same numbers as :func:`vision._blur_kernel._normal_equations_loops` by matrix products over the patch
    (the separable sums): ``(cost, J^T J, J^T r, sum r^2 J J^T)``, None where not asked."""
    H, W = patch.shape
    u, v, w, pu, pv = _k.path(p[0], p[1], p[2], p[3], p[4], p[5], p[6], n)
    A = math.exp(p[7])
    s = math.exp(p[8])
    rows = np.arange(H, dtype=float)
    cols = np.arange(W, dtype=float)
    gu, dgu, su = _profile(cols[None, :] - u[:, None], s)      # (n, W)
    gv, dgv, sv = _profile(rows[None, :] - v[:, None], s)      # (n, H)
    wc = w[:, None]
    gu, dgu, su = gu * wc, dgu * wc, su * wc
    base = gv.T @ gu
    full = (level + A * base)[pi, pj]
    d = patch[pi, pj]
    over = clipped & (full >= sat_eff)
    r = np.where(clipped, np.where(over, 0.0, sat_eff - full), d - full)
    cost = float(r @ r)
    if not want_jac:
        return cost, None, None, None
    J = np.empty((NP, pi.size))
    J[0] = A * (gv.T @ dgu)[pi, pj]
    J[1] = A * (dgv.T @ gu)[pi, pj]
    for a in range(5):
        J[2 + a] = A * ((gv.T * pu[a][None, :]) @ dgu + (dgv.T * pv[a][None, :]) @ gu)[pi, pj]
    J[7] = A * base[pi, pj]
    J[8] = A * s * (gv.T @ su + sv.T @ gu)[pi, pj]
    J[:, over] = 0.0
    return cost, J @ J.T, J @ r, ((J * (r * r)) @ J.T if want_meat else None)


def _normal_equations_numpy_into(patch, pi, pj, clipped, level, sat_eff, p, n, want_jac,
                                 want_meat, JTJ, g, MJ):
    """:func:`_normal_equations_numpy` with the signature of the loops (results written into
    ``JTJ``, ``g``, ``MJ``; returns the cost)."""
    cost, a, b, c = _normal_equations_numpy(patch, pi, pj, clipped, level, sat_eff, p, n,
                                            want_jac, want_meat)
    if want_jac:
        JTJ[:, :] = a
        g[:] = b
        if want_meat:
            MJ[:, :] = c
    return cost


@functools.lru_cache(maxsize=1)
def python_fit():
    """:func:`vision._blur_kernel.fit_loops` and the helpers it calls as plain Python bound to
    the numpy normal equations (whatever the kernel module's globals hold after compiling)."""
    env = dict(vars(_k))
    env["_EVALUATE"] = _normal_equations_numpy_into
    env["path"] = _k._PY["path"]
    for name in ("n_points", "_bound", "_evaluate", "_copy", "_cholesky_solve", "_lm", "_where",
                 "_score", "_centre_cov"):
        env[name] = types.FunctionType(_k._PY[name].__code__, env, name)
    return types.FunctionType(_k.fit_loops.__code__, env, "fit_loops")
