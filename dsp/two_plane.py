"""Two correction planes from the laser spots on two screens (monograph
section 4.3, (4.2)-(4.3)), and two-plane influence-coefficient balancing.

The laser beam runs along the shaft axis.  At a speed above the critical one
the rotor self-centres: its principal central axis lies on the rotation axis
and the shaft axis is displaced from it.  The beam hits a screen placed at
axial distance y_1 and then (moved) at y_2 in the spots M_1(x_1, z_1) and
M_2(x_2, z_2), read in axes fixed to the rotor's angular position (a
synchronised laser or a stroboscope).  The shaft axis is the line (4.2)::

    x = x_1 + (x_2 - x_1) / (y_2 - y_1) (y - y_1),  z likewise,

and (4.3) gives the points O_I, O_II where the principal central axis meets
the correction planes y = 0 and y = h, *relative to the shaft axis*: the
negatives of the shaft-axis points (the printed signs of (4.3) are consistent
with this reading: O_I = -x(0), O_II = -x(h)).

Everything here works on real numbers or on complex phasors (x + i z of a
1X component), since the relations are linear.
"""
from __future__ import annotations

import math

import numpy as np

from .errors import SignalError

__all__ = ["shaft_axis_points", "principal_axis_offsets", "two_plane_unbalances",
           "rotor_frame_phasor", "propagate", "iso_two_plane_allocation"]


def _check_distances(y1, y2):
    y1, y2 = float(y1), float(y2)
    if not (np.isfinite(y1) and np.isfinite(y2)) or y1 == y2:
        raise SignalError(f"screen distances y1 = {y1!r}, y2 = {y2!r} (m): must be finite and "
                          "different")
    return y1, y2


def shaft_axis_points(spot1, y1, spot2, y2, positions):
    """Points of the shaft axis at axial ``positions`` [m] from the line (4.2)
    through the spots ``spot1`` at y1 and ``spot2`` at y2 (real, complex
    x + i z phasors, or arrays of them; metres)."""
    y1, y2 = _check_distances(y1, y2)
    s1 = np.asarray(spot1)
    s2 = np.asarray(spot2)
    slope = (s2 - s1) / (y2 - y1)
    pos = np.asarray(positions, dtype=float)
    return s1[..., None] + slope[..., None] * (pos - y1) if s1.ndim else s1 + slope * (pos - y1)


def principal_axis_offsets(spot1, y1, spot2, y2, h):
    """(4.3): offsets (O_I, O_II) of the principal central axis from the shaft
    axis in the correction planes y = 0 and y = h [m] (the negated shaft-axis
    points)."""
    p = shaft_axis_points(spot1, y1, spot2, y2, [0.0, float(h)])
    return -p[..., 0], -p[..., 1]


def two_plane_unbalances(displacements, influence):
    """Unbalances in two planes from measured displacements and influence coefficients.

    Parameters
    ----------
    displacements : (2,) complex
        1X phasors (x + i y, fixed frame at the synchronised instant) of two
        measurement points [m], e.g. the shaft-axis points in the two
        correction planes from :func:`shaft_axis_points`.
    influence : (2, 2) complex
        ``influence[i, j]``: phasor at point i per unit unbalance (1 kg m, angle
        0) in plane j [m / (kg m)] -- from trial-weight runs or from a model
        (:meth:`stand.model.rotors.LinearRotor.unbalance_response`).

    Returns
    -------
    (2,) complex
        Unbalances s e^{i beta} [kg m] in the two planes (the correction is the
        negative).
    """
    d = np.asarray(displacements, dtype=complex)
    H = np.asarray(influence, dtype=complex)
    if d.shape != (2,) or H.shape != (2, 2):
        raise SignalError(f"displacements must be (2,), influence (2, 2); got {d.shape}, {H.shape}")
    if not np.all(np.isfinite(d)) or not np.all(np.isfinite(H)):
        raise SignalError("displacements / influence: non-finite values")
    if abs(np.linalg.det(H)) < 1e-12 * np.abs(H).max() ** 2:
        raise SignalError("influence matrix is singular: the two planes cannot be separated "
                          "(planes too close, or a node of the response)")
    return np.linalg.solve(H, d)


def rotor_frame_phasor(x, y, rotor_angle, blur_angle=0.0):
    """The synchronous (1X forward) phasor of a point from sparse frames.

    Each frame's position ``x + i y`` [m] (fixed frame) at the rotor angle ``phi``
    [rad] of its mid-exposure is turned into the rotor frame, ``z e^{-i phi}``; at a
    constant speed the steady whirl is one constant there, and what is not
    synchronous (a backward part, noise, a transient's remains) scatters and averages
    out over frames taken at many rotor angles.  ``blur_angle`` [rad]: the angle the
    rotor turns during one exposure; the centroid of the arc is shortened by
    ``sinc``, which is divided out.

    Returns ``(phasor, standard error)``: complex [m], and the standard error of the
    mean [m] per complex component, sqrt(sum |w - mean w|^2 / (2 n (n - 1))) over the
    n >= 3 frames' rotor-frame positions w: the std of the phasor's length and of its
    length times its angle, the sigma of :func:`propagate`.  (Before issue 30 it was the
    complex spread, sqrt 2 larger: RMS(z) 0.72 over 48 draws of a closed form.)
    """
    z = np.asarray(x, float) + 1j * np.asarray(y, float)
    phi = np.asarray(rotor_angle, float)
    ok = np.isfinite(z) & np.isfinite(phi)
    if np.count_nonzero(ok) < 3:
        raise SignalError(f"rotor-frame phasor: {np.count_nonzero(ok)} usable frame(s); needs 3")
    w = z[ok] * np.exp(-1j * phi[ok])
    h = 0.5 * float(blur_angle)
    shrink = math.sin(h) / h if h else 1.0
    Z = w.mean() / shrink
    se = float(np.sqrt(np.mean(np.abs(w - w.mean()) ** 2) / (2 * (w.size - 1)))) / shrink
    return complex(Z), se


def propagate(A, sigma):
    """Standard errors of ``A @ z`` for independent circular errors ``sigma`` of ``z``."""
    A = np.asarray(A, dtype=complex)
    return np.sqrt(np.abs(A) ** 2 @ np.asarray(sigma, float) ** 2)


def iso_two_plane_allocation(permissible, a1, a2, centre=0.0, limits=(0.3, 0.7)):
    """ISO 21940-11 (7.3): the permissible residual unbalance ``permissible`` (any unit)
    split between two planes at axial positions ``a1``, ``a2`` [m] by the lever rule
    about the centre of mass at ``centre``: ``U1 = U b2 / b``, ``U2 = U b1 / b``
    (``b1``, ``b2`` the planes' distances from the centre of mass, ``b = |a2 - a1|``),
    each kept within ``limits`` (the standard's 30 % / 70 %) of ``U`` -- the case of the
    centre of mass outside the middle of the span, or outside the planes.

    Returns ``(U1, U2)``."""
    a1, a2 = _check_distances(a1, a2)
    b = abs(a2 - a1)
    lo, hi = limits
    f1 = abs(a2 - centre) / b
    f2 = abs(a1 - centre) / b
    f1, f2 = (min(max(f, lo), hi) for f in (f1, f2))
    return permissible * f1, permissible * f2
