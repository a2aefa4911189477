"""Issue 17 parts 5-6: the generalised multi-plane criterion in ``stand theory``, the
exact bracketing of the criterion's poles, and the rotor parameters in scene files.

Tolerances: an edge is a speed where the criterion matrix changes definiteness; it is
bracketed by checking the definiteness at w (1 -+ 1e-6) (the edges are found to 1e-13
relative, the matrix is evaluated to ~1e-12).  The narrow flexible-shaft gap is
compared with the zero of the modal sum (2.164)-(2.165) found independently by Brent's
method, to 1e-10 relative (the root-finder's tolerance is 1e-13).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from stand.rotors.flexible import (flexible_shaft, shaft_criterion, shaft_natural_frequencies,
                                   shaft_working_ranges)
from stand.rotors.structure import (criterion_matrices, generalised_working_ranges,
                                    sign_changes, synchronous_poles, working_ranges)

HZ = 2 * math.pi

# ---------------------------------------------------------------- part 6: narrow gap
# 8-mode shaft whose mode 6 is at 925.93 Hz, the balancer 1.5 mm beside mid-span
# (the node of mode 6): the tiny residue puts the zero of (2.165) just below the pole,
# a non-working gap 925.80-925.93 Hz.
L, MPL, EJ8, A8 = 1.0, 10.0, 2681.091002565544, 0.5014951050016175


def _gap_zero():
    wj = shaft_natural_frequencies(L, MPL, EJ8, 8)
    f = lambda w: shaft_criterion(w, A8, L, MPL, EJ8, n_modes=8)     # noqa: E731
    return brentq(f, wj[4] * (1 + 1e-12), wj[5] * (1 - 1e-12), xtol=1e-300, rtol=1e-15), wj[5]


def test_the_fixed_grid_alone_misses_the_gap():
    """The regression: 20 000 geometric points over 1-2000 Hz step over the gap."""
    f = lambda w: shaft_criterion(w, A8, L, MPL, EJ8, n_modes=8)     # noqa: E731
    old = sign_changes(f, HZ * 1.0, HZ * 2000.0, 20000)               # no poles given
    assert not np.any(np.abs(old / HZ - 925.8) < 0.05)


@pytest.mark.parametrize("how", ["closed_form_truncated", "linear_rotor"])
def test_narrow_gap_next_to_a_pole_is_found(how):
    z, pole = _gap_zero()
    assert z / HZ == pytest.approx(925.80, abs=5e-3) and pole / HZ == pytest.approx(925.93, abs=1e-9)
    lo, hi = HZ * 1.0, HZ * 2000.0
    if how == "linear_rotor":
        rot = flexible_shaft(L, MPL, EJ8, 8, planes={"balancer": A8})
        crit, ranges = working_ranges(rot, "balancer", lo, hi)
    else:
        crit, ranges = shaft_working_ranges(A8, L, MPL, EJ8, hi, lo=lo, n_modes=8)
    assert np.min(np.abs(crit - z)) <= 1e-10 * z
    assert np.min(np.abs(crit - pole)) <= 1e-10 * pole
    # the gap: a working range ends at the zero, the next starts at the pole
    ends = [b for _, b in ranges]
    starts = [a for a, _ in ranges]
    assert any(abs(b - z) <= 1e-10 * z for b in ends)
    assert any(abs(a - pole) <= 1e-10 * pole for a in starts)
    # every pole whose mode has no node at the plane is a critical speed
    wj = shaft_natural_frequencies(L, MPL, EJ8, 8)
    for w in wj:
        assert np.min(np.abs(crit - w)) <= 1e-10 * w


def test_synchronous_poles_are_the_natural_frequencies():
    rot = flexible_shaft(L, MPL, EJ8, 8, planes={"balancer": A8})
    np.testing.assert_allclose(synchronous_poles(rot), shaft_natural_frequencies(L, MPL, EJ8, 8),
                               rtol=1e-12)


def test_every_sign_change_of_the_dense_criterion_is_reported():
    """Between two reported critical speeds the criterion keeps its sign (checked on a
    grid 10x denser than the scan, with the poles' sides)."""
    rot = flexible_shaft(L, MPL, EJ8, 8, planes={"balancer": A8})
    lo, hi = HZ * 1.0, HZ * 2000.0
    crit, _ = working_ranges(rot, "balancer", lo, hi)
    edges = np.concatenate([[lo], crit, [hi]])
    for a, b in zip(edges[:-1], edges[1:]):
        x = np.geomspace(a * (1 + 1e-9), b * (1 - 1e-9), 400)
        v = np.sign(shaft_criterion(x, A8, L, MPL, EJ8, n_modes=8))
        assert np.all(v == v[0]), (a / HZ, b / HZ)
