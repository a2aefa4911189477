"""Compiled right-hand sides, selected by an integer model kind at compile time.

The compiled integrators (:mod:`stand.integrate.dop853`, :mod:`stand.integrate.rk4`)
call :func:`rhs` with a model kind instead of taking the right-hand side as a
first-class function argument, so that numba can cache the compiled loops on
disk (first-class function arguments defeat the cache).  The loops ask for the
kind as a compile-time constant (``literally``), and :func:`rhs` resolves, while
compiling, to that kind's right-hand side only: a planar-rotor run compiles the
planar right-hand side and never the generic one (about ten times larger), and
each kind's loop is compiled and cached on its own.

A new rotor or weight model adds its kind to :data:`RHS`.
"""
import importlib

from ._jit import literally, njit, when_numba

PLANAR = 0
GENERIC = 1   #: any LinearRotor with weights in any planes (stand.rotors.coupled)

#: model kind -> (module, function) of its compiled right-hand side
#: ``f(t, y, dy, sp, wt, prog)`` (writes dy); imported when the kind is first used
RHS = {PLANAR: ("stand.planar", "rhs_planar"),
       GENERIC: ("stand.rotors.coupled_kernel", "rhs_generic")}

KIND_NAMES = {PLANAR: "planar", GENERIC: "generic"}


def rhs_of(kind: int):
    """The right-hand-side function of model ``kind``."""
    try:
        module, name = RHS[kind]
    except KeyError:
        raise ValueError(f"model kind {kind!r}: one of {sorted(RHS)}") from None
    return getattr(importlib.import_module(module), name)


def rhs(kind, t, y, dy, sp, wt, prog):
    """Evaluate the right-hand side of model ``kind`` into ``dy`` (in compiled code: the
    kind's function itself, chosen while compiling)."""
    rhs_of(kind)(t, y, dy, sp, wt, prog)


@njit(cache=True, error_model="numpy")
def evaluate(kind, t, y, dy, sp, wt, prog):
    """:func:`rhs` compiled for calls from Python (one specialisation per kind)."""
    literally(kind)
    rhs(kind, t, y, dy, sp, wt, prog)


def _register(numba):
    from numba.core import types
    from numba.extending import overload

    @overload(rhs, jit_options={"error_model": "numpy"})
    def _rhs_of_literal_kind(kind, t, y, dy, sp, wt, prog):
        if not isinstance(kind, types.IntegerLiteral):
            raise numba.core.errors.TypingError(
                "stand.kernels.rhs: the model kind must be a compile-time constant "
                "(numba.literally(kind) in the calling kernel)")
        f = rhs_of(kind.literal_value)
        f = getattr(f, "dispatcher", f)   # a stand-in made before numba was imported

        def impl(kind, t, y, dy, sp, wt, prog):
            f(t, y, dy, sp, wt, prog)

        return impl


when_numba(_register)
