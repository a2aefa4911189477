"""numba's ``njit``, imported only when a compiled function is first needed.

Importing numba costs about 0.3 s and its first compiled call another 0.4 s
(numba registers its numpy implementations, and that imports SciPy's BLAS):
more than a whole ``stand theory`` or ``stand run`` from a precompiled kernel
(:mod:`stand.integrate.aot`).  So :func:`njit` returns a :class:`LazyKernel`
while numba is not imported: a stand-in that imports numba, turns every
pending kernel into a real numba dispatcher and replaces the stand-ins by the
dispatchers in every loaded module's globals (so compiled code that calls
another kernel sees a dispatcher) the first time any kernel is called.  Once
numba is imported :func:`njit` is ``numba.njit`` itself.

Set ``STAND_DISABLE_JIT=1`` to run every kernel as plain Python/numpy (slow;
the tested fallback path, see ``benchmarks/bench_startup.py``).

Your own numba functions that call a stand kernel: import numba before stand
(the stand then makes real dispatchers at once), or call :func:`import_numba`
before compiling them, so that they see dispatchers and not stand-ins.

Stale caches.  numba invalidates a cached function only when *its own* file
changes, not when a kernel it calls or inlines from another module does: a
stale cache would silently run old physics.  :func:`drop_stale_caches` keeps,
per compiled module, a hash of its source and of the compiled modules it
imports (directly or not; a string literal naming a module, ``"stand.x.y"``, counts as
an import: the kernels chosen at compile time by model kind), and deletes that module's cache files when the hash changes:
editing the generic rotor kernel keeps the planar rotor's caches.
"""
from __future__ import annotations

import hashlib
import importlib.util
import os
import re
import sys
from pathlib import Path

_DISABLED = os.environ.get("STAND_DISABLE_JIT", "") not in ("", "0")
#: numba is installed and not disabled (it may not be imported yet)
HAVE_NUMBA = (not _DISABLED) and importlib.util.find_spec("numba") is not None

PACKAGE = Path(__file__).resolve().parent

_numba = None          # the numba module, once imported
_PENDING: list = []    # LazyKernel objects made before numba was imported
_HOOKS: list = []      # callables run with the numba module when it is imported


def literally(x):
    """``numba.literally`` in compiled code (compile one specialisation per value); identity
    in Python."""
    return x


_literally_shim = literally


class LazyKernel:
    """A function to be compiled by numba on its first call (numba is imported then).

    Calling it, or asking for a dispatcher attribute (``signatures``, ``stats``,
    ``py_func`` ...), compiles it (or loads it from numba's cache); the object then
    behaves as the numba dispatcher.
    """

    def __init__(self, py_func, options):
        self.py_func = py_func
        self.options = options
        self._dispatcher = None
        self.__name__ = py_func.__name__
        self.__qualname__ = py_func.__qualname__
        self.__module__ = py_func.__module__
        self.__doc__ = py_func.__doc__
        self.__wrapped__ = py_func

    @property
    def dispatcher(self):
        if self._dispatcher is None:
            import_numba()
        return self._dispatcher

    def __call__(self, *args, **kwargs):
        return self.dispatcher(*args, **kwargs)

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        return getattr(self.dispatcher, name)

    def __repr__(self):
        state = "compiled" if self._dispatcher is not None else "not compiled yet"
        return f"<stand kernel {self.__module__}.{self.__qualname__} ({state})>"


def njit(*args, **kwargs):
    """``numba.njit`` (lazily: see the module docstring), or the plain function when numba is
    missing or disabled."""
    if args and callable(args[0]):
        return njit(**kwargs)(args[0])
    if not HAVE_NUMBA:
        return lambda f: f
    if _numba is None and "numba" in sys.modules:   # someone else imported numba: no saving
        import_numba()
    if _numba is not None:
        return _numba.njit(*args, **kwargs)

    def wrap(f):
        k = LazyKernel(f, kwargs)
        _PENDING.append(k)
        return k

    return wrap


def when_numba(hook) -> None:
    """Run ``hook(numba)`` when numba is imported (now if it already is): registrations
    such as ``numba.extending.overload`` that need numba itself."""
    if _numba is not None:
        hook(_numba)
    elif HAVE_NUMBA:
        _HOOKS.append(hook)


def import_numba():
    """Import numba, compile-enable every pending kernel, and return the numba module."""
    global _numba
    if _numba is not None:
        return _numba
    if not HAVE_NUMBA:  # pragma: no cover - guarded by the callers
        raise RuntimeError("numba is not available (or STAND_DISABLE_JIT is set)")
    import numba

    drop_stale_caches()
    swap = {id(_literally_shim): numba.literally}
    for k in _PENDING:
        k._dispatcher = numba.njit(**k.options)(k.py_func)
        swap[id(k)] = k._dispatcher
    _numba = numba
    globals()["literally"] = numba.literally   # for modules imported from now on
    for hook in _HOOKS:
        hook(numba)
    # compiled code resolves the kernels it calls through its module's globals: put the
    # dispatchers (and numba.literally) where the stand-ins are
    shim = _literally_shim
    for mod in list(sys.modules.values()):
        d = getattr(mod, "__dict__", None)
        if not isinstance(d, dict) or d is globals():
            continue
        for name, v in list(d.items()):
            if id(v) in swap and (v is shim or isinstance(v, LazyKernel)):
                d[name] = swap[id(v)]
    _PENDING.clear()
    _HOOKS.clear()
    return numba


# --- cache invalidation ------------------------------------------------------------------

def _module_file(name: str) -> Path | None:
    rel = name.split(".")[1:]
    for p in (PACKAGE.joinpath(*rel).with_suffix(".py"), PACKAGE.joinpath(*rel, "__init__.py")):
        if p.exists():
            return p
    return None


_IMPORT = re.compile(rb"^[ \t]*(?:from[ \t]+(\.*)([\w.]*)[ \t]+import[ \t]+(\([^)]*\)|[^\n#]*)"
                     rb"|import[ \t]+(stand[\w.]*))", re.M)
#: a string literal naming a module (a registry entry: ``"stand.x.y"`` or ``"stand.x.y:obj"``)
_NAMED = re.compile(rb"[\"'](stand(?:\.\w+)+)(?::[\w.]+)?[\"']")


def _imports(path: Path, name: str) -> set:
    """Package-internal modules imported anywhere in a module's source (a static scan of
    its ``import`` lines; a regular expression, several times faster than parsing)."""
    pkg = name.split(".")
    if path.name != "__init__.py":
        pkg = pkg[:-1]
    out = set()
    for dots, mod, names, plain in _IMPORT.findall(path.read_bytes()):
        if plain:
            out.add(plain.decode())
            continue
        level, mod = len(dots), mod.decode()
        if level:
            base = pkg[: len(pkg) - level + 1]
            mod = ".".join(base + (mod.split(".") if mod else []))
        if not mod.startswith("stand"):
            continue
        out.add(mod)
        for a in names.decode().strip("()").replace("\\", " ").replace("\n", ",").split(","):
            a = a.split()[0] if a.split() else ""
            if a:
                out.add(f"{mod}.{a}")
    return {m for m in out if m.split(".")[0] == "stand" and _module_file(m) is not None}


def closure(*names: str, dynamic: bool = True) -> list:
    """The modules a compiled module depends on, as sorted names: itself, what it imports,
    and recursively what the compiled modules among those import (a module without
    compiled code contributes its own source, e.g. constants frozen into the kernels, and
    is not followed further).  ``dynamic`` adds the modules that compiled modules name in
    string literals (kernels chosen at compile time, e.g. :data:`stand.model.kernels.RHS`)."""
    seen, todo = set(), list(names)
    while todo:
        m = todo.pop()
        if m in seen:
            continue
        seen.add(m)
        f = _module_file(m)
        if f is None or (m not in names and b"@njit" not in f.read_bytes()):
            continue
        todo.extend(_imports(f, m))
        if dynamic:
            todo.extend(n.decode() for n in _NAMED.findall(f.read_bytes()) if _module_file(n.decode()))
    return sorted(seen)


def sources_hash(names) -> str:
    """SHA-1 over the sources of the given modules (names and contents)."""
    h = hashlib.sha1()
    for m in sorted(names):
        f = _module_file(m)
        if f is not None:
            h.update(m.encode())
            h.update(f.read_bytes())
    return h.hexdigest()


def drop_stale_caches() -> None:
    """Delete the numba cache files of every compiled module whose source, or the source of
    a module it imports, changed since its caches were written (module docstring)."""
    try:
        files = [f for f in PACKAGE.rglob("*.py") if b"@njit" in f.read_bytes()]
        for f in files:
            rel = f.relative_to(PACKAGE.parent).with_suffix("")
            name = ".".join(rel.parts)
            h = sources_hash(closure(name))
            cache = f.parent / "__pycache__"
            stamp = cache / f"{f.stem}.sources.sha1"
            if stamp.exists() and stamp.read_text() == h:
                continue
            for c in list(cache.glob(f"{f.stem}.*.nbi")) + list(cache.glob(f"{f.stem}.*.nbc")):
                c.unlink()
            cache.mkdir(exist_ok=True)
            stamp.write_text(h)
    except OSError:  # read-only install: sources cannot change under it
        pass
