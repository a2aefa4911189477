"""Precompiled integrator kernels: one extension module per model kind, no numba at run time.

A process that loads numba-cached kernels still pays for importing numba and
registering its numpy implementations (about 0.7 s, more than the whole run of
a typical scene).  So the DOP853 loop and the right-hand side of each model kind
are compiled ahead of time with ``numba.pycc`` into an ordinary extension module
(``_stand_<kind>_<hash>``), which a later process imports in a millisecond
without importing numba at all.

The module's name carries a hash of everything that determines the machine
code: the sources of the kernel and of the modules it imports
(:func:`stand._jit.closure`), numba's and Python's versions and the CPU (the
code is compiled for this CPU).  An edited source gives a new name, so a stale
module is never loaded; old ones are deleted when a new one is built.

The modules live in ``stand/__pycache__/precompiled`` (beside numba's own cache),
or in ``$STAND_CACHE_DIR``, or in the user's cache folder when the package
folder is read-only.  Building needs a C compiler (numba's helper library is
compiled in); without one, or when ``numba.pycc`` is missing, the stand uses
numba's just-in-time compilation instead (:mod:`stand.integrate.kernel_set`).
"""
from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import os
import platform
import sys
import sysconfig
import tempfile
import threading
import warnings
from pathlib import Path

from stand import _jit
from stand.model.kernels import KIND_NAMES, RHS

#: (name, numba signature) of the exported functions; ``{k}`` is the kind's name
_ARR1, _ARR2 = "f8[::1]", "f8[:,::1]"
EXPORTS = {
    "dop853": (f"Tuple((i8, f8, f8, i8))({_ARR1}, {_ARR2}, {_ARR2}, f8, {_ARR1}, {_ARR1}, f8, f8, "
               f"f8, f8, {_ARR1}, f8, {_ARR1}, i8, {_ARR2}, i8[::1], i8, f8)"),
    "evaluate": f"void(f8, {_ARR1}, {_ARR1}, {_ARR1}, {_ARR2}, {_ARR2})",
}

#: A compiled function outside the integrator (an *extra*, e.g. the screen renderer) is
#: precompiled on its own module, named ``"<module>:<function>"`` by the layer that owns it
#: (:func:`stand.integrate.kernel_set.extra`): the integrator names no layer above it.  The
#: module gives the function's numba signature as ``<function>_signature()``.


def is_extra(kind) -> bool:
    """Whether ``kind`` names an extra (``"<module>:<function>"``), not a model kind."""
    return isinstance(kind, str) and ":" in kind


def cache_dir() -> Path:
    """Folder of the precompiled modules (module docstring)."""
    env = os.environ.get("STAND_CACHE_DIR")
    if env:
        return Path(env) / "precompiled"
    d = _jit.PACKAGE / "__pycache__"
    if os.access(d if d.exists() else _jit.PACKAGE, os.W_OK):
        return d / "precompiled"
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "stand" / "precompiled"


def _cpu() -> str:
    """This CPU's model and instruction-set flags (the code is compiled for them)."""
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as fh:
            keep = [ln for ln in fh.read(65536).splitlines()
                    if ln.startswith(("model name", "flags", "Features", "CPU part"))]
        return "\n".join(sorted(set(keep)))
    except OSError:
        return platform.processor() + platform.machine()


def _numba_version() -> str:
    """numba's version file (read, not imported: importing numba is what is avoided)."""
    spec = importlib.util.find_spec("numba")
    try:
        return (Path(spec.origin).parent / "_version.py").read_text(errors="replace")
    except (OSError, AttributeError, TypeError):
        return "unknown"


def _label(kind) -> str:
    """A model kind's name, or an extra's function name."""
    return kind.rpartition(":")[2] if is_extra(kind) else KIND_NAMES[kind]


def module_name(kind) -> str:
    """Name of the precompiled module of model ``kind`` (or of extra ``kind``,
    ``"<module>:<function>"``) for the current sources."""
    h = hashlib.sha1()
    h.update(_jit.sources_hash(kernel_modules(kind)).encode())
    exports = kind if is_extra(kind) else sorted(EXPORTS.items())
    for part in (_numba_version(), sys.version, _cpu(), repr(exports)):
        h.update(part.encode())
    return f"_stand_{_label(kind)}_{h.hexdigest()[:16]}"


def kernel_modules(kind) -> list:
    """The package modules whose sources make up kind ``kind``'s compiled kernels."""
    if is_extra(kind):
        return _jit.closure(kind.partition(":")[0], dynamic=False)
    return _jit.closure("stand.integrate.dop853", "stand.model.kernels", RHS[kind][0], dynamic=False)


def _path(name: str) -> Path:
    return cache_dir() / (name + sysconfig.get_config_var("EXT_SUFFIX"))


def load(kind: int):
    """The precompiled module of ``kind`` for the current sources, or None if not built."""
    name = module_name(kind)
    path = _path(name)
    if not path.exists():
        return None
    if name in sys.modules:
        return sys.modules[name]
    try:
        loader = importlib.machinery.ExtensionFileLoader(name, str(path))
        spec = importlib.util.spec_from_file_location(name, path, loader=loader)
        mod = importlib.util.module_from_spec(spec)
        loader.exec_module(mod)
    except ImportError:  # a damaged file: rebuild
        return None
    sys.modules[name] = mod
    return mod


def available() -> str | None:
    """None when precompiling is possible here, otherwise why not."""
    if not _jit.HAVE_NUMBA:
        return "numba is not installed or STAND_DISABLE_JIT is set"
    if importlib.util.find_spec("numba.pycc") is None:
        return "numba.pycc (ahead-of-time compilation) is not available in this numba"
    from shutil import which

    cc = sysconfig.get_config_var("CC") or "cc"
    if which(cc.split()[0]) is None and which("cc") is None and which("gcc") is None:
        return "no C compiler found (numba.pycc compiles numba's helper library)"
    return None


#: the name numba's module mixin (``modulemixin.c``) is compiled under, the same for every
#: module: its only name-dependent symbol is the init function the module's code calls
#: (``pycc_init_<name>``), which each module is told to call under this name instead
_MIXIN_NAME = "_stand_mixins"


def _mixins_class():
    """``numba.pycc.CC`` whose C helper objects (numba's helper library and module mixin: the
    same for every kernel, :data:`_MIXIN_NAME`) are compiled once per numba version into the
    cache folder (one process at a time; the others wait and reuse them), in a thread that
    runs while numba compiles the kernels (the C compiler is a separate process: the two
    use both cores)."""
    from numba.pycc import CC

    class MixinsAhead(CC):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            self._init_function = "pycc_init_" + _MIXIN_NAME   # what modulemixin.o defines

        def _get_mixin_defines(self):
            return [(k, _MIXIN_NAME if k == "PYCC_MODULE_NAME" else v)
                    for k, v in CC._get_mixin_defines(self)]

        def start_mixins(self):
            self._mixins, self._error = None, None

            def work():
                try:
                    self._mixins = self._cached_mixins()
                except Exception as exc:  # noqa: BLE001 - re-raised in the main thread
                    self._error = exc

            self._thread = threading.Thread(target=work, daemon=True)
            self._thread.start()

        def _cached_mixins(self):
            h = hashlib.sha1((_numba_version() + sys.version + repr(sysconfig.get_config_var("CC"))
                              + repr(self._get_mixin_defines()) + _cpu()).encode()).hexdigest()
            d = cache_dir() / f"mixins-{h[:16]}"
            listing = d / "objects.txt"
            from stand.io.lock import file_lock

            with file_lock(cache_dir() / ".mixins.lock"):   # concurrent builds: compiled once
                return self._mixins_in(d, listing)

        def _mixins_in(self, d, listing):
            if listing.exists():
                objs = [d / ln for ln in listing.read_text().split()]
                if all(o.exists() for o in objs):
                    return [str(o) for o in objs]
            d.mkdir(parents=True, exist_ok=True)
            with tempfile.TemporaryDirectory(dir=d, prefix=".build-") as tmp:
                objs = CC._compile_mixins(self, tmp)
                names = []
                for i, o in enumerate(objs):
                    names.append(f"{i:02d}_{Path(o).name}")
                    os.replace(o, d / names[-1])
            tmp_listing = d / f".objects.{os.getpid()}.txt"
            tmp_listing.write_text("\n".join(names))
            os.replace(tmp_listing, listing)
            return [str(d / n) for n in names]

        #: the exports only call functions numba has compiled and optimised already (a
        #: model kind's DOP853 loop and right-hand side, linked from numba's JIT library):
        #: the module's code is generated from their optimised IR as it is, not run through
        #: LLVM's module optimisation once more (4 s of a planar build; the same machine
        #: code as the JIT's, the wrappers a call instead of inlined); an extra compiles its
        #: own code here, which needs the optimisation (False)
        linked_only = False

        def _compile_object_files(self, build_dir):
            if not self.linked_only:
                return CC._compile_object_files(self, build_dir)
            from numba.core import codegen
            from numba.pycc import cc as cc_module

            class Linked(codegen.AOTCodeLibrary):
                def _optimize_final_module(self):
                    pass     # function passes ran as each part was added

            class Compiler(cc_module.ModuleCompiler):
                def __init__(self, *args, **kwargs):
                    super().__init__(*args, **kwargs)
                    self.context.codegen()._library_class = Linked   # this module's only

            saved, cc_module.ModuleCompiler = cc_module.ModuleCompiler, Compiler
            try:
                return CC._compile_object_files(self, build_dir)
            finally:
                cc_module.ModuleCompiler = saved

        def _compile_mixins(self, build_dir):
            if getattr(self, "_thread", None) is None:
                return self._cached_mixins()
            self._thread.join()
            if self._error is not None:
                raise self._error
            return self._mixins

    return MixinsAhead


def build(kind: int):
    """Compile kind ``kind``'s kernels into their extension module and return it loaded.

    Takes as long as numba's own compilation of the same kernels plus a few seconds
    of C compilation.  Concurrent builds (several test workers) are safe: each
    writes its own temporary file and renames it into place.
    """
    why = available()
    if why is not None:
        raise RuntimeError(f"cannot precompile the kernels: {why}")
    numba = _jit.import_numba()
    from stand.io.lock import file_lock

    out = cache_dir()
    with file_lock(_lock_path(kind)):   # concurrent builds: one compiles, the others load it
        mod = load(kind)
        return mod if mod is not None else _build(kind, numba, out)


def _lock_path(kind) -> Path:
    return cache_dir() / f".{_label(kind)}.lock"


def building(kind: int) -> bool:
    """Whether another process is building kind ``kind``'s module now."""
    from stand.io.lock import is_locked

    return is_locked(_lock_path(kind))


def main(argv=None) -> int:
    """``python -m stand.integrate.precompiled KIND``: build quietly at low priority (the
    command line's background build); a failure is logged beside the modules."""
    import traceback

    args = sys.argv[1:] if argv is None else argv
    names = {v: k for k, v in KIND_NAMES.items()}
    if len(args) == 1 and is_extra(args[0]):
        names[args[0]] = args[0]
    if len(args) != 1 or args[0] not in names:
        print(f"usage: python -m stand.integrate.precompiled {{{','.join(names)},<module>:<function>}}",
              file=sys.stderr)
        return 2
    try:
        os.nice(10)
    except (AttributeError, OSError):  # pragma: no cover
        pass
    try:
        build(names[args[0]])
    except Exception:  # noqa: BLE001 - a background build must not fail loudly
        cache_dir().mkdir(parents=True, exist_ok=True)
        (cache_dir() / f"build-{args[0]}.log").write_text(traceback.format_exc())
        return 1
    return 0


def _build(kind, numba, out):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _MixinsAhead = _mixins_class()
    name = module_name(kind)
    import numpy as np

    if is_extra(kind):
        import importlib

        module, _, func = kind.partition(":")
        mod = importlib.import_module(module)
        f = getattr(mod, func)
        exports = {func: (getattr(mod, f"{func}_signature")(), getattr(f, "dispatcher", f))}
    else:
        exports = _kernel_exports(kind, np)
    with tempfile.TemporaryDirectory(dir=out, prefix=".build-") as tmp:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", category=numba.NumbaPendingDeprecationWarning)
            cc = _MixinsAhead(name)
        cc.output_dir = tmp
        cc.target_cpu = "host"
        cc.verbose = False
        cc.linked_only = not is_extra(kind)
        for export, (sig, f) in exports.items():
            cc.export(export, sig)(f)
        cc.start_mixins()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cc.compile()
        built = Path(tmp) / _path(name).name
        os.replace(built, _path(name))
    for old in out.glob(f"_stand_{_label(kind)}_*"):
        if old.name != _path(name).name:
            try:
                old.unlink()
            except OSError:  # pragma: no cover - in use on some platforms
                pass
    mod = load(kind)
    if mod is None:  # pragma: no cover
        raise RuntimeError(f"built {_path(name)} but could not import it")
    return mod


def _kernel_exports(kind, np):
    """The DOP853 loop and the right-hand side of model ``kind``: name -> (signature, function).
    The right-hand side is called as the kind's function itself (not through
    :func:`stand.model.kernels.evaluate`, whose JIT compilation would emit it once more)."""
    from stand.integrate.dop853 import WORK_ROWS, dop853_loop
    from stand.model.kernels import kernel_of

    loop = dop853_loop.dispatcher if hasattr(dop853_loop, "dispatcher") else dop853_loop
    ev = kernel_of(kind)
    ev = getattr(ev, "dispatcher", ev)

    # the kind is a constant of these wrappers: numba compiles its kernels only
    def _dop853(sp, wt, prog, t, y, f, h_abs, t_end, rtol, atol, cap, max_step, ts, k_next,
                out_, stats, max_steps, limit):
        work = np.empty((WORK_ROWS, y.shape[0]))
        return loop(kind, sp, wt, prog, t, y, f, h_abs, t_end, rtol, atol, cap, max_step, ts,
                    k_next, out_, stats, max_steps, limit, work)

    def _evaluate(t, y, dy, sp, wt, prog):
        ev(t, y, dy, sp, wt, prog)

    return {"dop853": (EXPORTS["dop853"], _dop853), "evaluate": (EXPORTS["evaluate"], _evaluate)}


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
