"""The books' own forms of the weight models, kept as test oracles (issue 29, item 4).

The package runs each model once, on the fixed-frame SI right-hand sides of
stand/model (planar kernel, generic kernel with its bodies) and the rotating
frame derived from them (:mod:`stand.theories.rotating`).  The books write the same
models in their own dimensionless variables, with their own right-hand sides
and calling conventions; those are here, beside the tests, as the independent
check: the tests integrate both and ask them to agree (<= 1e-8 relative).

Modules
-------
book_run
    The books' right-hand sides behind one calling convention ``f(tau, y)`` and
    a ``[weight_model]`` scene run on them (scipy's solvers) into the common
    :class:`stand.integrate.result.Run`.
book_ode
    The books' ``solve_ivp`` convention (a frame's ``rhs(tau, y, p)``, ``simulate``).
gravity_pair, damper, two_axis
    The book's own equations of ch. 7.1, 7.2 and 6 (fixed and rotating frames; the
    two-axis pendulum also in a QP motion's frame and with a run-up).
oval_race
    Balls on an out-of-round race (``race_out_of_roundness``): the Lagrangian over the
    balls' absolute angles, written without the stand (tests/test_race_out_of_roundness.py).
_dense
    A dense linear solve on plain floats (Gaussian elimination, partial pivoting) for the
    small mass matrices of oval_race, two_ball_stand and two_ball_record.
"""
