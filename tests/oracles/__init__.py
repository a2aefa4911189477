"""The books' own forms of the weight models, kept as test oracles (issue 29, item 4).

The package runs each model once, on the fixed-frame SI right-hand sides of
stand/model (planar kernel, generic kernel with its bodies) and the rotating
frame derived from them (:mod:`stand.model.rotating`).  The books write the same
models in their own dimensionless variables, with their own right-hand sides
and calling conventions; those are here, beside the tests, as the independent
check: the tests integrate both and ask them to agree (<= 1e-8 relative).

Modules
-------
book_run
    The books' right-hand sides behind one calling convention ``f(tau, y)`` and
    a ``[weight_model]`` scene run on them (scipy's solvers) into the common
    :class:`stand.integrate.result.Run`.
"""
