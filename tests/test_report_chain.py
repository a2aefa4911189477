"""One identification chain (issue 40): ``stand report`` is a view of ``stand analyze``'s result.

For every lab sample (data_samples/daq/*.csv with their maps, data_samples/fit/*.csv,
data_samples/recordings/*.h5) and every sample scene (data_samples/scenes/*.toml, run
short), the numbers of ``stand analyze --json`` and of ``stand report --json`` are
compared: the report's ``analysis`` section number by number, and the numbers the
report presents (residual unbalance, 1X, ISO grade, natural frequency, critical speed)
against the analysis' keys they show.  Both commands compute the same thing from the same
file in the same process, deterministically: the tolerance is 1e-12 relative (a rounding
of the last bits, should a BLAS sum change order), nothing physical.

Each analysis is computed once (issue 43's five-minute suite): within this module
``stand.analysis.identify.analyze`` -- what both commands call -- hands a deep copy of its
first result to a later call with the same file and the same arguments (grade, service
speed, map), so a report that passed other arguments than ``stand analyze`` still differs;
that two computations agree (determinism) is checked with the real function on a recording
(``test_two_computations_agree``).  The chapter-5 theory the balancing report draws beside
a planar scene is left out here (the report says so in its notes): the chain compares the
analysis' numbers, none of the theory's; the report's theory is tested in
test_report_balancing.py.
"""
from __future__ import annotations

import copy
import dataclasses
import inspect
import json
import math
import os
from pathlib import Path

import pytest

from stand.cli.main import main
from stand.io.result import flatten_numbers

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "data_samples"
REL = 1e-12


def _memoized_analysis(fn):
    """``fn`` (``analyze``) computed once per file and arguments; a deep copy of that first
    result to every later call (no caller sees another caller's changes).  A sample of
    data_samples/ is computed once per test session, whichever worker asks first
    (tests/_shared.py); the key names the chapter-5 theory function in force (this module
    replaces it), so a result made without the theory never reaches a test that has it."""
    from _shared import once
    from stand.theories.planar import speedmap

    signature, cache = inspect.signature(fn), {}

    def analyze(*args, **kwargs):
        bound = signature.bind(*args, **kwargs)
        bound.apply_defaults()
        path, *rest = bound.arguments.values()
        if not isinstance(path, (str, os.PathLike)):      # a Run or Recording in memory
            return fn(*args, **kwargs)
        key = (str(Path(path).resolve()), repr(rest))
        if key not in cache:
            theory = speedmap.scene_theory
            shared = f"analyze {key!r} theory {theory.__module__}.{theory.__qualname__}"
            inside = SAMPLES.resolve() in Path(key[0]).parents
            cache[key] = (once(shared, lambda: fn(*args, **kwargs)) if inside
                          else fn(*args, **kwargs))
        return copy.deepcopy(cache[key])
    return analyze


def _no_theory(scene, *args, **kwargs):
    raise RuntimeError("left out of the report-chain test (tests/test_report_chain.py)")


@pytest.fixture(scope="module", autouse=True)
def _each_analysis_once():
    """Within the module: one analysis per (file, arguments), no chapter-5 theory (module
    docstring); yields the real ``analyze``."""
    from stand.analysis import identify
    from stand.theories.planar import speedmap

    saved = identify.analyze, speedmap.scene_theory
    identify.analyze, speedmap.scene_theory = _memoized_analysis(saved[0]), _no_theory
    try:
        yield saved[0]
    finally:
        identify.analyze, speedmap.scene_theory = saved


_FULL_LAB = {"daq_runup_no_speed", "daq_runup", "daq_lab", "two_ball_runup", "acc_runup"}


def _lab_cases():
    """``(id, file, map or None)`` of every lab sample: each map with the table its name
    starts with (``daq_runup_no_speed.map.toml`` -> ``daq_runup.csv``)."""
    cases = []
    for folder in ("daq", "fit"):
        tables = sorted((SAMPLES / folder).glob("*.csv"))
        for m in sorted((SAMPLES / folder).glob("*.map.toml")):
            stem = m.name[: -len(".map.toml")]
            table = max((t for t in tables if stem.startswith(t.stem)), key=lambda t: len(t.stem))
            # the run-up tables' analyses take 3-15 s each: the chain on a run-up table runs on
            # acc_runup (the daq_runup run-up measured in g) by default in test_lab_samples.py
            # (with its truth, one analysis for both), on all of them here with `-m full`
            # (their analyses tested in test_lab_daq.py, test_lab_tachometer.py,
            # test_fit_reference.py)
            marks = [pytest.mark.full] if stem in _FULL_LAB else []
            cases.append(pytest.param(table, m, id=f"{folder}/{stem}", marks=marks))
    for h5 in sorted((SAMPLES / "recordings").glob("*.h5")):
        cases.append(pytest.param(h5, None, id=f"recordings/{h5.stem}"))
    return cases


def _cli_json(capsys, *argv) -> dict:
    assert main([str(a) for a in argv]) == 0
    return json.loads(capsys.readouterr().out)


def _same(x, y, what):
    if x is None or y is None:
        assert x is None and y is None, (what, x, y)
    elif isinstance(x, float) and math.isnan(x):
        assert math.isnan(y), (what, x, y)
    else:
        assert y == pytest.approx(x, rel=REL, abs=0), (what, x, y)


def check_same_numbers(analysis: dict, report: dict) -> int:
    """The report's ``analysis`` is the analysis' document; the presented numbers are its
    numbers.  Returns how many numbers were compared."""
    got = report["analysis"]
    a, b = dict(flatten_numbers(analysis)), dict(flatten_numbers(got))
    assert set(a) == set(b), set(a) ^ set(b)
    for k, v in a.items():
        _same(v, b[k], k)
    assert {k: v for k, v in analysis.items() if isinstance(v, str)} == \
        {k: v for k, v in got.items() if isinstance(v, str)}
    bq, dyn = report["balancing_quality"], report["dynamics"]
    shown = [(bq["residual_unbalance_gmm"], analysis.get("unbalance_gmm"), "unbalance"),
             (bq["residual_unbalance_gmm_std"], analysis.get("unbalance_gmm_std"), "its std"),
             (bq["residual_unbalance_angle_deg"], analysis.get("unbalance_angle_deg"), "angle"),
             (bq["response_1x_m"], analysis.get("response_1x_m"), "1X"),
             (bq["residual_speed_hz"], analysis.get("speed_hz"), "speed"),
             (bq["truth_residual_unbalance_gmm"], analysis.get("truth_unbalance_gmm"), "truth"),
             (bq["ring_reading"], analysis.get("ring_reading"), "rings"),
             (bq["vibration_1x"], analysis.get("vibration_1x"), "vibration"),
             (bq["iso_21940_11"]["achieved_grade_mm_s"],
              (analysis.get("iso_grade") or {}).get("achieved_grade_mm_s"), "ISO grade"),
             (bq["iso_21940_11"]["permissible_residual_gmm"],
              (analysis.get("iso_grade") or {}).get("permissible_gmm"), "permissible"),
             (dyn["natural_frequency"]["identified_hz"], analysis.get("natural_frequency_hz"), "f0"),
             (dyn["natural_frequency"]["damping_ratio"], analysis.get("damping_ratio"), "zeta"),
             (dyn["settling"], analysis.get("settling") or [], "settling")]
    st = analysis.get("stationary_stretch")
    shown.append((bq["residual_window_s"] or None,
                  [st["t_start_s"], st["t_end_s"]] if st else None, "window"))
    resonance = [r for r in dyn["critical_speeds"] if "resonance" in r["source"]]
    shown.append((resonance[0]["speed_hz"] if resonance else None,
                  analysis.get("critical_speed_hz"), "critical speed"))
    sync = [r["speed_hz"] for r in dyn["critical_speeds"] if "synchrony" in r["source"]]
    shown.append((sync or None, [c["speed_hz"] for c in analysis["critical_speeds_hz"]] or None,
                  "synchrony"))
    n = len(a)
    for x, y, what in shown:
        if isinstance(x, (dict, list)):
            fx, fy = dict(flatten_numbers(x)), dict(flatten_numbers(y))
            assert set(fx) == set(fy), what
            for k in fx:
                _same(fy[k], fx[k], f"{what}.{k}")
            n += len(fx)
        else:
            _same(y, x, what)
            n += 1
    return n


def test_the_check_can_fail():
    """A report whose presented unbalance, or whose analysis section, differs in the 10th
    digit fails the comparison."""
    doc = {"unbalance_gmm": 240.0, "unbalance_gmm_std": 0.2, "critical_speeds_hz": [],
           "recording": "x"}
    rep = {"analysis": dict(doc), "balancing_quality": {
        "residual_unbalance_gmm": 240.0, "residual_unbalance_gmm_std": 0.2,
        "residual_unbalance_angle_deg": None, "response_1x_m": None, "residual_speed_hz": None,
        "truth_residual_unbalance_gmm": None, "ring_reading": None, "vibration_1x": None,
        "iso_21940_11": {"achieved_grade_mm_s": None, "permissible_residual_gmm": None},
        "residual_window_s": []},
        "dynamics": {"natural_frequency": {"identified_hz": None, "damping_ratio": None},
                     "settling": [], "critical_speeds": []}}
    assert check_same_numbers(doc, rep) >= 2           # it passes as it is
    bad = json.loads(json.dumps(rep))
    bad["balancing_quality"]["residual_unbalance_gmm"] = 240.0 * (1 + 1e-10)
    with pytest.raises(AssertionError):
        check_same_numbers(doc, bad)
    bad = json.loads(json.dumps(rep))
    bad["analysis"]["unbalance_gmm_std"] = 0.21
    with pytest.raises(AssertionError):
        check_same_numbers(doc, bad)


def test_two_computations_agree(capsys, monkeypatch, _each_analysis_once):
    """The chain with the real ``analyze``: each command computes its own analysis of a
    recording and the numbers agree to 1e-12."""
    from stand.analysis import identify

    monkeypatch.setattr(identify, "analyze", _each_analysis_once)
    path = SAMPLES / "recordings" / "influence_ref.h5"
    analysis = _cli_json(capsys, "analyze", path, "--json")
    report = _cli_json(capsys, "report", path, "--json")
    assert check_same_numbers(analysis, report) > 10


@pytest.mark.parametrize("path, rmap", _lab_cases())
def test_lab_sample_same_numbers(path, rmap, capsys):
    opts = ["--map", rmap] if rmap else []
    analysis = _cli_json(capsys, "analyze", path, *opts, "--json")
    report = _cli_json(capsys, "report", path, *opts, "--json")
    assert check_same_numbers(analysis, report) > 10


def test_bode_table_report_has_its_plots_and_identification(tmp_path):
    """A Bode table gives a document with its Bode and polar plots and the f0, zeta, U and
    critical speed of ``stand analyze``, each with its ±."""
    path, rmap = SAMPLES / "daq" / "bode_table.csv", SAMPLES / "daq" / "bode_table.map.toml"
    html, js = tmp_path / "b.html", tmp_path / "b.json"
    assert main(["report", str(path), "--map", str(rmap), "-o", str(html),
                 "--json-file", str(js)]) == 0
    doc = json.loads(js.read_text("utf-8"))
    a = doc["analysis"]
    for key in ("natural_frequency_hz", "damping_ratio", "unbalance_gmm", "critical_speed_hz"):
        assert a[key] is not None and a[key + "_std"] > 0, key
    truth = json.loads((SAMPLES / "daq" / "bode_table.truth.json").read_text("utf-8"))
    f0 = truth.get("natural_frequency_hz")
    if f0 is not None:
        assert abs(a["natural_frequency_hz"] - f0) < 5 * a["natural_frequency_hz_std"] + 1e-3 * f0
    page = html.read_text("utf-8")
    assert "Bode plot" in page and "1X polar plot" in page
    assert doc["dynamics"]["natural_frequency"]["identified_hz"] == a["natural_frequency_hz"]


def _scene_cases():
    return [pytest.param(p, id=p.stem) for p in sorted((SAMPLES / "scenes").glob("*.toml"))]


@pytest.mark.parametrize("scene", _scene_cases())
def test_scene_same_numbers(scene, tmp_path, capsys):
    """Each sample scene, run for 2 s (or less), written and read back by both commands."""
    from stand.integrate.simulate import simulate
    from stand.recording.hdf5 import write_recording
    from stand.scene.parse import load_scene

    s = load_scene(scene)
    s = dataclasses.replace(s, run=dataclasses.replace(s.run, duration=min(s.run.duration, 2.0)))
    h5 = write_recording(simulate(s), tmp_path / f"{scene.stem}.h5")
    analysis = _cli_json(capsys, "analyze", h5, "--json")
    report = _cli_json(capsys, "report", h5, "--json")
    assert check_same_numbers(analysis, report) > 5
