"""The regime of a planar rotor with body weights (no balls) is judged against their capacity.

The analysis calls a planar run "balanced" when the whirl lies inside the ring of zone 1,
S / (16 M) (the rings, :mod:`stand.instruments.rings`, and the run's summary count the body
weights' capacity, :meth:`stand.scene.model.Scene.weights_capacity`).  With the balls' capacity
alone a body-weight scene had S = 0: a zero ring, never "balanced" however well it balanced.
"""
import dataclasses
from pathlib import Path

import numpy as np

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"


def test_planar_body_weights_ring_of_zone_1_counts_their_capacity(monkeypatch):
    import stand
    from dsp import regime as rg
    from stand.scene.parse import load_scene

    scene = load_scene(SCENES / "body_damper.toml")
    assert scene.kind == "planar" and scene.balancer.count == 0 and scene.bodies
    S = scene.weights_capacity()
    assert S > 0
    run = stand.run(dataclasses.replace(scene, run=dataclasses.replace(scene.run, duration=3.0)))
    seen = []
    real = rg.classify_windows

    def spy(t, phi, w, x, y, w_s, thr, *a, **k):
        seen.append(thr)
        return real(t, phi, w, x, y, w_s, thr, *a, **k)

    monkeypatch.setattr(rg, "classify_windows", spy)
    stand.analyze(run)
    assert seen, "the regime was not classified"
    np.testing.assert_allclose(seen[-1], S / scene.total_mass / 16, rtol=1e-12)
