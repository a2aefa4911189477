"""One scene language (issue 39 item 6, issue 40 item 4): the planar rotor written as
``[rotor]``/``[supports]``/``[balancer]`` or as ``[structure] type = "planar"`` with
``[[weights]]`` is one Scene and one run, bit for bit; the planar ``[balancer]`` takes the
dry-friction keys and ``rolling`` of a ball ``[[weights]]`` table with the same meaning; every
angle of a scene file is in degrees -- ``[structure]`` angles included, a unit string may say
otherwise (a file may declare ``[scene] language``; undeclared is language 2, degrees);
recordings written before the rule (scene language 1) still read their angles in rad.  (docs/scene.md, the scene
language rules.)
"""
from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

import stand
from stand.integrate.simulate import simulate
from stand.scene.model import SCENE_LANGUAGE, SceneError
from stand.scene.parse import load_scene, parse

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "data_samples" / "scenes"
RECS = ROOT / "data_samples" / "recordings"

# the universal stand of ball_runup.toml (4.45 kg rotor, two 45 g balls on 80 mm, f0 = 3 Hz),
# 3 s of its run-up: the balls move, the friction acts, the sticking state rises and falls
M, E, C, H = 4.45, 8.0899e-4, 1613.09, 8.5577
BALLS = """type = "balls"
count = 2
mass = 0.045
radius = 0.08
drag = 0.16965
initial_angles = [150.0, 210.0]
"""
FRICTION = """friction = 2.0e-3
static_friction = 0.01
slip_speed = 0.05
dwell_time = 0.2
release_time = 0.02
"""
TAIL = """
[drive]
type = "speed"
programme = [[0.0, 0.0], [10.0, 15.0]]

[run]
duration = 3.0
sample_rate = 200.0
"""


def planar_text(extra: str, unbalance_angle=25.0) -> str:
    """The planar form: [rotor], [supports], [balancer] with ``extra`` keys."""
    angle = f'"{unbalance_angle}"' if isinstance(unbalance_angle, str) else repr(unbalance_angle)
    return (f"[rotor]\nmass = {M!r}\neccentricity = {E!r}\nunbalance_angle = {angle}\n"
            f"[supports]\nstiffness = {C!r}\ndamping = {H!r}\n"
            f"[balancer]\n{BALLS}{extra}" + TAIL)


def weights_text(extra: str, unbalance_angle=25.0, language: str = "language = 2\n",
                 unbalance: str = f"unbalance = {M * E!r}") -> str:
    """The same stand written as [structure] type = "planar" with the balls in [[weights]]
    (``language``: the [scene] declaration, "" for none)."""
    angle = unbalance_angle if isinstance(unbalance_angle, str) else repr(unbalance_angle)
    angle = f'"{angle}"' if isinstance(unbalance_angle, str) else angle
    return ((f"[scene]\n{language}" if language else "")
            + f'[structure]\ntype = "planar"\nmass = {M!r}\nstiffness_x = {C!r}\nstiffness_y = {C!r}\n'
            f"damping_x = {H!r}\ndamping_y = {H!r}\n{unbalance}\n"
            f"unbalance_angle = {angle}\n"
            f'[[weights]]\nplane = "balancer"\n{BALLS}{extra}' + TAIL)


def _agreement(a, b) -> tuple:
    """(largest shaft distance / largest whirl radius, largest weight-angle difference [rad])."""
    scale = np.max(np.hypot(a.x, a.y))
    return (float(np.max(np.hypot(a.x - b.x, a.y - b.y)) / scale),
            float(np.max(np.abs(a.weight_angle - b.weight_angle))))


def _same_scene(a, b) -> None:
    """Every field of two Scenes equal (arrays element for element), but the text."""
    for f in dataclasses.fields(a):
        if f.name == "text":
            continue
        x, y = getattr(a, f.name), getattr(b, f.name)
        if f.name == "balancer" or f.name == "drive":
            for g in dataclasses.fields(x):
                np.testing.assert_array_equal(getattr(x, g.name), getattr(y, g.name), g.name)
        else:
            assert x == y, (f.name, x, y)


def _channels(run) -> dict:
    """Every array of a Run: time, state, planes, weights, coordinates, truth, rotor."""
    out = {"t": run.t, "state": run.state, "rotor_angle": run.rotor_angle,
           "rotor_speed": run.rotor_speed}
    for group in ("planes", "weights", "coordinates", "truth"):
        for name, value in getattr(run, group).items():
            items = (value.items() if isinstance(value, dict) else
                     enumerate(value) if isinstance(value, tuple) else [("", value)])
            for k, v in items:          # (coordinates and truth: (array, unit) pairs)
                if isinstance(v, np.ndarray):
                    out[f"{group}/{name}/{k}"] = v
    return out


# ---------------------------------------------------------------- one planar rotor, two spellings
@pytest.mark.parametrize("angle", [25.0, "25 deg", "1.2 rad", 0.0])
def test_both_spellings_are_one_scene_and_one_run(angle):
    """Issue 40 item 4: [rotor]/[supports]/[balancer] and [structure] type = "planar" with
    [[weights]] read into one Scene (kind "planar", the same floats) and run on the same
    kernel, the planar one: every channel of the two runs is equal bit for bit.  The angle is
    in degrees in both forms (a unit string says otherwise); the same keys (eccentricity)."""
    ecc = f"eccentricity = {E!r}"
    a_sc = stand.load(planar_text("", angle))
    b_sc = stand.load(weights_text("", angle, unbalance=ecc))
    assert a_sc.kind == b_sc.kind == "planar" and a_sc.generic_kernel == b_sc.generic_kernel == ""
    _same_scene(a_sc, b_sc)
    want = {25.0: math.radians(25.0), "25 deg": math.radians(25.0), "1.2 rad": 1.2, 0.0: 0.0}[angle]
    assert a_sc.rotor.unbalance_angle == pytest.approx(want, rel=1e-15, abs=0)
    a, b = simulate(a_sc), simulate(b_sc)       # two integrations, not one cached answer
    assert a.stats.status == b.stats.status == 0 and a.stats.nfev == b.stats.nfev
    ca, cb = _channels(a), _channels(b)
    assert ca.keys() == cb.keys() and len(ca) >= 8
    for k in ca:
        assert np.array_equal(ca[k], cb[k]), k
    # the balls moved and the shaft whirls: the comparison is of a run that did something
    assert np.ptp(a.weights["ball1"]["angle"] if "ball1" in a.weights else a.state[:, 2]) > 0.1
    # the unbalance's written as kg m (the builder's key) is the same rotor to round-off
    c_sc = stand.load(weights_text("", angle))
    assert c_sc.rotor.unbalance == pytest.approx(a_sc.rotor.unbalance, rel=2e-16)


def test_both_spellings_with_friction_run_alike_on_the_generic_kernel():
    """Dry friction: both spellings are one Scene on the generic kernel, bit for bit."""
    ecc = f"eccentricity = {E!r}"
    a_sc, b_sc = stand.load(planar_text(FRICTION)), stand.load(weights_text(FRICTION, unbalance=ecc))
    _same_scene(a_sc, b_sc)
    assert "friction" in b_sc.generic_kernel
    a, b = simulate(a_sc), simulate(b_sc)
    for k, v in _channels(a).items():
        assert np.array_equal(v, _channels(b)[k]), k


def test_planar_structure_the_planar_form_cannot_say_stays_a_rotor_scene():
    """Transverse gravity (a horizontal axis) or two ball tables: the generic structure."""
    g = weights_text("").replace('type = "planar"\n', 'type = "planar"\ng = [0.0, -9.81]\n')
    sc = stand.load(g)
    assert sc.kind == "rotor" and sc.generic_kernel == "rotor type planar"
    two = weights_text("").replace("[drive]", f'[[weights]]\nplane = "balancer"\n{BALLS}\n[drive]')
    sc = stand.load(two)
    assert sc.kind == "rotor" and len(sc.weights) == 2


def test_planar_structure_torque_drive_gives_the_rotor_inertia():
    """[drive] inertia of a [structure] scene is J_p about the shaft; the planar Scene holds
    J_C = J_p - M e^2 (rotor.inertia), so that J_0 = J_C + M e^2 is J_p to round-off."""
    torque = 'type = "torque"\nmodel = "constant"\ntorque = 0.1\ninertia = 0.05\n'
    text = weights_text("", unbalance=f"eccentricity = {E!r}").replace(
        'type = "speed"\nprogramme = [[0.0, 0.0], [10.0, 15.0]]\n', torque)
    sc = stand.load(text)
    assert sc.kind == "planar" and sc.drive.kind == "torque"
    assert sc.rotor.inertia_about_shaft == pytest.approx(0.05, rel=1e-15)
    with pytest.raises(SceneError, match=r"drive\.inertia = 1e-09: must be > M e\^2"):
        stand.load(text.replace("inertia = 0.05", "inertia = 1e-9"))


def test_initial_angles_take_unit_strings_in_both_tables():
    """initial_angles: degrees, or a unit string per weight, in [balancer] and [[weights]]."""
    for text in (planar_text(""), weights_text("")):
        sc = stand.load(text.replace("[150.0, 210.0]", '["2.5 rad", 210.0]'))
        assert list(sc.balancer.initial_angles) == [2.5, math.radians(210.0)]
        with pytest.raises(SceneError, match=r"initial_angles\[0\] = \"2\.5 furlongs\": unknown unit"):
            stand.load(text.replace("[150.0, 210.0]", '["2.5 furlongs", 210.0]'))


def test_structure_eccentricity_and_unbalance_not_both():
    text = weights_text("").replace("unbalance = ", f"eccentricity = {E!r}\nunbalance = ")
    with pytest.raises(SceneError, match=r"structure\.eccentricity and structure\.unbalance"):
        stand.load(text)


# ---------------------------------------------------------------- old files: never a silent change
def test_undeclared_bare_structure_angle_is_degrees_and_language_1_reads_rad():
    """Since issue 39 a bare [structure] angle is in degrees (scene language 2, the default);
    a file (or a recording's stored text) of language 1 says so and reads rad; a unit string
    reads as it says in both; an unknown language is refused naming the key."""
    text = weights_text("", 1.57, language="")
    assert stand.load(text).rotor.unbalance_angle == pytest.approx(math.radians(1.57), rel=1e-15)
    assert stand.load(text).language == 2
    for fix, want in (('"1.57 rad"', 1.57), ('"89.9544 deg"', math.radians(89.9544))):
        for lang in ("", "[scene]\nlanguage = 1\n"):
            sc = stand.load(lang + text.replace("unbalance_angle = 1.57", f"unbalance_angle = {fix}"))
            assert sc.rotor.unbalance_angle == pytest.approx(want, rel=1e-15)
    declared = {1: 1.57, 2: math.radians(1.57)}
    for lang, want in declared.items():
        sc = stand.load(text.replace("[structure]", f"[scene]\nlanguage = {lang}\n[structure]"))
        assert sc.rotor.unbalance_angle == pytest.approx(want, rel=1e-15) and sc.language == lang
    # the [rotor] form reads the same degrees: one language
    assert stand.load(planar_text("", 1.57)).rotor.unbalance_angle == pytest.approx(
        math.radians(1.57), rel=1e-15)
    with pytest.raises(SceneError, match=r"scene\.language = 3: must be <= 2"):
        stand.load(text.replace("[structure]", "[scene]\nlanguage = 3\n[structure]"))


def test_undeclared_bare_grinding_and_flexible_angles_are_degrees():
    st = dict(BUILDERS["grinding"], type="grinding")
    deg = parse(_doc(dict(st, alpha=30.0), language=None))
    rad = parse(_doc(dict(st, alpha=f"{math.radians(30.0)!r} rad"), language=None))
    a, b = deg.linear_rotor(), rad.linear_rotor()
    for m in ("M", "D", "K"):
        np.testing.assert_allclose(getattr(a, m), getattr(b, m), rtol=1e-12, atol=0)
    zero = parse(_doc(dict(st, alpha=0.0), language=None)).linear_rotor()
    assert not np.allclose(zero.K, a.K) or not np.allclose(zero.D, a.D)   # alpha enters


# ---------------------------------------------------------------- friction and rolling
def test_balancer_friction_is_the_weights_form_to_round_off():
    """[balancer] friction = ... on the planar scene is the [[weights]] form of the same
    stand: the same PlaneWeights, the same kernel (generic: the planar one has no friction),
    the same run.  Both build the same LinearRotor (M e written as its float), the same
    weight table and scales, so the runs agree bit for bit (measured: 0); the bound 1e-12
    leaves room for a reordered sum, far below the tolerance-level 1e-8 of two kernels."""
    a_sc, b_sc = stand.load(planar_text(FRICTION)), stand.load(weights_text(FRICTION))
    assert a_sc.kind == b_sc.kind == "planar"
    (wa,), (wb,) = a_sc.weights, b_sc.weights
    assert wa.plane == wb.plane == "balancer" and wa.friction == wb.friction
    assert wa.friction.kinetic == 2e-3 and wa.friction.static == 0.01 and wa.friction.sticks
    assert wa.friction.slip_speed == 0.05 and wa.friction.dwell_time == 0.2
    assert wa.friction.release_time == 0.02
    for f in ("mass", "radius", "drag", "inertia", "initial_angles", "initial_speeds"):
        np.testing.assert_array_equal(getattr(wa.balancer, f), getattr(wb.balancer, f))
    assert "friction" in a_sc.generic_kernel
    a, b = stand.run(a_sc), stand.run(b_sc)
    assert a.stats.status == 0 and b.stats.status == 0
    xy, ang = _agreement(a, b)
    assert xy <= 1e-12 and ang <= 1e-12, (xy, ang)
    # the friction acts: the frictionless stand runs differently
    free = stand.run(dataclasses.replace(a_sc, friction=None))
    assert _agreement(a, free)[1] > 1e-3


def test_rolling_balls_agree_with_the_weights_form():
    """rolling = true: J = 7/5 m l^2 in both forms.  The planar kernel honours any J (its
    weight table takes J), so rolling balls without friction stay on it; through the generic
    kernel the planar form is the [[weights]] form to round-off, and the two kernels agree
    to the integration tolerance (rtol 1e-10: ~1e-10 measured)."""
    extra = "rolling = true\n"
    a_sc, b_sc = stand.load(planar_text(extra)), stand.load(weights_text(extra))
    J = 7.0 / 5.0 * 0.045 * 0.08 ** 2
    np.testing.assert_allclose(a_sc.balancer.inertia, J, rtol=1e-15)
    np.testing.assert_array_equal(a_sc.weights[0].balancer.inertia, b_sc.weights[0].balancer.inertia)
    assert a_sc.generic_kernel == "" and a_sc.friction is None
    assert b_sc.generic_kernel == ""       # one Scene: the planar kernel for both forms
    gen, ref = simulate(a_sc, kernel="generic"), simulate(b_sc, kernel="generic")
    xy, ang = _agreement(gen, ref)
    assert xy <= 1e-12 and ang <= 1e-12, (xy, ang)
    tight = dataclasses.replace(a_sc, run=dataclasses.replace(a_sc.run, rtol=1e-10, atol=1e-12))
    xy, ang = _agreement(simulate(tight), simulate(tight, kernel="generic"))
    assert xy <= 1e-8 and ang <= 1e-8, (xy, ang)
    # and rolling is not the point-ball model
    point = stand.run(stand.load(planar_text("")))
    assert _agreement(gen, point)[1] > 1e-3


def test_friction_keeps_the_planar_scene_off_the_planar_kernel():
    sc = stand.load(planar_text("friction = 2e-3\n"))
    with pytest.raises(SceneError, match='kernel = "planar": dry friction'):
        simulate(sc, kernel="planar")
    # what the generic kernel cannot run is refused when the scene is read
    text = planar_text("friction = 2e-3\n").replace(
        "programme = [[0.0, 0.0], [10.0, 15.0]]",
        "programme = [[0.0, 15.0]]\ncoast_down = {start = 1.0, time_constant = 2.0}")
    with pytest.raises(SceneError, match=r"balancer\.friction .*generic kernel.*coast_down"):
        stand.load(text)


def test_friction_keys_are_checked_as_in_weights():
    """The same reader for both forms: the same messages, with the table's path."""
    for bad, match in (("friction = -1.0", r"friction = -1\.0: must be >= 0 \(dimensionless"),
                       ("friction = 0.01\nstatic_friction = 0.001",
                        r"static_friction = 0\.001: must be >= 0\.01"),
                       ("slip_speed = 0.0", r"slip_speed = 0\.0: must be > 0 \(rad/s\)"),
                       ("dwell_time = true", r"dwell_time = true: must be a number \(s\)"),
                       ('rolling = "yes"', r'rolling = "yes": must be true or false')):
        msgs = []
        for text, where in ((planar_text(bad + "\n"), "balancer"),
                            (weights_text(bad + "\n"), "weights[0]")):
            with pytest.raises(SceneError, match=match) as exc:
                stand.load(text)
            assert str(exc.value).startswith(f"{where}.")
            msgs.append(str(exc.value)[len(where):])
        assert msgs[0] == msgs[1]


@pytest.mark.parametrize("key", ["friction = 2e-3", "static_friction = 0.01", "rolling = true",
                                 "slip_speed = 0.1"])
def test_friction_keys_refused_with_type_none(key):
    text = planar_text("").replace(f"[balancer]\n{BALLS}", f'[balancer]\ntype = "none"\n{key}\n')
    with pytest.raises(SceneError, match=r'balancer\.\w+ = .*: not allowed with balancer\.type = '
                                         r'"none"'):
        stand.load(text)
    text = weights_text("").replace(f"[[weights]]\nplane = \"balancer\"\n{BALLS}",
                                    f'[[weights]]\nplane = "balancer"\ntype = "none"\n{key}\n')
    with pytest.raises(SceneError, match=r'weights\[0\]\.\w+ = .*: not allowed with '
                                         r'weights\[0\]\.type = "none"'):
        stand.load(text)


def test_rolling_pendulums_refused():
    text = planar_text("").replace('type = "balls"', 'type = "pendulums"') .replace(
        "initial_angles", "rolling = true\ninitial_angles")
    with pytest.raises(SceneError, match=r"balancer\.rolling = true: only for balls"):
        stand.load(text)


def test_theory_says_friction_is_outside_and_still_answers(monkeypatch):
    import sys

    from stand.theories.planar import speedmap

    # the chapter-5 speed map (seconds) is a function of the Scene's fields: computed once for
    # scenes whose fields are equal (the two spellings below; their text differs), so that the
    # test checks the theory's notes on both without a second speed map
    cache, computed = {}, []
    original = speedmap.scene_theory

    def once(scene, *args, **kwargs):
        with np.printoptions(threshold=sys.maxsize, floatmode="unique"):
            key = (repr(dataclasses.replace(scene, text="")), repr(args), repr(sorted(kwargs.items())))
        if key not in cache:
            computed.append(key)
            cache[key] = original(scene, *args, **kwargs)
        return cache[key]

    monkeypatch.setattr(speedmap, "scene_theory", once)
    sc = stand.load(planar_text("friction = 2e-3\n"))
    th = stand.theory(sc, floquet=False)
    assert th["kind"] == "chapter5" and th["stable_bands"]
    assert any("dry friction of balancer" in n and "outside the steady-motion theory" in n
               for n in th["not_applicable"])
    # the [[weights]] spelling is the same Scene: the same theory, the same note
    th2 = stand.theory(stand.load(weights_text("friction = 2e-3\n")), floquet=False)
    assert th2["kind"] == "chapter5" and th2["not_applicable"] == th["not_applicable"]
    assert len(computed) == 1       # one Scene: its fields equal, one speed map
    # a rotor-family structure says it its way
    th = stand.theory(stand.load(weights_text("friction = 2e-3\n").replace(
        'type = "planar"\n', 'type = "planar"\ng = [0.0, -1e-3]\n')), floquet=False)
    assert th["kind"] == "structure"
    assert any("dry friction of the weights in plane balancer" in n for n in th["not_applicable"])


def test_friction_keys_are_sweep_keys():
    import tomllib

    from stand.sweep.checks import SweepSpecError
    from stand.sweep.keys import check_key, point_scene_dict

    base = tomllib.loads(planar_text(FRICTION))
    for key in ("balancer.friction", "balancer.static_friction", "balancer.dwell_time"):
        check_key("axis[0].key", key, base)
    with pytest.raises(SweepSpecError, match="unknown key balancer.rolling"):
        check_key("axis[0].key", "balancer.rolling", base)
    check_key("axis[0].key", "weights[0].friction", tomllib.loads(weights_text(FRICTION)))
    sc = parse(point_scene_dict(base, ["balancer.friction"], [4e-3]))
    assert sc.friction.kinetic == 4e-3


def test_friction_sample_balls_stop_short_of_balance():
    sc = stand.load(SCENES / "ball_friction.toml")
    assert sc.friction.kinetic == 2e-3 and sc.generic_kernel
    run = stand.run(sc)
    r = np.hypot(run.x, run.y)[run.t > run.t[-1] - 2.0].max()
    e = sc.rotor.unbalance / sc.total_mass
    assert 0.5 * 2e-3 * 0.08 < r < 1.5 * 2e-3 * 0.08 and e / r > 5
    assert stand.run(dataclasses.replace(sc, friction=None)).whirl_radius()[-1] < 1e-6 * r


# ---------------------------------------------------------------- angles in degrees
#: a minimal [structure] table of every builder with an unbalance angle
BUILDERS = {
    "planar": dict(mass=2.0, stiffness_x=1e4),
    "two_mass": dict(body_mass=2.0, rotor_mass=1.0, body_stiffness=1e4, rotor_stiffness=3e4),
    "grinding": dict(mass=1.0, c_xi=1e4, c_eta=3e4, alpha=30.0, f=0.3),
    "spherical_hinge": dict(A=0.1, C=0.02, mass=5.0, l=0.2, k1=400.0, k2=800.0, a=0.3),
    "cylindrical_hinge": dict(A=0.1, mass=5.0, l=0.2, k=400.0, a=0.3),
    "fixed_point_stand": dict(),
    "spatial": dict(mass=10.0, A=0.3, C=0.1, l1=0.2, l2=0.3, c1=2e4, couple_unbalance=1e-3,
                    couple_positions=[-0.1, 0.1]),
}


def _doc(structure: dict, language=2) -> dict:
    doc = {"structure": structure, "drive": {"type": "speed", "programme": [[0.0, 1.0]]},
           "run": {"duration": 0.1, "sample_rate": 100.0}}
    return doc if language is None else dict(doc, scene={"language": language})


@pytest.mark.parametrize("kind", sorted(BUILDERS))
def test_structure_unbalance_angle_is_in_degrees(kind):
    """unbalance_angle = 40.0 is 40 deg for every builder that takes one (it ran 40 rad)."""
    sc = parse(_doc(dict(BUILDERS[kind], type=kind, unbalance=2e-3, unbalance_angle=40.0)))
    ubs = sc.linear_rotor().unbalances
    static = [u for u in ubs if u.s == 2e-3 and not (kind == "spatial" and u.plane != "unbalance1")]
    assert len(static) == 1
    u = static[0]
    np.testing.assert_allclose(u.s * np.array([math.cos(u.angle), math.sin(u.angle)]),
                               2e-3 * np.array([math.cos(math.radians(40.0)),
                                                math.sin(math.radians(40.0))]), rtol=1e-15)
    if kind == "spatial":    # the couple at the same angle (and opposite)
        angles = sorted(u.angle for u in ubs if u.s == 1e-3)
        np.testing.assert_allclose(angles, [math.radians(40.0), math.radians(40.0) + math.pi])


def test_unit_strings_say_otherwise():
    for value, want in (("0.7 rad", 0.7), ("40 deg", math.radians(40.0)), ("0.25 rev", math.pi / 2),
                        ("40", math.radians(40.0)), (-30, math.radians(-30.0))):
        sc = parse(_doc(dict(type="planar", mass=2.0, stiffness_x=1e4, unbalance=2e-3,
                             unbalance_angle=value)))
        assert sc.linear_rotor().unbalances[0].angle == pytest.approx(want, rel=1e-15), value
        assert sc.rotor.unbalance_angle == pytest.approx(want, rel=1e-15)


def test_grinding_alpha_and_flexible_unbalances_are_in_degrees():
    from stand.model.rotors.flexible import flexible_shaft
    from stand.model.rotors.grinding import grinding_rotor

    sc = parse(_doc(dict(BUILDERS["grinding"], type="grinding")))
    want = grinding_rotor(1.0, 1e4, 3e4, math.radians(30.0), 0.3)
    np.testing.assert_array_equal(sc.linear_rotor().K, want.K)
    sc = parse(_doc(dict(type="grinding", mass=1.0, c_xi=1e4, c_eta=3e4, alpha="0.5 rad", f=0.3)))
    np.testing.assert_array_equal(sc.linear_rotor().K,
                                  grinding_rotor(1.0, 1e4, 3e4, 0.5, 0.3).K)
    st = dict(type="flexible", length=1.0, mass_per_length=10.0, EJ=2000.0, n_modes=3,
              planes={"balancer": 0.5, "b2": 0.25},
              unbalances={"balancer": 2e-3, "b2": [1e-3, 30.0], "b3": [1e-3, "0.5 rad"]})
    st["planes"]["b3"] = 0.75
    got = {u.plane: (u.s, u.angle) for u in parse(_doc(st)).linear_rotor().unbalances}
    assert got == {"balancer": (2e-3, 0.0), "b2": (1e-3, math.radians(30.0)), "b3": (1e-3, 0.5)}
    want = flexible_shaft(1.0, 10.0, 2000.0, 3, planes=st["planes"],
                          unbalances={"balancer": 2e-3, "b2": [1e-3, math.radians(30.0)],
                                      "b3": [1e-3, 0.5]})
    assert [(u.plane, u.s, u.angle) for u in want.unbalances] == [
        (p, *got[p]) for p in ("balancer", "b2", "b3")]


@pytest.mark.parametrize("key,value,match", [
    ("unbalance_angle", "40 furlongs", r"structure\.unbalance_angle = \"40 furlongs\": unknown "
                                       r"unit 'furlongs'"),
    ("unbalance_angle", "abc", r"structure\.unbalance_angle = \"abc\": expected a number and a unit"),
    ("unbalance_angle", "5 mm", r"structure\.unbalance_angle = \"5 mm\": unit 'mm' is a length unit"),
    ("unbalance_angle", True, r"structure\.unbalance_angle = true: must be an angle"),
    ("unbalance_angle", [1.0], r"structure\.unbalance_angle = \[1\.0\]: must be an angle"),
    ("unbalance_angle", math.inf, r"structure\.unbalance_angle = inf: must be finite"),
    ("alpha", "thirty", r"structure\.alpha = \"thirty\": expected a number and a unit"),
])
def test_bad_angles_are_refused_naming_the_key(key, value, match):
    st = dict(BUILDERS["grinding"], type="grinding", unbalance=1e-3)
    st[key] = value
    with pytest.raises(SceneError, match=match):
        parse(_doc(st))


def test_bad_flexible_unbalance_angle_is_refused_naming_the_key():
    st = dict(type="flexible", length=1.0, mass_per_length=10.0, EJ=2000.0, n_modes=3,
              unbalances={"balancer": [1e-3, "40 furlongs"]})
    with pytest.raises(SceneError, match=r"structure\.unbalances\.balancer\[1\] = \"40 furlongs\""):
        parse(_doc(st))
    st["unbalances"] = {"balancer": [1e-3, 0.5, 2.0]}
    with pytest.raises(SceneError, match=r"structure\.unbalances\.balancer = .*\[s \(kg m\), angle"):
        parse(_doc(st))


# ---------------------------------------------------------------- old recordings (language 1)
def test_language_1_reads_structure_angles_in_rad():
    text = weights_text("", unbalance_angle=0.7, language="")
    assert load_scene(text, language=2).linear_rotor().unbalances[0].angle == pytest.approx(
        math.radians(0.7), rel=1e-15)
    old = load_scene(text, language=1)
    assert old.language == 1 and old.linear_rotor().unbalances[0].angle == 0.7
    # the planar tables read the same in both languages
    a, b = load_scene(planar_text(""), language=1), stand.load(planar_text(""))
    assert a.rotor == b.rotor
    with pytest.raises(SceneError, match="scene language 3"):
        load_scene(text, language=3)


def test_old_sample_recordings_read_with_their_angles():
    """data_samples/recordings/influence_*.h5 were written before the rule (no
    scene_language attribute): their stored unbalances [s, 0.5236...] are rad, and read so;
    the sample scenes now say [s, 30.0] (deg) -- the same rotor."""
    rec = stand.read(RECS / "influence_ref.h5")
    assert "scene_language" not in rec.attrs and rec.scene.language == 1
    assert any("predates scene language 2" in n and "structure.unbalances" in n for n in rec.notes)
    new = stand.load(SCENES / "influence_reference.toml")
    assert [(u.plane, u.s, u.angle) for u in rec.scene.linear_rotor().unbalances] == [
        (u.plane, u.s, u.angle) for u in new.linear_rotor().unbalances]


def test_recordings_store_their_scene_language(tmp_path):
    text = weights_text("", unbalance_angle=40.0, language="")
    sc = load_scene(text, language=2)       # (a text without [scene] language, as stored)
    sc = dataclasses.replace(sc, run=dataclasses.replace(sc.run, duration=0.05))
    path = stand.save(stand.run(sc), tmp_path / "new.h5")
    rec = stand.read(path)
    assert rec.attrs["scene_language"] == SCENE_LANGUAGE and not rec.notes
    assert rec.scene.linear_rotor().unbalances[0].angle == pytest.approx(math.radians(40.0))
    # an old recording written again keeps its text and its language
    old = stand.read(RECS / "influence_trial1.h5")
    again = stand.read(stand.save(old, tmp_path / "again.h5"))
    assert again.attrs["scene_language"] == 1 and again.scene_text == old.scene_text
    assert [u.angle for u in again.scene.linear_rotor().unbalances] == [
        u.angle for u in old.scene.linear_rotor().unbalances]
    # a file without the attribute is language 1
    with h5py.File(path, "a") as f:
        del f.attrs["scene_language"]
    assert stand.read(path).scene.linear_rotor().unbalances[0].angle == pytest.approx(40.0)
    # a text that declares [scene] language = 2 is read so, attribute or not
    sc = stand.load(weights_text("", unbalance_angle=40.0))
    path = stand.save(stand.run(dataclasses.replace(
        sc, run=dataclasses.replace(sc.run, duration=0.05))), tmp_path / "declared.h5")
    with h5py.File(path, "a") as f:
        del f.attrs["scene_language"]
    assert stand.read(path).scene.rotor.unbalance_angle == pytest.approx(math.radians(40.0))
