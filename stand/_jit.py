"""numba's ``njit`` when available and enabled; a transparent no-op otherwise.

Set the environment variable ``STAND_DISABLE_JIT=1`` to run every kernel as plain
Python/numpy (slow; for checking the compiled path).
"""
import hashlib
import os
from pathlib import Path

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


def _invalidate_stale_caches() -> None:
    """Drop numba's on-disk caches when the source of any compiled function changed.

    numba invalidates a cached function only when *its own* file changes, not
    when a function it calls or inlines from another module does (the compiled
    integrator inlines the right-hand side from ``planar.py``): a stale cache
    would silently run old physics.  A hash of every package source that holds
    compiled code (the files that use ``njit``: only they can be called or
    inlined from a compiled function) is kept beside the caches; when it
    differs, the caches are deleted.  Editing a file without compiled code
    (the CLI, the scene reader, the reports) keeps the caches.
    """
    pkg = Path(__file__).resolve().parent
    try:
        files = sorted(f for f in pkg.rglob("*.py") if b"njit" in f.read_bytes())
        digest = hashlib.sha1()
        for f in files:
            digest.update(str(f.relative_to(pkg)).encode())
            digest.update(f.read_bytes())
        h = digest.hexdigest()
        stamp = pkg / "__pycache__" / "numba_sources.sha1"
        if stamp.exists() and stamp.read_text() == h:
            return
        for d in pkg.rglob("__pycache__"):
            for f in list(d.glob("*.nbi")) + list(d.glob("*.nbc")):
                f.unlink()
        stamp.parent.mkdir(exist_ok=True)
        stamp.write_text(h)
    except OSError:  # read-only install: sources cannot change under it
        pass


if HAVE_NUMBA:
    _invalidate_stale_caches()
