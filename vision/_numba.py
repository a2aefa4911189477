"""numba for vision's compiled loops, when it is there and allowed.

Every compiled kernel of the package (the blurred-spot fit, its starting values, the
tracker's front) is a plain-Python function compiled on first use; ``STAND_DISABLE_JIT=1``
or ``NUMBA_DISABLE_JIT=1`` (or numba missing) keeps the numpy path.  The kernels' own files
write their ``numba.njit`` options: numba's cache is invalidated per source file, so what
decides the compiled code stays in the file that holds it (this one compiles nothing).
"""
from __future__ import annotations

import functools
import os
import threading

__all__ = ["jit_disabled", "numba_or_none", "cache_missing", "once"]

_LOCK = threading.RLock()


def once(setup):
    """A module's lazy set-up ``setup()`` (it wraps the module's kernels with ``numba.njit``,
    which compiles on their first call behind numba's own lock, and returns them, or None) run
    once under one lock, its result kept: two threads whose first calls meet (two trackers at
    once) both get the finished set-up, never the other's half-built state nor a second ``jit``
    of a jitted function.  A set-up that raised is not run again (it may have replaced some of
    its module's functions): every later call raises the same error."""
    done = []

    @functools.wraps(setup)
    def wrapper():
        if not done:
            with _LOCK:
                if not done:
                    try:
                        done.append(setup())
                    except BaseException as exc:
                        done.append(exc)
        if isinstance(done[0], BaseException):
            raise done[0]
        return done[0]
    return wrapper


def jit_disabled() -> bool:
    """Whether ``STAND_DISABLE_JIT`` or ``NUMBA_DISABLE_JIT`` asks for the numpy path."""
    return any(os.environ.get(k, "") not in ("", "0")
               for k in ("STAND_DISABLE_JIT", "NUMBA_DISABLE_JIT"))


def numba_or_none():
    """The ``numba`` module (imported here, on first use), or None when it is missing or
    disabled (:func:`jit_disabled`)."""
    if jit_disabled():
        return None
    try:
        import numba
    except ImportError:
        return None
    return numba


def cache_missing(dispatcher) -> bool:
    """True when numba is available and ``dispatcher()`` (a function returning a compiled
    numba dispatcher, or None) has no cache file yet: its first call will compile (a best
    guess from numba's cache index; False when that cannot be told)."""
    if jit_disabled():
        return False
    try:
        import importlib.util
        if importlib.util.find_spec("numba") is None:
            return False
        fit = dispatcher()
        return fit is not None and not os.path.exists(fit._cache._cache_file._index_path)
    except Exception:   # noqa: BLE001 - numba's private cache layout: no answer, no message
        return False
