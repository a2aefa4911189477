"""Every rotor-family sample scene loads, has a theory, and runs (shortened here;
the full samples each run in well under a minute, see docs/rotors.md)."""
import dataclasses
import glob
import json

import pytest

from stand.cli.main import main
import stand
from stand.theories import rotors as rotor_theory
from stand.scene.structure_tables import ROTOR_TYPES

from _helpers import theory_computed_once

SAMPLES = sorted(glob.glob("data_samples/scenes/family_*.toml") +
                 ["data_samples/scenes/platform_paper004.toml"])


def test_one_sample_per_rotor_type():
    kinds = {stand.load(p).structure_type for p in SAMPLES}
    # "cylindrical_hinge" is the section-4.4 stand's model (fixed_point_stand)
    assert set(ROTOR_TYPES) - kinds <= {"cylindrical_hinge"}


@pytest.mark.parametrize("path", SAMPLES)
def test_sample_theory_and_short_run(path, capsys):
    sc = stand.load(path)
    with theory_computed_once(shared=True):   # `stand theory` below reads this one (same numbers)
        th = rotor_theory.family_theory(sc, floquet=False)
        assert main(["theory", path, "--no-floquet"]) == 0
    json.dumps(th)
    top = sc.drive.programme[-1, 1] / (2 * 3.141592653589793)
    plane = sc.weights[0].plane
    ranges = th["engineering_criterion"][plane]["working_ranges_hz"]
    # the sample's final speed lies inside a predicted working range
    assert any(a < top < b for a, b in ranges), (top, ranges)
    short = dataclasses.replace(sc, run=dataclasses.replace(sc.run, duration=0.5))
    run = stand.run(short)
    assert run.success and run.t[-1] == pytest.approx(0.5)
    # a [structure] type = "planar" scene is the chapter-5 planar rotor (scene language, issue 40):
    # `stand theory` gives its speed bands; the other rotor types their working ranges
    want = "stable motions by speed band" if sc.kind == "planar" else "working ranges"
    assert want in capsys.readouterr().out


def test_theory_reports_the_floquet_edges_of_the_two_mass_sample(capsys):
    assert main(["theory", "data_samples/scenes/family_two_mass.toml", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    mm = doc["main_motion"]["critical_speeds_hz"]
    # docs/rotors.md: simulation edges 9.2-9.4, 22.2-22.8 (basin), 39-40 Hz
    assert len(mm) == 3 and 9.2 < mm[0] < 9.4 and 39.0 < mm[2] < 40.0
