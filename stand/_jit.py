"""numba's ``njit`` when available and enabled; a transparent no-op otherwise.

Set the environment variable ``STAND_DISABLE_JIT=1`` to run every kernel as plain
Python/numpy (slow; for checking the compiled path).
"""
import os

_DISABLED = os.environ.get("STAND_DISABLE_JIT", "") not in ("", "0")

try:  # pragma: no cover - import guard
    if _DISABLED:
        raise ImportError
    from numba import njit as _njit

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover
    HAVE_NUMBA = False

    def _njit(*args, **kwargs):
        if args and callable(args[0]):
            return args[0]
        return lambda f: f


def njit(*args, **kwargs):
    """``numba.njit`` or identity."""
    return _njit(*args, **kwargs)
