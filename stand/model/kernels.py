"""Compiled right-hand sides, selected by an integer model kind at compile time.

The compiled integrators (:mod:`stand.integrate.dop853`, :mod:`stand.integrate.rk4`)
call :func:`derivatives` with a model kind instead of taking the right-hand side as a
first-class function argument, so that numba can cache the compiled loops on
disk (first-class function arguments defeat the cache).  The loops ask for the
kind as a compile-time constant (``literally``), and :func:`derivatives` resolves, while
compiling, to that kind's right-hand side only: a planar-rotor run compiles the
planar right-hand side and never the generic one (about ten times larger), and
each kind's loop is compiled and cached on its own.

A new rotor or weight model adds its kind to :data:`RHS`.
"""
import importlib

from stand._jit import literally, njit, when_numba

PLANAR = 0
GENERIC = 1   #: any LinearRotor with weights in any planes (stand.integrate.coupled)

#: model kind -> (module, function) of its compiled right-hand side
#: ``f(t, y, dy, sp, wt, prog)`` (writes dy); imported when the kind is first used
RHS = {PLANAR: ("stand.model.planar", "rhs_planar"),
       GENERIC: ("stand.model.rotors.coupled_kernel", "rhs_generic")}

KIND_NAMES = {PLANAR: "planar", GENERIC: "generic"}


def kernel_of(kind: int):
    """The right-hand-side function of model ``kind``."""
    try:
        module, name = RHS[kind]
    except KeyError:
        raise ValueError(f"model kind {kind!r}: one of {sorted(RHS)}") from None
    return getattr(importlib.import_module(module), name)


def derivatives(kind, t, y, dy, sp, wt, prog):
    """Evaluate the right-hand side of model ``kind`` into ``dy`` (in compiled code: the
    kind's function itself, chosen while compiling)."""
    kernel_of(kind)(t, y, dy, sp, wt, prog)


@njit(cache=True, error_model="numpy", _nrt=False)
def evaluate(kind, t, y, dy, sp, wt, prog):
    """:func:`derivatives` compiled for calls from Python (one specialisation per kind).

    Without reference counting, as the DOP853 loop (the right-hand sides allocate nothing)."""
    literally(kind)
    derivatives(kind, t, y, dy, sp, wt, prog)


def _register(numba):
    from numba.core import types
    from numba.core.imputils import lower_builtin
    from numba.core.typing.templates import AbstractTemplate, infer_global, signature

    def kernel_type(context, kind):
        f = kernel_of(kind.literal_value)
        return context.resolve_value_type(getattr(f, "dispatcher", f))  # a stand-in: its dispatcher

    # The call goes straight to the kind's right-hand side, typed and lowered here as numba
    # lowers a call of a compiled function: no function of its own in between (an overload's
    # implementation is compiled once per caller's set of flags, each with its own machine
    # code of the whole right-hand side).  The planar right-hand side is compiled with
    # forceinline (stand.model.planar): LLVM inlines it into the calling loop (a call, its
    # arrays passed field by field, cost 5 % of a run, and inlined the loop's stage sums
    # vectorise).  Any other kind: a call (the generic right-hand side is ten times larger; it
    # allocates nothing, so compiled without reference counting: the atomic counts of its
    # array arguments cost a fifth of a 20-coordinate call, issue 33).
    @infer_global(derivatives)
    class _Derivatives(AbstractTemplate):
        def generic(self, args, kws):
            if kws or not args or not isinstance(args[0], types.IntegerLiteral):
                raise numba.core.errors.TypingError(
                    "stand.model.kernels.derivatives: the model kind must be a compile-time "
                    "constant (numba.literally(kind) in the calling kernel)")
            kernel_type(self.context, args[0]).get_call_type(self.context, args[1:], {})
            return signature(types.none, *args)

    @lower_builtin(derivatives, types.IntegerLiteral, types.VarArg(types.Any))
    def _call(context, builder, sig, args):
        rhs = kernel_type(context.typing_context, sig.args[0])
        rsig = rhs.get_call_type(context.typing_context, sig.args[1:], {})
        context.get_function(rhs, rsig)(builder, args[1:])
        return context.get_dummy_value()


when_numba(_register)
