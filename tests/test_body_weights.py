"""Body weights on the generic kernel (issue 16): the book models are the oracles.

Each book model of stand/model/balancers (its own rotor, its own dimensionless
right-hand side in Python) is rebuilt as a generic composition -- the planar
rotor 2.5.1 x one body weight of stand/model/rotors/bodies -- and both are
integrated over a transient at rtol 1e-12.  Two independent integrations of
the same equations at that tolerance agree to ~1e-11 over these spans (the
spans are kept where the motion is not sensitive to its initial state: the
book model against itself at rtol 1e-12 vs 1e-13 agrees to <1e-10), so the
bound 1e-8 relative fails for any difference in the equations (a dropped
term changes the shaft motion at the percent level).
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import stand
from stand.model.balancers import damper, gravity_pair, liquid_chamber, liquid_float, two_axis
from stand.theories.weights import liquid_chamber_quasi_static as lqs
from stand.integrate.book_run import STATE_COLUMNS, initial_state
from oracles.book_run import book_rhs as _rhs
from stand.model.balancers.composition import composition
from stand.integrate.driver import run_dop853
from stand.integrate.result import SolverStats
from stand.model.rotors.bodies import LiquidWeight, PlaneBody, body_channels
from stand.integrate.coupled import build_model, initial_state as generic_initial, samples_si
from stand.model.rotors.planar_supports import planar_rotor
from stand.scene.model import SceneError

RTOL = 1e-12


def _generic(comp, ts, omega_ref=1.0):
    model = build_model(comp.rotor, (), comp.programme, omega_ref, (comp.body,))
    y = generic_initial(model, (), comp.q0, comp.qd0)
    if hasattr(comp, "initial_body"):
        o = model.first_body_state
        y[o:o + 3] = comp.initial_body[:3]
        y[o + 3:o + 6] = comp.initial_body[3:] / model.omega_ref
    w = model.omega_ref
    out = np.full((ts.size, y.size), np.nan)
    out[0] = y
    st = SolverStats(method="DOP853", rtol=RTOL, atol=RTOL * 1e-3)
    k = run_dop853(model, y, ts[-1] * w, RTOL, RTOL * 1e-3, ts * w, out, st, 10 ** 8, False)
    assert st.success and k == ts.size
    t, q, qd, phi, speed, _, planes, residual = samples_si(model, out, ts * w)
    coords, _ = body_channels(model.bt, model.bodies, out, w, phi, planes)
    return q, coords[0], residual["balancer"]


def _book(kind, p, ts):
    y0 = initial_state(kind, p, {})
    sol = solve_ivp(_rhs(kind, p), (0, ts[-1]), y0, method="DOP853", rtol=RTOL, atol=1e-16,
                    t_eval=ts)
    assert sol.success
    return y0, sol.y


CASES = {
    "two_axis": two_axis.TwoAxisParams(R_m=0.2, R_omega=2.5, R_g=0.4, h1=0.1, h2=0.1, H=0.05,
                                       e0=0.6),
    "gravity_pair": gravity_pair.GravityPairParams(R_m=0.05, R_omega=3.0, e0=0.5, gamma=0.3),
    "damper": damper.DamperParams(R_m=0.1, R_omega=2.0, R_g=0.3, h=0.3, H=0.3, e0=0.4),
}


@pytest.mark.parametrize("kind", list(CASES))
def test_generic_composition_matches_the_book_model(kind):
    p = CASES[kind]
    ts = np.linspace(0.0, 20.0, 401)
    y0, yb = _book(kind, p, ts)
    q, body, _ = _generic(composition(kind, p, ts[-1], y0), ts)
    cols = STATE_COLUMNS[kind]
    xb, ybk = yb[cols.index("x")], yb[cols.index("y")]
    scale = np.max(np.hypot(xb, ybk))
    assert scale > 0.01                       # a real transient, not a rotor at rest
    assert np.max(np.hypot(q[:, 0] - xb, q[:, 1] - ybk)) / scale < 1e-8
    if kind == "damper":
        n = np.column_stack([body["n_x"], body["n_y"], body["n_z"]])
        assert np.max(np.abs(n - yb[4:7].T)) < 1e-8
    else:
        assert np.max(np.abs(body["tilt"] - yb[0])) < 1e-8
        assert np.max(np.abs(body["angle"] - yb[1])) < 1e-8


def test_liquid_float_run_up_matches_paper_001_model():
    """Paper 001 model M1 through its run-up (speed law (6)) against the lever body."""
    p = liquid_float.LiquidFloatParams(Omega_0=30.0, psi=0.6, n=2.0, e=1e-3, omega_0=5.0,
                                       epsilon=3.0, m1=2.0)
    ts = np.linspace(0.0, 20.0, 2001)
    y0 = initial_state("liquid_float", p, {})
    sol = solve_ivp(_rhs("liquid_float", p), (0, ts[-1]), y0, method="DOP853", rtol=RTOL,
                    atol=1e-16, t_eval=ts)
    q, _, _ = _generic(composition("liquid_float", p, ts[-1], y0), ts, omega_ref=None)
    scale = np.max(np.hypot(sol.y[0], sol.y[1]))
    assert np.max(np.hypot(q[:, 0] - sol.y[0], q[:, 1] - sol.y[1])) / scale < 1e-8


def _chamber_composition(R=0.1, h=0.03, V=4e-4, M=4.0, c=2.0e4, chi=30.0, e=1e-3, tau=0.0,
                         speed=80.0):
    r = math.sqrt(R * R - V / (math.pi * h))
    body = LiquidWeight("liquid_chamber", 1000.0 * V, R, r, height=h, relaxation_time=tau,
                        volume=V)
    rotor = planar_rotor(M, c, c, chi, chi, unbalance=M * e)
    return rotor, PlaneBody("balancer", body), [[0.0, speed]]


def test_liquid_chamber_at_once_is_paper_001_lever():
    """The chamber whose free surface follows at once is model M1 with
    psi = M/(M + m lambda), lambda = R^2/(R^2 - r^2): the same transient to 1e-8."""
    rotor, pb, prog = _chamber_composition(speed=30.0)
    M, m, lam = 4.0, pb.body.mass, pb.body.lever
    c, chi = 2.0e4, 30.0
    p = liquid_float.LiquidFloatParams(Omega_0=math.sqrt(c / M), psi=M / (M + m * lam),
                                       n=chi / M, e=1e-3, omega_0=30.0, epsilon=0.0, m1=M)
    ts = np.linspace(0.0, 3.0, 601)
    sol = solve_ivp(_rhs("liquid_float", p), (0, ts[-1]), np.zeros(4), method="DOP853",
                    rtol=RTOL, atol=1e-16, t_eval=ts)

    class C:
        pass

    comp = C()
    comp.rotor, comp.body, comp.programme = rotor, pb, np.array(prog, float)
    comp.q0 = comp.qd0 = np.zeros(2)
    q, _, _ = _generic(comp, ts, omega_ref=None)
    scale = np.max(np.hypot(sol.y[0], sol.y[1]))
    assert np.max(np.hypot(q[:, 0] - sol.y[0], q[:, 1] - sol.y[1])) / scale < 1e-8


def _steady_alpha0(speed, tau=0.0):
    """Run the chamber to its steady state; return (alpha0, k, delta) of thesis 002."""
    rotor, pb, prog = _chamber_composition(speed=speed, tau=tau)
    M, c, chi = 4.0, 2.0e4, 30.0
    m = pb.body.mass
    Mt = M + m
    model = build_model(rotor, (), prog, None, (pb,))
    y = generic_initial(model, (), None, None)
    w = model.omega_ref
    T = 60.0                               # 60 s >> 1/n = 2 Mt/chi ~ 0.3 s
    ts = np.array([0.0, T - 0.5, T]) * w
    out = np.full((3, y.size), np.nan)
    out[0] = y
    st = SolverStats(method="DOP853", rtol=1e-11, atol=1e-14)
    assert run_dop853(model, y, T * w, 1e-11, 1e-14, ts, out, st, 10 ** 8, False) == 3
    t, q, qd, phi, _, _, planes, residual = samples_si(model, out, ts)
    coords, unb = body_channels(model.bt, model.bodies, out, w, phi, planes)
    D = unb[0][-1, 0] + 1j * unb[0][-1, 1]       # liquid unbalance, rotor frame
    D0 = M * 1e-3                                # rotor unbalance along +x
    alpha0 = abs(np.angle(D))
    k = D0 / abs(D)
    wcr2, n2 = c / Mt, chi / Mt                  # (2.5): tan delta = 2 n w / (w_cr^2 - w^2)
    delta = math.atan2(n2 * speed, wcr2 - speed ** 2)
    return alpha0, k, delta, residual["balancer"][-1]


@pytest.mark.parametrize("speed", [40.0, 55.0, 80.0, 120.0])
def test_liquid_chamber_steady_state_solves_thesis_2_12(speed):
    """Steady state of the dynamic chamber: the liquid's centre of mass lies along the
    deflection, (2.10b), so alpha0 solves (2.12) to 1e-8; above the critical speed of the
    liquid-loaded rotor it is the corrected (2.13), below it the other root of l.814."""
    alpha0, k, delta, _ = _steady_alpha0(speed)
    s2 = math.sin(delta) ** 2
    lhs = math.sin(alpha0)
    rhs = math.sin(delta) * math.sqrt(1 + 2 * k * math.cos(alpha0) + k * k) / k
    assert lhs == pytest.approx(rhs, rel=1e-8, abs=1e-10)
    root = math.sqrt((1 - s2) * (k * k - s2))
    corrected = lqs.equilibrium_angle(k, delta).alpha0
    assert corrected == pytest.approx(math.pi - math.acos((s2 + root) / k), abs=1e-12)
    other = math.acos((-s2 + root) / k)
    rotor, pb, _ = _chamber_composition()
    w_eff = math.sqrt(2.0e4 / (4.0 + pb.body.mass * pb.body.lever))
    expected = corrected if speed > w_eff else other
    assert alpha0 == pytest.approx(expected, abs=1e-8)


def test_liquid_chamber_relaxation_keeps_the_steady_state():
    """A free surface that relaxes (tau_l > 0) reaches the same steady state as the
    instant one: the relaxation only shapes the transient."""
    a0, k0, _, U0 = _steady_alpha0(80.0, tau=0.0)
    a1, k1, _, U1 = _steady_alpha0(80.0, tau=0.05)
    assert a1 == pytest.approx(a0, abs=1e-7)
    assert k1 == pytest.approx(k0, rel=1e-7)
    assert np.allclose(U1, U0, rtol=1e-6, atol=1e-12)


SCENE = """
[rotor]
mass = 3.0
eccentricity = 2.0e-4
[supports]
stiffness_x = 3.0e4
stiffness_y = 3.0e4
damping_x = 20.0
damping_y = 20.0
[[weights]]
{weights}
[drive]
type = "speed"
programme = [[0.0, 0.0], [2.0, 20.0]]
[run]
duration = 3.0
sample_rate = 400.0
"""

BAD = [
    ('type = "liquid_chamber"\nchamber_radius = 0.1\nchamber_height = 0.03\nfill_volume = -1e-4',
     r"weights\[0\]\.fill_volume = -0\.0001: must be > 0 \(m\^3\)"),
    ('type = "liquid_chamber"\nchamber_radius = 0.1\nchamber_height = 0.03\nfill_volume = 1e-3',
     r"weights\[0\]\.fill_volume = 0\.001: must be < the chamber's volume .* \(m\^3"),
    ('type = "two_axis_pendulum"\nmass = 0.1\narm = 0.06\nhousing_radius = 0.05',
     r"weights\[0\]\.arm = 0\.06: must be < housing_radius = 0\.05 \(m"),
    ('type = "damper"\nmass = 0.1\narm = 0.05\ninertia = 1e-5',
     r"weights\[0\]\.inertia = 1e-05: must be >= m l\^2 = 0\.00025 \(kg\*m\^2"),
    ('type = "liquid_float"\nliquid_mass = 0.2\nchamber_radius = 0.05\nfloat_radius = 0.06',
     r"weights\[0\]\.float_radius = 0\.06: must be < chamber_radius = 0\.05 \(m\)"),
    ('type = "sand"\nmass = 0.1', r"weights\[0\]\.type = .*sand.*two_axis_pendulum"),
]


@pytest.mark.parametrize("body,message", BAD)
def test_bad_body_weights_name_key_value_unit(tmp_path, body, message):
    p = tmp_path / "bad.toml"
    p.write_text(SCENE.format(weights=body))
    with pytest.raises(SceneError, match=message):
        stand.load(p)


def test_bad_body_weight_cli_one_line(tmp_path, capsys):
    p = tmp_path / "bad.toml"
    p.write_text(SCENE.format(weights=BAD[0][0]))
    from stand.cli.main import main

    assert main(["run", str(p), "-o", str(tmp_path / "o.h5")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "fill_volume" in err and "m^3" in err


MIXED = """
[structure]
type = "two_mass"
body_mass = 4.0
rotor_mass = 2.0
body_stiffness = 4.0e4
rotor_stiffness = 6.0e4
body_damping = 20.0
rotor_damping = 5.0
unbalance = 2.0e-4
[[weights]]
plane = "balancer"
type = "balls"
count = 2
mass = 0.02
radius = 0.05
drag = 0.5
[[weights]]
plane = "body"
type = "liquid_chamber"
chamber_radius = 0.08
chamber_height = 0.02
fill_volume = 2.0e-4
[drive]
type = "speed"
programme = [[0.0, 0.0], [2.0, 25.0]]
[run]
duration = 3.0
sample_rate = 500.0
"""


def test_mixed_balls_and_liquid_on_a_two_mass_rotor(tmp_path):
    """A ball balancer in one plane and a liquid chamber in the other: both run, both are in
    the run, and each plane's residual adds its own weights' unbalance."""
    text = MIXED
    p = tmp_path / "mixed.toml"
    p.write_text(text)
    run = stand.run(stand.load(p))
    assert run.success
    assert {"ball1", "ball2", "liquid1"} <= set(run.weights)
    assert run.weight_planes["liquid1"] == "body"
    assert np.all(np.isfinite(run.weights["liquid1"]["liquid_x"]))
    # the body plane's residual is the liquid's unbalance alone (the rotor's is in "balancer")
    lq = run.weights["liquid1"]
    d = 1000.0 * 2.0e-4 * (lq["liquid_x"] + 1j * lq["liquid_y"]) * np.exp(-1j * run.rotor_angle)
    U = run.truth["residual/body"][0]
    assert np.allclose(U[:, 0] + 1j * U[:, 1], d, atol=1e-15)


def test_weights_capacity_per_plane_and_all(tmp_path):
    """Scene.weights_capacity, the one capacity S of the stand: the balls' sum m l in their
    plane, the liquid's own capacity in its plane, both summed for None; the rings use the
    main plane's and refuse a scene without weights."""
    from stand.instruments.rings import _capacity

    p = tmp_path / "mixed.toml"
    p.write_text(MIXED)
    sc = stand.load(p)
    liquid = sc.bodies[0].body.capacity
    assert liquid > 0
    assert sc.weights_capacity("balancer") == pytest.approx(2 * 0.02 * 0.05, rel=1e-15)
    assert sc.weights_capacity("body") == liquid
    assert sc.weights_capacity() == pytest.approx(2 * 0.02 * 0.05 + liquid, rel=1e-15)
    assert sc.weights_capacity("rotor") == 0.0 and _capacity(sc) == sc.weights_capacity("balancer")
    bare = stand.load("data_samples/scenes/no_balancer.toml")
    assert bare.weights_capacity() == 0.0
    with pytest.raises(SceneError, match="capacity S = 0"):
        _capacity(bare)


def test_body_channels_in_the_recording(tmp_path):
    p = tmp_path / "d.toml"
    p.write_text(SCENE.format(weights='type = "damper"\nmass = 0.1\narm = 0.03\ndrag = 1e-3\n'
                                      'initial_tilt = 10.0'))
    run = stand.run(stand.load(p))
    assert run.success
    out = tmp_path / "d.h5"
    stand.save(run, out)
    rec = stand.read(out)
    n = np.column_stack([rec.weights["damper1"][c] for c in ("n_x", "n_y", "n_z")])
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-9)
    # the truth residual is rotor unbalance + m l n_h in the rotor frame
    U = rec.truth["residual/balancer"][0]
    phi = rec.rotor_angle
    d = 0.1 * 0.03 * (n[:, 0] + 1j * n[:, 1]) * np.exp(-1j * phi)
    assert np.allclose(U[:, 0] + 1j * U[:, 1], 3.0 * 2e-4 + d, atol=1e-12)


def test_si_scene_and_its_book_parameters_move_alike(tmp_path):
    """A planar SI scene with a two-axis pendulum and the book model of its parameters
    (composition.book_params, (6.9)-(6.11)) give the same motion: x_book = x l / rho1^2
    at tau = omega0 t (the scalings checked both ways)."""
    from stand.model.balancers.composition import book_params

    p = tmp_path / "s.toml"
    p.write_text(SCENE.replace('programme = [[0.0, 0.0], [2.0, 20.0]]',
                               'programme = [[0.0, 25.0]]').replace("duration = 3.0",
                                                                     "duration = 1.0")
                 .format(weights='type = "two_axis_pendulum"\nmass = 0.1\narm = 0.03\n'
                                 'inertia_tilt = 1.2e-4\ninertia_axial = 1.0e-4\n'
                                 'tilt_drag = 2e-4\nturn_drag = 3e-4\ninitial_tilt = 5.0'))
    sc = stand.load(p)
    run = stand.run(sc, rtol=1e-12, atol=1e-15)
    kind, bp = book_params(sc)
    assert kind == "two_axis"
    Ms, w0 = 3.1, math.sqrt(3.0e4 / 3.1)
    y0 = np.array([math.radians(5.0), 0.0, 0.0, 0.0, 0.0, bp.R_omega, 0.0, 0.0])
    ts = run.t * w0
    yb = solve_ivp(_rhs("two_axis", bp), (0, ts[-1]), y0, method="DOP853", rtol=RTOL,
                   atol=1e-16, t_eval=ts).y
    scale = 0.03 / (1.2e-4 / 0.1)                      # l / rho1^2 [1/m]
    zb = yb[2] + 1j * yb[3]
    z = (run.x + 1j * run.y) * scale
    assert np.max(np.abs(z - zb)) / np.max(np.abs(zb)) < 1e-8
    assert np.max(np.abs(run.weights["two_axis1"]["tilt"] - yb[0])) < 1e-8


def test_theory_of_a_body_scene_holds_the_book_model(tmp_path, capsys):
    """stand theory on an SI scene with one liquid chamber: the structure's natural
    frequencies (liquid locked) and the thesis's optimal fill and liquid choice."""
    import json

    from stand.cli.main import main

    p = tmp_path / "c.toml"
    p.write_text(SCENE.format(weights='type = "liquid_chamber"\nchamber_radius = 0.1\n'
                                      'chamber_height = 0.03\nfill_volume = 2e-4'))
    assert main(["theory", str(p), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    (wm,) = doc["weight_models"]
    assert wm["type"] == "liquid_chamber" and wm["plane"] == "balancer"
    # locked liquid: the damped frequency of c = 3e4 N/m, d = 20 N s/m, M + rho V = 3.2 kg
    wn, zeta = math.sqrt(3.0e4 / 3.2), 20.0 / (2 * math.sqrt(3.0e4 * 3.2))
    assert doc["natural_frequencies_hz_at_rest"][0] == pytest.approx(
        wn * math.sqrt(1 - zeta ** 2) / (2 * math.pi), rel=1e-9)
    ov = wm["optimal_volume"]
    assert ov["D0_kg_m"] == pytest.approx(3.0 * 2e-4, rel=1e-12)
    assert wm["liquid_choice"]["chosen"]


@pytest.mark.parametrize("kind", ["two_axis", "gravity_pair", "damper"])
def test_book_steady_motions_are_equilibria_of_the_derived_rotating_form(kind):
    """The books' steady motions ((6.12) steady states, (7.6), (7.51)) are equilibria of
    the rotating-frame form derived from the one fixed-frame composition
    (stand.theories.rotating) to 1e-10."""
    from stand.theories.weights import damper_steady, gravity_pair_steady, two_axis_steady
    from stand.theories.rotating import rotating_rhs

    p = CASES[kind]
    comp = composition(kind, p, 1.0)
    model = build_model(comp.rotor, (), comp.programme, 1.0, (comp.body,))
    o, L = model.first_body_state, model.scale[0]
    if kind == "two_axis":
        motions = [m.state for m in two_axis_steady.steady_motions(p)]
    elif kind == "gravity_pair":
        motions = [m.state for m in gravity_pair_steady.steady_motions(p)]
    else:
        motions = [m.state(p.R_omega) for m in damper_steady.steady_motions(p)]
    assert motions
    for s in motions:
        z = np.zeros(model.size)
        if kind == "damper":     # [xi, eta, xi', eta', n (3), W (3)], rotating components
            z[0], z[1] = s[0] / L, s[1] / L
            z[o:o + 3] = s[4:7]
            z[o + 3:o + 6] = s[7:10]
        else:                    # [phi, psi, xi, eta, ...] at rest in the rotating frame
            z[0], z[1] = s[2] / L, s[3] / L
            z[o], z[o + 1] = s[0], s[1]
        dz = rotating_rhs(model, p.R_omega, z)
        assert np.max(np.abs(dz)) < 1e-10, (kind, s, dz)


def test_bodies_on_the_spatial_rigid_rotor():
    """A two-axis pendulum and a relaxing liquid chamber in one plane of the spatial rigid
    rotor (2.7): the run succeeds and the plane's truth residual is the rotor's unbalance
    plus both bodies' mass x centre-of-mass offset (rotor frame)."""
    from pathlib import Path

    sc = stand.load(Path(__file__).parent / "data" / "spatial_bodies.toml")
    assert sc.structure_type == "spatial" and len(sc.bodies) == 2
    run = stand.run(sc)
    assert run.success
    e = np.exp(-1j * run.rotor_angle)
    pend, liq = run.weights["two_axis1"], run.weights["liquid1"]
    d_p = 0.05 * 0.02 * np.sin(pend["tilt"]) * (-np.sin(pend["angle"]) + 1j * np.cos(pend["angle"]))
    d_l = sc.bodies[1].body.mass * (liq["liquid_x"] + 1j * liq["liquid_y"])
    U = run.truth["residual/balancer1"][0]
    rotor_u = sum(u.s * np.exp(1j * u.angle) for u in sc.linear_rotor().unbalances
                  if u.plane == "balancer1")
    assert np.allclose(U[:, 0] + 1j * U[:, 1], rotor_u + (d_p + d_l) * e, atol=1e-15)


@pytest.mark.parametrize("kind,table", [
    ("two_axis_pendulum", "{ R_m = 0.02, R_rho = 0.7, R_g = 0.4, h1 = 0.1, h2 = 0.2 }"),
    ("damper", "{ R_m = 0.02, R_g = 0.3, h = 0.25 }")])
def test_dimensionless_sugar_round_trips(tmp_path, kind, table):
    """The book's dimensionless form of a body weight (with its SI mass and arm) gives back
    the same book parameters (composition.book_params)."""
    from stand.model.balancers.composition import book_params

    p = tmp_path / "d.toml"
    p.write_text(SCENE.format(weights=f'type = "{kind}"\nmass = 0.1\narm = 0.03\n'
                                      f'dimensionless = {table}'))
    _, bp = book_params(stand.load(p))
    want = dict(x.split("=") for x in table.strip("{} ").replace(" ", "").split(","))
    for k, v in want.items():
        assert getattr(bp, k) == pytest.approx(float(v), rel=1e-12), k
