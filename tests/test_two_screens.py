"""Two laser screens -> the shaft axis line (4.2) -> both correction planes (4.3)
-> the unbalances in the two planes (static + couple), on a simulated spatial rotor."""
import math

import numpy as np
import pytest

from dsp.errors import SignalError
from dsp.two_plane import principal_axis_offsets, shaft_axis_points, two_plane_unbalances
from stand.model.rotors import Unbalance
from stand.integrate.coupled import simulate_coupled
from stand.model.rotors.spatial import spatial_scene_rotor


def test_printed_43_is_the_negated_axis_line():
    # a line through (1, y=2) and (3, y=4): x(y) = y - 1 -> x(0) = -1, x(h=1) = 0
    oi, oii = principal_axis_offsets(1.0, 2.0, 3.0, 4.0, 1.0)
    # (4.3): O_I = -x1 + (x2 - x1)/(y2 - y1) y1 = -1 + 2 = 1 = -x(0)
    assert oi == pytest.approx(1.0) and oii == pytest.approx(0.0)
    with pytest.raises(SignalError, match="different"):
        shaft_axis_points(1.0, 2.0, 3.0, 2.0, [0.0])


def test_two_screens_give_static_and_couple_unbalance():
    aI, aII = -0.1, 0.15                 # correction planes [m from the centre of mass]
    sI, sII = 1.5e-3 * np.exp(0.4j), 1.0e-3 * np.exp(2.5j)   # truth [kg m]
    rot = spatial_scene_rotor(10.0, 0.3, 0.1, 0.2, 0.3, 2.0e4, balancer_positions=[aI, aII],
                              stiffness_damping=2e-3, screen_positions=[0.5, 0.8])
    import dataclasses

    rot = dataclasses.replace(rot, unbalances=(
        Unbalance("balancer1", abs(sI), float(np.angle(sI))),
        Unbalance("balancer2", abs(sII), float(np.angle(sII)))))
    w = 2 * math.pi * 20.0               # above the rigid-body critical speeds (9.7, 15 Hz)
    run = simulate_coupled(rot, [], [[0.0, w]], 8.0, 40 * 20.0, rtol=1e-10, atol=1e-12)
    last = run.t >= 6.0                   # steady: decay rate ~ beta w^2 / 2
    phas = {}
    for p in ("screen1", "screen2"):
        z = run.planes[p][last, 0] + 1j * run.planes[p][last, 1]
        phas[p] = np.mean(z * np.exp(-1j * run.rotor_angle[last]))   # forward 1X, rotor frame
    d = shaft_axis_points(phas["screen1"], 0.5, phas["screen2"], 0.8, [aI, aII])
    # the axis points agree with the model's response in the planes
    for k, p in enumerate(("balancer1", "balancer2")):
        model = sum(np.dot([1, 1j], rot.unbalance_response(w, u.plane, u.s, u.angle, at=p)) / 2
                    for u in rot.unbalances)
        assert abs(d[k] - model) < 1e-3 * abs(model)
    H = np.array([[np.dot([1, 1j], rot.unbalance_response(w, pj, 1.0, at=pi)) / 2
                   for pj in ("balancer1", "balancer2")] for pi in ("balancer1", "balancer2")])
    U = two_plane_unbalances(d, H)
    np.testing.assert_allclose(U, [sI, sII], rtol=2e-3)
