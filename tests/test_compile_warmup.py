"""What the compile warm-up's savings rest on (benchmarks/README.md, "The test run's warm-up
from a cold cache"): the bisection that replaces numpy's searchsorted in the compiled
right-hand sides, and numba.pycc's C helpers compiled under one name for every module."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

from stand import _jit
from stand.model.programme import row_before


def test_row_before_is_searchsorted_right_minus_one():
    """``row_before`` = ``np.searchsorted(table[:k, 0], tau, "right") - 1`` inside the
    table's range, repeated times (a step change) included."""
    f = getattr(row_before, "py_func", row_before)
    rng = np.random.default_rng(3)
    for k in (2, 3, 7, 40):
        t = np.sort(rng.integers(0, 12, k).astype(float))
        t[0], t[-1] = 0.0, 12.0
        table = np.column_stack([t, rng.normal(size=k), rng.normal(size=k), np.zeros(k)])
        for tau in np.concatenate([rng.uniform(0.0, 12.0, 50), t[:-1]]):
            if tau >= t[-1]:
                continue
            i = f(table, tau, k)
            assert i == np.searchsorted(t, tau, "right") - 1
            assert t[i] <= tau < t[i + 1]


def test_pycc_helpers_are_compiled_under_one_name_for_every_module():
    """Two modules' C helpers have the same macros (so one compiled set serves both) and each
    module's code calls the init function that set defines."""
    if not _jit.HAVE_NUMBA:
        pytest.skip("numba not installed")
    pytest.importorskip("numba.pycc")
    from stand.integrate import precompiled

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cls = precompiled._mixins_class()
        a, b = cls("_stand_planar_0123"), cls("_stand_generic_4567")
    assert a._get_mixin_defines() == b._get_mixin_defines()
    defines = dict(a._get_mixin_defines())
    assert defines["PYCC_MODULE_NAME"] == precompiled._MIXIN_NAME
    assert a._init_function == b._init_function == "pycc_init_" + precompiled._MIXIN_NAME
