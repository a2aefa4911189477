"""The paper-003 sample with two balancers: the generalised criterion in stand theory, and
the run above its onset balancing both planes."""
import json
from pathlib import Path

import numpy as np
import pytest

import stand

from _helpers import stand_stdout

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"
SAMPLE = SCENES / "paper003_two_balancers.toml"


@pytest.mark.parametrize("name,onset_hz", [("paper003_two_balancers", 21.4688),
                                           ("paper003_two_screens", 21.6068)])
def test_theory_json_holds_the_generalised_criterion_of_the_sample(name, onset_hz):
    """With balancers (two_balancers) or without (two_screens: the rotor's two correction
    planes), stand theory --json holds the two-plane criterion; its onset is where
    criterion_matrix turns negative definite."""
    path = SCENES / f"{name}.toml"
    out = stand_stdout("theory", path, "--json")
    gc = json.loads(out)["generalised_criterion"]
    assert gc["planes"] == ["balancer1", "balancer2"]
    sc = stand.load(path)
    from stand.integrate.coupled import with_locked_weights

    rot = with_locked_weights(sc.linear_rotor(), sc.weights)

    def definite(f_hz):
        M = rot.criterion_matrix(2 * np.pi * f_hz, gc["planes"])
        return bool(np.all(np.linalg.eigvalsh(0.5 * (M + M.T)) < 0))

    (onset,) = gc["onsets_hz"]
    assert not definite(onset * (1 - 1e-6)) and definite(onset * (1 + 1e-6))
    assert gc["working_ranges_hz"] == [[onset, None]]
    assert onset == pytest.approx(onset_hz, rel=1e-5)


def test_the_pair_balances_above_the_onset():
    run = stand.run(stand.load(SAMPLE))
    assert run.success and run.rotor_speed[-1] / (2 * np.pi) == pytest.approx(30.0)
    for p in ("balancer1", "balancer2"):
        assert np.hypot(*run.planes[p][-1]) < 1e-9          # m: balanced (2e-3 kg m unbalance)
