"""dsp.unbalance: 1X order tracking, model inversion, rings, ISO 21940-11 (issue 5 item 2)."""
import math
try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib
from pathlib import Path

import numpy as np
import pytest

from dsp.errors import SignalError
from dsp.unbalance import (ISO_GRADES_MM_S, iso_21940_grade, iso_21940_permissible,
                           reduction_factor, synchronous_component, unbalance_from_response,
                           unbalance_from_rings)

ROOT = Path(__file__).resolve().parents[1]
SPEED_REV_S = 15.0


@pytest.fixture(scope="module")
def no_balancer_run():
    """no_balancer.toml held at a constant 15 rev/s (supercritical, R = 4.95) for 20 s."""
    from stand.scene.parse import parse_scene
    from stand.integrate.simulate import simulate

    data = tomllib.loads((ROOT / "data_samples/scenes/no_balancer.toml").read_text())
    data["drive"]["programme"] = [[0.0, SPEED_REV_S], [1.0, SPEED_REV_S]]
    data["run"]["duration"] = 20.0
    tr = simulate(parse_scene(data))
    assert tr.success
    sel = tr.t >= 10.0          # transient decays as exp(-zeta w1 t), zeta w1 ~ 0.96 /s
    M = data["rotor"]["mass"]
    k = data["supports"]["stiffness"]
    c = data["supports"]["damping"]
    model = dict(mass_kg=M, natural_frequency_hz=math.sqrt(k / M) / (2 * math.pi),
                 damping_ratio=c / (2 * math.sqrt(k * M)))
    truth = dict(U=M * data["rotor"]["eccentricity"],
                 beta=math.radians(data["rotor"]["unbalance_angle"]))
    return tr, sel, model, truth


def _check_unbalance(sc, model, truth):
    u = unbalance_from_response(sc, sc.speed_rad_s, **model)
    assert u.unbalance_kg_m == pytest.approx(truth["U"], rel=0.01)   # acceptance: 1 %
    assert u.unbalance_kg_m == pytest.approx(truth["U"], rel=1e-4)   # achieved
    assert abs(np.angle(np.exp(1j * (u.angle_rad - truth["beta"])))) < math.radians(0.1)
    assert u.unbalance_gmm == pytest.approx(truth["U"] * 1e6, rel=1e-4)
    assert u.speed_ratio > 1.1                                       # supercritical band
    return u


def test_unbalance_of_no_balancer_from_rotor_angle(no_balancer_run):
    tr, sel, model, truth = no_balancer_run
    sc = synchronous_component(tr.t[sel], tr.x[sel], tr.y[sel], rotor_angle=tr.rotor_angle[sel])
    assert sc.revolutions == 150
    assert sc.speed_rad_s == pytest.approx(2 * math.pi * SPEED_REV_S, rel=1e-9)
    # supercritical: the shaft deflects toward the light side, ~180 deg from the heavy spot
    assert abs(abs(sc.phase_deg) - 180.0) < 5.0
    _check_unbalance(sc, model, truth)


def test_unbalance_of_no_balancer_from_keyphasor(no_balancer_run):
    tr, sel, model, truth = no_balancer_run
    n = int(tr.rotor_angle[-1] // (2 * math.pi))
    pulses = np.interp(2 * math.pi * np.arange(n + 1), tr.rotor_angle, tr.t)
    sc = synchronous_component(tr.t[sel], tr.x[sel], tr.y[sel], keyphasor_times=pulses)
    ref = synchronous_component(tr.t[sel], tr.x[sel], tr.y[sel], rotor_angle=tr.rotor_angle[sel])
    assert abs(sc.vector_m - ref.vector_m) < 1e-6 * abs(ref.vector_m)
    _check_unbalance(sc, model, truth)


def test_wrapped_rotor_angle_and_noise_uncertainty():
    rng = np.random.default_rng(1)
    fs, w, A, ph = 1000.0, 2 * math.pi * 12.3, 1e-3, 0.7
    t = np.arange(0, 5.0, 1 / fs)
    phi = w * t + 0.3
    z = A * np.exp(1j * (phi + ph)) + 0.2e-3 * np.exp(1j * 2 * math.pi * 3.1 * t)
    sigma = 1e-4
    x = z.real + sigma * rng.standard_normal(t.size)
    y = z.imag + sigma * rng.standard_normal(t.size)
    sc = synchronous_component(t, x, y, rotor_angle=np.mod(phi, 2 * math.pi))
    assert sc.revolutions == int((phi[-1]) // (2 * math.pi)) - 1 + (phi[0] <= 0)
    err = abs(sc.vector_m - A * np.exp(1j * ph))
    assert err < 4 * math.sqrt(2) * sc.vector_std_m + 0.02 * A
    assert sc.amplitude_std_m > 0 and sc.phase_std_rad > 0
    assert sc.speed_rad_s == pytest.approx(w, rel=1e-9)


def test_rings_zone_and_half_zone():
    S = 0.01                                  # kg m
    radii = np.linspace(0.0, 20 * 0.5e-3, 21)  # ring i at i * 0.5 mm (zones 0..20)
    r = unbalance_from_rings(3.2 * 0.5e-3, radii, S)
    assert r.zone == 3 and not r.off_scale
    assert r.unbalance_kg_m == pytest.approx(3 * S / 16)
    assert r.unbalance_std_kg_m == pytest.approx(S / 32)
    assert r.unbalance_gmm == pytest.approx(3 * S / 16 * 1e6)
    assert r.interpolated_kg_m == pytest.approx(3.2 * S / 16)
    assert unbalance_from_rings(0.0, radii, S).zone == 0
    far = unbalance_from_rings(1.0, radii, S)
    assert far.zone == 20 and far.off_scale
    assert far.interpolated_kg_m == pytest.approx(2000 * S / 16)   # linear extrapolation
    with pytest.raises(ValueError, match="ring_radii_m"):
        unbalance_from_rings(1e-3, [0.0, 2e-3, 1e-3], S)
    with pytest.raises(SignalError, match="radius_m"):
        unbalance_from_rings(float("nan"), radii, S)


def test_iso_21940():
    m, w = 4.45, 2 * math.pi * 15.0
    U = iso_21940_permissible(6.3, m, w)
    assert U == pytest.approx(1000 * 6.3 * 4.45 / w)          # 297.5 g mm
    g = iso_21940_grade(U, m, w, target_grade_mm_s=6.3)
    assert g.grade_mm_s == pytest.approx(6.3) and g.passed and g.grade_class == 6.3
    assert g.permissible_gmm == pytest.approx(U)
    g = iso_21940_grade(3600.0, m, w, target_grade_mm_s=40, unbalance_std_gmm=36.0)
    assert g.grade_mm_s == pytest.approx(3600 * w / (1000 * m))   # 76.2 mm/s
    assert g.grade_class == 100.0 and g.label == "G 100" and g.passed is False
    assert g.grade_std_mm_s == pytest.approx(0.01 * g.grade_mm_s)
    assert iso_21940_grade(1e9, m, w).grade_class is None
    assert iso_21940_grade(0.0, m, w).grade_class == ISO_GRADES_MM_S[0]
    with pytest.raises(ValueError, match="rotor_mass_kg"):
        iso_21940_permissible(6.3, 0.0, w)


def test_reduction_factor():
    r = reduction_factor(3600.0, 36.0, before_std=36.0, after_std=0.36)
    assert r.factor == pytest.approx(100.0)
    assert r.percent == pytest.approx(99.0)
    assert r.decibel == pytest.approx(40.0)
    assert r.factor_std == pytest.approx(100 * math.hypot(0.01, 0.01))
    assert reduction_factor(1.0, 0.0).factor == math.inf


# ------------------------------------------------------------------ bad signals

def _clean(n=2000, fs=200.0, f=15.0):
    t = np.arange(n) / fs
    phi = 2 * math.pi * f * t
    z = 1e-3 * np.exp(1j * phi)
    return t, z.real.copy(), z.imag.copy(), phi


def test_bad_no_keyphasor_pulse():
    t, x, y, _ = _clean()
    with pytest.raises(SignalError, match="no keyphasor pulse"):
        synchronous_component(t, x, y, keyphasor_times=[])
    with pytest.raises(SignalError, match="no keyphasor pulse within"):
        synchronous_component(t, x, y, keyphasor_times=[100.0, 101.0])
    with pytest.raises(SignalError, match="only one keyphasor pulse"):
        synchronous_component(t, x, y, keyphasor_times=[1.0])
    with pytest.raises(SignalError, match="no phase reference"):
        synchronous_component(t, x, y)


def test_bad_too_short():
    t, x, y, phi = _clean(n=20)                  # 0.1 s = 1.5 revolutions
    with pytest.raises(SignalError, match="too short"):
        synchronous_component(t, x, y, rotor_angle=phi)
    t, x, y, phi = _clean()
    with pytest.raises(SignalError, match="too short"):       # two pulses = one revolution
        synchronous_component(t, x, y, keyphasor_times=[1 / 15, 2 / 15])


def test_bad_constant_nan_inf_time():
    t, x, y, phi = _clean()
    with pytest.raises(SignalError, match="constant"):
        synchronous_component(t, np.full_like(x, 1e-3), np.zeros_like(y), rotor_angle=phi)
    for bad in (np.nan, np.inf):
        xb = x.copy()
        xb[7] = bad
        with pytest.raises(SignalError, match="non-finite"):
            synchronous_component(t, xb, y, rotor_angle=phi)
    pb = phi.copy()
    pb[3] = np.nan
    with pytest.raises(SignalError, match="rotor_angle"):
        synchronous_component(t, x, y, rotor_angle=pb)
    tb = t.copy()
    tb[10], tb[11] = tb[11], tb[10]
    with pytest.raises(SignalError, match="strictly increasing"):
        synchronous_component(tb, x, y, rotor_angle=phi)
    with pytest.raises(SignalError, match="same length"):
        synchronous_component(t, x[:-1], y, rotor_angle=phi)


def test_bad_rotor_not_turning_forward_or_aliased():
    t, x, y, phi = _clean()
    with pytest.raises(SignalError, match="turning forward"):
        synchronous_component(t, x, y, rotor_angle=-phi)
    # 150 rev/s sampled at 200 Hz: 270 deg per sample, unwrap cannot follow
    t, x, y, phi = _clean(f=150.0)
    with pytest.raises(SignalError):
        synchronous_component(t, x, y, rotor_angle=phi)
