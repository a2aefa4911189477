"""Balancing without a phase reference (issue 41 item 2): the four-run method.

The oracle is the forward model alone: a known influence coefficient ``h`` and correction
``U0`` give the reference vibration ``V0 = -h U0`` and the trial runs' amplitudes
``|V0 + T exp(i theta) h|``; a meter shows them rounded to its resolution ``r``
(uniform error, sigma = r / sqrt 12).
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from dsp.amplitude_only import four_run, resolution_sigma
from stand.analysis.field_balance import balance_job
from stand.analysis.field_job import parse_job
from stand.cli.main import main
from stand.io.tomlfile import tomllib

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "data_samples" / "balance" / "four_run.toml"
CLASSIC = np.radians([0.0, 120.0, 240.0])


def _readings(h, U0, T, theta, resolution=0.0):
    V0 = -h * U0
    A = np.abs(V0 + T * np.exp(1j * np.asarray(theta)) * h)
    a0 = abs(V0)
    if resolution:
        a0, A = np.round(a0 / resolution) * resolution, np.round(A / resolution) * resolution
    return a0, A


def _angle_err_deg(a_rad, b_rad):
    return abs((math.degrees(a_rad - b_rad) + 180.0) % 360.0 - 180.0)


def test_exact_readings_give_the_correction_exactly():
    h, U0 = 0.8 * np.exp(1j * np.radians(40)), 2.0 * np.exp(1j * np.radians(250))
    a0, A = _readings(h, U0, 1.5, CLASSIC)
    r = four_run(a0, A, 1.5, CLASSIC)
    # exact model, exact readings: only floating point separates the answer from the truth
    assert r.mass == pytest.approx(2.0, rel=1e-9)
    assert _angle_err_deg(r.angle_rad, np.radians(250)) < 1e-7
    assert abs(r.h[0]) == pytest.approx(0.8, rel=1e-9)
    assert r.after[0] == pytest.approx(0.0, abs=1e-9)
    assert r.warnings == []


def test_acceptance_within_half_percent_and_half_degree():
    """Trial at 0, 120, 240 deg, readings to 0.01 mm/s of ~10 mm/s: the ± is ~0.1 % / 0.1 deg,
    so 0.5 % / 0.5 deg is a >= 4 sigma bound that a wrong method (or a mirror) would break."""
    h, U0 = 0.25 * np.exp(1j * np.radians(30)), 35.0 * np.exp(1j * np.radians(200))
    a0, A = _readings(h, U0, 20.0, CLASSIC, resolution=0.01)
    r = four_run(a0, A, 20.0, CLASSIC, sigma=resolution_sigma(0.01))
    assert r.mass_std / r.mass < 0.125e-2 and math.degrees(r.angle_std_rad) < 0.125
    assert r.mass == pytest.approx(35.0, rel=0.005)
    assert _angle_err_deg(r.angle_rad, np.radians(200)) < 0.5
    assert abs(r.h[0]) == pytest.approx(0.25, rel=0.005)


@pytest.mark.parametrize("jobs", [12, pytest.param(300, marks=pytest.mark.full)])
def test_uncertainty_covers_the_truth_over_random_cases(jobs):
    """Readings rounded to 0.1 mm/s: |error| / sigma of the mass and of the angle is within
    2 sigma in >= 90 % of 300 random jobs (95 % for a normal error), and not absurdly
    conservative (the median |z| of a normal error is 0.67; a ± ten times too large gives 0.07).

    The default run draws the first 12 of the same jobs (0.14 s each; the 300 with ``-m
    full``): 24 values of z, at most 4 outside 2 sigma (binomial at 5 %: 5 or more has
    probability 0.7 %), and the median's bounds 0.3-1.2 are -2.3 and +3.3 of its spread at
    n = 24 (1 / (2 f(0.67) sqrt 24) = 0.16); a ± 3x too small or 10x too large fails both."""
    rng = np.random.default_rng(41)
    z = []
    for _ in range(jobs):
        V0 = rng.uniform(4.0, 20.0)                       # mm/s
        h = rng.uniform(0.1, 1.0) * np.exp(1j * rng.uniform(0, 2 * np.pi))
        U0 = -V0 / h
        T = rng.uniform(0.3, 1.0) * abs(U0)               # a trial changing the vibration 30..100 %
        theta = CLASSIC + rng.uniform(0, 2 * np.pi)
        a0, A = _readings(h, U0, T, theta, resolution=0.1)
        r = four_run(a0, A, T, theta, sigma=resolution_sigma(0.1))
        z.append((r.mass - abs(U0)) / r.mass_std)
        z.append(_angle_err_deg(r.angle_rad, np.angle(U0)) / math.degrees(r.angle_std_rad))
    z = np.abs(np.array(z))
    assert np.mean(z <= 2.0) >= (0.90 if jobs >= 300 else 20 / 24)
    assert 0.3 < np.median(z) < 1.2


def test_bunched_trial_positions_warn_of_the_mirror():
    h, U0 = 0.25 * np.exp(1j * np.radians(30)), 35.0 * np.exp(1j * np.radians(200))
    theta = np.radians([0.0, 4.0, 8.0])
    a0, A = _readings(h, U0, 20.0, theta, resolution=0.1)
    r = four_run(a0, A, 20.0, theta, sigma=resolution_sigma(0.1))
    # two corrections fit within the meter's rounding: the answer is not to be trusted, and the
    # warning names the other one (here the truth, 35 g @ 200 deg, to its ±)
    assert len(r.warnings) == 1 and "mirror" in r.warnings[0] and "0, 120, 240" in r.warnings[0]
    other = re.search(r"second correction ([\d.]+) @ ([\d.]+) deg", r.warnings[0])
    found = [(r.mass, math.degrees(r.angle_rad)), (float(other[1]), float(other[2]))]
    assert any(abs(m - 35.0) < 1.5 and abs((a - 200.0 + 180) % 360 - 180) < 5 for m, a in found)
    # spread out, the same trial gives one answer and no warning
    a0, A = _readings(h, U0, 20.0, CLASSIC, resolution=0.1)
    assert four_run(a0, A, 20.0, CLASSIC, sigma=resolution_sigma(0.1)).warnings == []


@pytest.mark.parametrize("angles, amplitudes, words", [
    ([0.0, 180.0, 0.0], [9.0, 7.0, 9.0], ["0, 180 deg", "3 or more distinct angles"]),
    ([0.0, 120.0, 240.0], [8.8, 8.8, 8.8], ["trial mass too small", "larger trial mass"]),
])
def test_bad_inputs_one_line(angles, amplitudes, words):
    with pytest.raises(ValueError) as e:
        four_run(8.8, amplitudes, 20.0, np.radians(angles), sigma=resolution_sigma(0.1))
    msg = str(e.value)
    assert "\n" not in msg
    for w in words:
        assert w in msg


# ------------------------------------------------------------------ the job file and the CLI
def test_amplitude_only_reading_and_its_resolution():
    job = parse_job(tomllib.loads(SAMPLE.read_text()))
    assert job.amplitude_only
    r = job.runs[0]
    assert r.readings["S1"] == pytest.approx(8.8e-3)                  # mm/s -> m/s
    assert r.std["S1"] == pytest.approx(0.1e-3 / math.sqrt(12))        # last digit 0.1 mm/s


def test_sample_job_api_and_cli(capsys):
    # the sample is synthetic: 35 g @ 200 deg, readings rounded to 0.1 mm/s
    res = balance_job(SAMPLE)
    c = res["corrections"]["P1"]
    assert abs(c["mass"] - 35.0) <= 3 * c["mass_std"]
    assert abs((c["angle_deg"] - 200.0 + 180) % 360 - 180) <= 3 * c["angle_std_deg"]
    assert 0.1 < c["mass_std"] < 1.0
    assert main(["balance", str(SAMPLE)]) == 0
    out = capsys.readouterr().out
    m = re.search(r"P1: ([\d.]+) ± ([\d.]+) g @ ([\d.]+) ± ([\d.]+) °", out)
    assert m, out
    assert float(m.group(1)) == pytest.approx(c["mass"], abs=0.01)
    assert float(m.group(3)) == pytest.approx(c["angle_deg"], abs=0.01)
    assert "four_run" in out


def test_sample_job_report_shows_amplitudes_without_angles(tmp_path):
    html = tmp_path / "four_run.html"
    assert main(["balance", str(SAMPLE), "-o", str(html)]) == 0
    text = re.sub(r"<[^>]+>", " ", html.read_text())
    # the meter's readings as written, with their rounding's sigma (0.1 / sqrt 12), no angle
    assert "S1 13.600 ± 0.029" in text
    assert not re.search(r"S1 13\.6\S* ± 0\.029 mm/s at", text)


_HEAD = '[job]\nvibration_unit = "mm/s"\n[planes.P1]\n[[run]]\nkind = "reference"\n'


def _trials(*runs):
    return "".join(f'[[run]]\nkind = "trial"\ntrial = {{ P1 = "{t}" }}\nreadings = {{ S1 = "{a}" }}\n'
                   for t, a in runs)


@pytest.mark.parametrize("body, words", [
    (_HEAD + 'readings = { S1 = "8.8" }\n' + _trials(("20 @ 0", "13.6 @ 10"), ("20 @ 120", "9.3")),
     ["amplitude-only", "run[1].readings.S1", "has a phase", "every reading"]),
    (_HEAD + 'readings = { S1 = "8.8" }\n' + _trials(("20 @ 0", "13.6"), ("20 @ 120", "9.3")),
     ["3 or more distinct angles"]),
    (_HEAD + 'readings = { S1 = "8.8" }\n'
     + _trials(("20 @ 0", "8.8"), ("20 @ 120", "8.8"), ("20 @ 240", "8.8")),
     ["S1: the trial runs", "trial mass too small"]),
    (_HEAD + 'readings = { S1 = "8.8" }\n[planes.P2]\n'
     + _trials(("20 @ 0", "13.6"), ("20 @ 120", "9.3"), ("20 @ 240", "5.9")),
     ["one plane", "@ angle"]),
])
def test_bad_amplitude_only_job_one_line_exit_2(tmp_path, capsys, body, words):
    f = tmp_path / "job.toml"
    f.write_text(body)
    assert main(["balance", str(f)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "error" in err, err
    for w in words:
        assert w in err, err
