"""Compiled right-hand sides, selected by an integer model kind.

The compiled integrator calls :func:`rhs` with a model kind instead of taking
the right-hand side as a first-class function argument, so that numba can
cache the compiled loop on disk (first-class function arguments defeat the
cache and cost a few seconds of compilation in every process).  A new rotor or
weight model adds its kind here.
"""
from ._jit import njit
from .planar import rhs_planar
from .rotors.coupled_kernel import rhs_generic

PLANAR = 0
GENERIC = 1   #: any LinearRotor with weights in any planes (stand.rotors.coupled)


@njit(cache=True, inline="always", error_model="numpy")
def rhs(kind, t, y, dy, sp, wt, prog):
    """Evaluate the right-hand side of model ``kind`` into ``dy``."""
    if kind == PLANAR:
        rhs_planar(t, y, dy, sp, wt, prog)
    elif kind == GENERIC:
        rhs_generic(t, y, dy, sp, wt, prog)
    else:  # pragma: no cover - guarded in Python
        dy[:] = 0.0
