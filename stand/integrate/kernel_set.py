"""The compiled functions the integrator calls for one model kind, from the fastest source.

:func:`kernels` returns, for a model kind, the DOP853 loop and the right-hand
side evaluation from (in this order):

1. the precompiled extension module (:mod:`stand.integrate.precompiled`): no numba
   import, ready in a millisecond;
2. numba's just-in-time compilation with its on-disk cache (the first run after an
   install or an edit of the kernel's sources compiles: said on stderr with the
   elapsed time; about 5 s for the planar rotor).  The command line then builds
   the precompiled module in a detached background process
   (:func:`precompile_in_background`), and ``stand warmup`` builds it in the
   foreground;
3. plain Python/numpy (``STAND_DISABLE_JIT=1``; slow, the tested fallback).

``STAND_KERNELS=jit`` skips 1 and never builds (what the tests use to compare the
two); ``STAND_KERNELS=precompiled`` requires 1, building it now if missing.

Why numba's JIT first: a cold build of the precompiled module compiles the same
kernels plus an object file and numba's C helpers (about 2-3 s more than the JIT
compile), which the first run should not wait for; built afterwards from numba's
cache it costs 3-5 s of background time.
"""
from __future__ import annotations

import os
import sys
import threading
import time
from dataclasses import dataclass
from functools import partial
from typing import Callable

import numpy as np

from stand import _jit
from stand.model.kernels import KIND_NAMES

#: about how long building / JIT-compiling a kind's kernels takes on a 2-core machine [s]
BUILD_SECONDS = {0: 8, 1: 25}
JIT_SECONDS = {0: 5, 1: 20}

_CACHE: dict = {}


@dataclass(frozen=True)
class KernelSet:
    """The integrator's compiled functions for one model kind.

    Attributes
    ----------
    kind : int
    source : str
        ``"precompiled"``, ``"jit"`` or ``"python"``.
    dop853 : callable
        ``dop853(sp, wt, prog, t, y, f, h_abs, t_end, rtol, atol, cap, max_step, ts, k_next,
        out, stats, max_steps, limit) -> (status, t, h_abs, k_next)`` (see
        :func:`stand.integrate.dop853.dop853_loop`).
    evaluate : callable
        ``evaluate(t, y, dy, sp, wt, prog)``: the right-hand side into ``dy``.
    jacobian : callable
        ``jacobian(t, y, f0, sp, wt, prog, J)``: forward-difference Jacobian into ``J``
        (``f0`` = the right-hand side at ``(t, y)``; compiled on first use).
    """

    kind: int
    source: str
    dop853: Callable
    evaluate: Callable
    jacobian: Callable


def _mode() -> str:
    mode = os.environ.get("STAND_KERNELS", "auto").strip().lower() or "auto"
    if mode not in ("auto", "jit", "precompiled"):
        raise ValueError(f"STAND_KERNELS = {mode!r}: one of auto, jit, precompiled")
    return mode


class _Announce:
    """'compiling the ... kernel (one time, about N s)' on stderr when the work lasts more than
    ``delay`` seconds (loading from a cache does not), the elapsed seconds updated in place on
    a terminal, and the time taken at the end."""

    def __init__(self, what: str, about_s: float, delay: float = 2.0):
        self.what, self.about, self.delay = what, about_s, delay
        self._stop = threading.Event()
        self._shown = False

    def _run(self):
        if self._stop.wait(self.delay):
            return
        tty = sys.stderr.isatty()
        msg = f"stand: compiling the {self.what} (one time, about {self.about:.0f} s)..."
        print(msg, end="" if tty else "\n", file=sys.stderr, flush=True)
        self._shown = True
        while tty and not self._stop.wait(1.0):
            print(f"\r{msg} {time.perf_counter() - self.t0:.0f} s", end="", file=sys.stderr,
                  flush=True)

    def __enter__(self):
        self.t0 = time.perf_counter()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()
        if self._shown:
            tail = "done" if exc[0] is None else "failed"
            cr = "\r" if sys.stderr.isatty() else ""
            print(f"{cr}stand: compiling the {self.what}: {tail} in "
                  f"{time.perf_counter() - self.t0:.1f} s" + " " * 24, file=sys.stderr, flush=True)
        return False


def _checked(kind: int, source: str, loop, ev, jac) -> KernelSet:
    """A kernel set around compiled entry points that take exactly C-contiguous float64
    arrays (int64 for the statistics) and plain scalars: inputs are converted, an array written
    in place in another form goes through a C-contiguous copy (never numba's type dispatch,
    which would compile another specialisation, seconds, for the same numbers)."""
    c = np.ascontiguousarray

    def ok(a, dt=np.float64):
        return a.dtype == dt and a.flags.c_contiguous and a.flags.writeable

    def through_copies(call, *pairs):
        """``call(*arrays)`` of the (array, dtype) ``pairs``, each in that form or a copy."""
        use = [a if ok(a, dt) else np.array(a, dt, order="C") for a, dt in pairs]
        result = call(*use)
        for (a, _), u in zip(pairs, use):
            if u is not a:
                a[...] = u
        return result

    F = np.float64

    def dop853(sp, wt, prog, t, y, f, h_abs, t_end, rtol, atol, cap, max_step, ts, k_next, out,
               stats, max_steps, limit):
        return through_copies(lambda y, f, out, stats: loop(
            c(sp, F), c(wt, F), c(prog, F), float(t), y, f, float(h_abs), float(t_end),
            float(rtol), float(atol), c(cap, F), float(max_step), c(ts, F), int(k_next), out,
            stats, int(max_steps), float(limit)), (y, F), (f, F), (out, F), (stats, np.int64))

    # the entry point itself, for a caller that has made every array C-contiguous float64
    # (int64 statistics) and passes plain floats and ints
    dop853.unchecked = loop

    def evaluate(t, y, dy, sp, wt, prog):
        through_copies(lambda dy: ev(float(t), c(y, F), dy, c(sp, F), c(wt, F), c(prog, F)),
                       (dy, F))

    evaluate.unchecked = ev     # as dop853.unchecked

    def jacobian(t, y, f0, sp, wt, prog, J):
        through_copies(lambda J: jac()(float(t), c(y, F), c(f0, F), c(sp, F), c(wt, F),
                                       c(prog, F), J), (J, F))

    return KernelSet(kind, source, dop853, evaluate, jacobian)


def _wrap_precompiled(kind: int, mod) -> KernelSet:
    jac = []

    def jit_jacobian():   # the finite-difference Jacobian (stiff methods) is not precompiled
        if not jac:
            jac.append(_entry_points(kind, jacobian_only=True))
        return jac[0]

    return _checked(kind, "precompiled", mod.dop853, mod.evaluate, jit_jacobian)


def _entry_points(kind: int, jacobian_only: bool = False):
    """numba's compiled entry points of kind ``kind`` (loaded from numba's cache or compiled):
    calling them skips numba's type dispatch, which for a kernel that asks for a literal
    kind costs milliseconds per call (a typing attempt, then the literal retry).  The
    right-hand side's entry point is the kind's function itself, with the argument types the
    DOP853 loop calls it with: compiled with the loop, no function of its own around it
    (:func:`stand.model.kernels.evaluate` would emit the whole right-hand side again)."""
    numba = _jit.import_numba()
    from numba import typeof, types

    from stand.model.kernels import kernel_of
    from stand.integrate.dop853 import dop853_loop
    from stand.integrate.jacobian import jac_fd

    lit = types.literal(kind)
    a1, a2 = typeof(np.zeros(1)), typeof(np.zeros((1, 1)))
    i1, f8, i8 = typeof(np.zeros(1, np.int64)), types.float64, types.int64
    # the entry points take the kind too (its value is compiled in; any int is accepted)
    jac = lambda: partial(jac_fd.compile((lit, f8, a1, a1, a1, a2, a2, a2)), kind)  # noqa: E731
    if jacobian_only:
        return jac()
    loop = dop853_loop.compile((lit, a1, a2, a2, f8, a1, a1, f8, f8, f8, f8, a1, f8, a1, i8, a2,
                                i1, i8, f8, a2))
    rhs = kernel_of(kind)
    ev = getattr(rhs, "dispatcher", rhs).compile((f8, a1, a1, a1, a2, a2))
    del numba
    return _with_workspace(loop, kind), ev, jac


def _with_workspace(loop, kind):
    """``loop(kind, ..., limit, work)`` as the kernel set's ``dop853(..., limit)``."""
    from stand.integrate.dop853 import workspace

    def dop853(sp, wt, prog, t, y, f, *rest):
        return loop(kind, sp, wt, prog, t, y, f, *rest, workspace(y.size))

    return dop853


def _jit_set(kind: int) -> KernelSet:
    """numba's JIT kernels of ``kind`` (compiled now, announced if it takes a while), or the
    plain-Python ones when numba is disabled."""
    if not _jit.HAVE_NUMBA:
        from stand.model.kernels import evaluate
        from stand.integrate.dop853 import dop853_loop
        from stand.integrate.jacobian import jac_fd

        return KernelSet(kind, "python", _with_workspace(dop853_loop, kind),
                         lambda *a: evaluate(kind, *a), lambda *a: jac_fd(kind, *a))
    with _Announce(f"{KIND_NAMES[kind]} kernel", JIT_SECONDS.get(kind, 30)):
        loop, ev, jac = _entry_points(kind)
    compiled = []

    def jacobian_entry():
        if not compiled:
            compiled.append(jac())
        return compiled[0]

    return _checked(kind, "jit", loop, ev, jacobian_entry)


def kernels(kind: int, build: bool = False) -> KernelSet:
    """The integrator's functions for model ``kind`` (module docstring for the order).

    ``build``: compile the precompiled module now if it is missing (``stand warmup``; also
    with ``STAND_KERNELS=precompiled``).  Otherwise a missing module means numba's JIT for
    this process, and the command line starts building the module in the background
    when the command ends (:func:`precompile_in_background`).
    """
    mode = _mode()
    if kind in _CACHE and (_CACHE[kind].source == "precompiled" or not build):
        return _CACHE[kind]
    build = build or mode == "precompiled"
    ks = None
    if _jit.HAVE_NUMBA and mode != "jit":
        from stand.integrate import precompiled

        mod = precompiled.load(kind)
        if mod is None and build:
            why = precompiled.available()
            if why is not None:
                if mode == "precompiled":
                    raise RuntimeError(f"STAND_KERNELS=precompiled: {why}")
            else:
                try:
                    with _Announce(f"{KIND_NAMES[kind]} kernel", BUILD_SECONDS.get(kind, 30)):
                        mod = precompiled.build(kind)
                except Exception as exc:  # noqa: BLE001 - any build failure: use numba's JIT
                    if mode == "precompiled":
                        raise
                    print(f"stand: precompiling failed ({type(exc).__name__}: {exc}); using "
                          "numba's just-in-time compilation", file=sys.stderr)
        if mod is not None:
            ks = _wrap_precompiled(kind, mod)
    if ks is None:
        ks = _jit_set(kind)
        if _jit.HAVE_NUMBA and mode == "auto":
            _JIT_USED.add(kind)
    _CACHE[kind] = ks
    return ks


_JIT_USED: set = set()
_EXTRAS: dict = {}


def extra(jit_function: Callable) -> Callable:
    """A compiled function outside the integrator (e.g. the screen renderer), from the fastest
    source as :func:`kernels`: its precompiled module (no numba import; the extra is named
    ``"<module>:<function>"`` after ``jit_function``, whose module gives
    ``<function>_signature()``), else ``jit_function`` (numba's JIT; the command line then
    builds the module in the background).  ``STAND_KERNELS=precompiled`` builds it now if
    missing."""
    py = getattr(jit_function, "py_func", jit_function)
    name = f"{py.__module__}:{py.__name__}"
    if name in _EXTRAS:
        return _EXTRAS[name]
    mode = _mode()
    f = jit_function
    if _jit.HAVE_NUMBA and mode != "jit":
        from stand.integrate import precompiled

        mod = precompiled.load(name)
        if mod is None and mode == "precompiled":
            with _Announce(f"{name} kernel", 10):
                mod = precompiled.build(name)
        if mod is not None:
            f = getattr(mod, py.__name__)
        elif mode == "auto":
            _JIT_USED.add(name)
    _EXTRAS[name] = f
    return f


def precompile_in_background(say: bool = True) -> list:
    """Start, detached, the build of the precompiled module of every kind this process ran
    on numba's JIT (and that nobody is building): the next command starts without numba.
    The command line calls this when a command ends; returns the kinds' names."""
    if not _JIT_USED or _mode() != "auto":
        return []
    import subprocess

    from stand.integrate import precompiled

    started = []
    for kind in sorted(_JIT_USED, key=str):
        if (precompiled.load(kind) is not None or precompiled.available() is not None
                or precompiled.building(kind)):
            continue
        subprocess.Popen([sys.executable, "-m", "stand.integrate.precompiled",
                          kind if precompiled.is_extra(kind) else precompiled._label(kind)],
                         stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL, start_new_session=True, close_fds=True)
        started.append(precompiled._label(kind))
    _JIT_USED.clear()
    if started and say:
        print(f"stand: precompiling the {', '.join(started)} kernel in the background (later "
              "commands start without compiling)", file=sys.stderr)
    return started
