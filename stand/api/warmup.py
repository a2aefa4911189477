"""``stand warmup``: compile ahead, so that no later command waits for a compiler.

* the integrator kernels of the planar rotor (``--all``: of every model kind) are
  precompiled (:mod:`stand.integrate.precompiled`), or compiled into numba's cache
  where precompiling is impossible;
* with ``--all`` also numba's cache of the other compiled functions, for every
  kind: the fixed-step RK4 loop (``stand accuracy``, planar scenes), the finite-difference
  Jacobian (Radau/BDF/LSODA runs) and the right-hand side evaluation;
* the screen renderer (``stand run`` of a scene with a screen camera) is precompiled too;
* the blurred-spot fit of ``stand track`` (:mod:`vision.blur`, about 10 s the first time);
* the line fit of :func:`dsp.lines.refine_frequencies` (:mod:`dsp._line_kernel`, about 15 s
  the first time), which batch work in one process switches to.
"""
from __future__ import annotations

import time

import numpy as np

from stand import _jit
from stand.model.kernels import KIND_NAMES, PLANAR


def _jit_extras(kind: int) -> None:
    """Compile (or load) the RK4 loop (planar only) and the finite-difference Jacobian of
    ``kind`` for the argument types the stand passes (C-contiguous float64 arrays, Python
    floats and ints).  (The right-hand side's entry point for calls from Python is the
    kind's function itself, compiled with the DOP853 loop: :mod:`stand.integrate.kernel_set`.)"""
    numba = _jit.import_numba()
    from numba import typeof, types

    from stand.integrate.jacobian import jac_fd
    from stand.integrate.rk4 import rk4_loop

    lit = types.literal(kind)
    a1, a2 = typeof(np.zeros(1)), typeof(np.zeros((1, 1)))
    f8, i8 = types.float64, types.int64
    if kind == PLANAR:   # RK4 error reports take planar scenes only (stand.integrate.accuracy)
        rk4_loop.compile((lit, a1, a2, a2, a1, f8, i8, i8, a2))
    jac_fd.compile((lit, f8, a1, a1, a1, a2, a2, a2))
    del numba


def warmup(every_kind: bool = False, say=print, precompile: bool = True, kinds=None) -> list:
    """Compile ahead (module docstring); returns one dict per item: ``what``, ``source``
    (precompiled / jit / python), ``seconds``.  ``precompile=False``: numba's JIT only
    (enough for work in this process).  ``kinds``: these model kinds only (with everything
    ``every_kind`` compiles for each), e.g. one per process to use several cores; without
    ``kinds`` also the blurred-spot fit of ``stand track``."""
    from stand.integrate.kernel_set import kernels

    chosen = kinds is not None
    if chosen:
        kinds, every_kind = sorted(kinds), True
    else:
        kinds = sorted(KIND_NAMES) if every_kind else [0]
    done = []
    for kind in kinds:
        t0 = time.perf_counter()
        ks = kernels(kind, build=precompile)
        row = {"what": f"{KIND_NAMES[kind]} integrator kernel", "source": ks.source,
               "seconds": time.perf_counter() - t0}
        done.append(row)
        say(f"{row['what']}: {row['source']} ({row['seconds']:.1f} s)")
        if every_kind and _jit.HAVE_NUMBA:
            t0 = time.perf_counter()
            _jit_extras(kind)
            row = {"what": f"{KIND_NAMES[kind]} RK4 loop, Jacobian and right-hand side",
                   "source": "jit", "seconds": time.perf_counter() - t0}
            done.append(row)
            say(f"{row['what']}: {row['source']} ({row['seconds']:.1f} s)")
    if _jit.HAVE_NUMBA and not chosen and precompile:
        from stand.integrate import precompiled

        t0 = time.perf_counter()
        try:
            source = "precompiled" if precompiled.build("stand.instruments.render:render_frame") is not None else "jit"
        except Exception:  # noqa: BLE001 - no compiler: numba's JIT on first use
            source = "jit"
        row = {"what": "screen renderer (stand run with a screen)", "source": source,
               "seconds": time.perf_counter() - t0}
        done.append(row)
        say(f"{row['what']}: {row['source']} ({row['seconds']:.1f} s)")
    if _jit.HAVE_NUMBA and not chosen:
        from dsp._line_kernel import warm as warm_lines
        from vision.blur import warm as warm_blur

        for what, warm in (("line fit (dsp.refine_frequencies, batch work)", warm_lines),
                           ("blurred-spot fit (stand track)", warm_blur)):
            t0 = time.perf_counter()
            source = "jit" if warm() == "numba" else "python"
            row = {"what": what, "source": source, "seconds": time.perf_counter() - t0}
            done.append(row)
            say(f"{row['what']}: {row['source']} ({row['seconds']:.1f} s)")
    return done
