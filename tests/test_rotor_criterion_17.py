"""Issue 17 parts 5-6: the generalised multi-plane criterion in ``stand theory``, the
exact bracketing of the criterion's poles, and the rotor parameters in scene files.

Tolerances: an edge is a speed where the criterion matrix changes definiteness; it is
bracketed by checking the definiteness at w (1 -+ 1e-6) (the edges are found to 1e-13
relative, the matrix is evaluated to ~1e-12).  The narrow flexible-shaft gap is
compared with the zero of the modal sum (2.164)-(2.165) found independently by Brent's
method, to 1e-10 relative (the root-finder's tolerance is 1e-13).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from stand.model.rotors.flexible import (flexible_shaft, shaft_criterion, shaft_natural_frequencies,
                                   shaft_working_ranges)
from stand.model.rotors.structure import (criterion_matrices, generalised_working_ranges,
                                    sign_changes, synchronous_poles, working_ranges)

from _helpers import stand_stdout, theory_computed_once

HZ = 2 * math.pi

# ---------------------------------------------------------------- part 6: narrow gap
# 8-mode shaft whose mode 6 is at 925.93 Hz, the balancer 1.5 mm beside mid-span
# (the node of mode 6): the tiny residue puts the zero of (2.165) just below the pole,
# a non-working gap 925.80-925.93 Hz.
L, MPL, EJ8, A8 = 1.0, 10.0, 2681.091002565544, 0.5014951050016175


def _gap_zero():
    wj = shaft_natural_frequencies(L, MPL, EJ8, 8)
    f = lambda w: shaft_criterion(w, A8, L, MPL, EJ8, n_modes=8)     # noqa: E731
    return brentq(f, wj[4] * (1 + 1e-12), wj[5] * (1 - 1e-12), xtol=1e-300, rtol=1e-15), wj[5]


def test_the_fixed_grid_alone_misses_the_gap():
    """The regression: 20 000 geometric points over 1-2000 Hz step over the gap."""
    f = lambda w: shaft_criterion(w, A8, L, MPL, EJ8, n_modes=8)     # noqa: E731
    old = sign_changes(f, HZ * 1.0, HZ * 2000.0, 20000)               # no poles given
    assert not np.any(np.abs(old / HZ - 925.8) < 0.05)


@pytest.fixture(scope="module")
def shaft8():
    """The 8-mode shaft as a LinearRotor and its working ranges over 1-2000 Hz (the generic
    search at its default grid), computed once for the two tests that read them."""
    rot = flexible_shaft(L, MPL, EJ8, 8, planes={"balancer": A8})
    return rot, working_ranges(rot, "balancer", HZ * 1.0, HZ * 2000.0)


@pytest.mark.parametrize("how", ["closed_form_truncated", "linear_rotor"])
def test_narrow_gap_next_to_a_pole_is_found(how, shaft8):
    z, pole = _gap_zero()
    assert z / HZ == pytest.approx(925.80, abs=5e-3) and pole / HZ == pytest.approx(925.93, abs=1e-9)
    lo, hi = HZ * 1.0, HZ * 2000.0
    if how == "linear_rotor":
        crit, ranges = shaft8[1]
    else:
        crit, ranges = shaft_working_ranges(A8, L, MPL, EJ8, hi, lo=lo, n_modes=8)
    assert np.min(np.abs(crit - z)) <= 1e-10 * z
    assert np.min(np.abs(crit - pole)) <= 1e-10 * pole
    # the gap: a working range ends at the zero, the next starts at the pole
    ends = [b for _, b in ranges]
    starts = [a for a, _ in ranges]
    assert any(abs(b - z) <= 1e-10 * z for b in ends)
    assert any(abs(a - pole) <= 1e-10 * pole for a in starts)
    # every pole whose mode has no node at the plane is a critical speed
    wj = shaft_natural_frequencies(L, MPL, EJ8, 8)
    for w in wj:
        assert np.min(np.abs(crit - w)) <= 1e-10 * w


def test_synchronous_poles_are_the_natural_frequencies():
    rot = flexible_shaft(L, MPL, EJ8, 8, planes={"balancer": A8})
    np.testing.assert_allclose(synchronous_poles(rot), shaft_natural_frequencies(L, MPL, EJ8, 8),
                               rtol=1e-12)


def test_every_sign_change_of_the_dense_criterion_is_reported(shaft8):
    """Between two reported critical speeds the criterion keeps its sign (checked on a
    grid 10x denser than the scan, with the poles' sides)."""
    lo, hi = HZ * 1.0, HZ * 2000.0
    crit, _ = shaft8[1]
    edges = np.concatenate([[lo], crit, [hi]])
    for a, b in zip(edges[:-1], edges[1:]):
        x = np.geomspace(a * (1 + 1e-9), b * (1 - 1e-9), 400)
        v = np.sign(shaft_criterion(x, A8, L, MPL, EJ8, n_modes=8))
        assert np.all(v == v[0]), (a / HZ, b / HZ)


# ------------------------------------------------- part 5: the generalised criterion
# Paper-003 rotor (long: J > C) on two isotropic supports in paper 003's axial convention,
# two balancers at -0.15 m and +0.2 m from the centre of mass.
P003 = dict(mass=10.0, A=0.3, C=0.1, l1=0.2, l2=0.3, c1=2.0e4, c2=3.0e4)
SCENE_003 = """
[scene]
name = "paper003_two_balancers"
[structure]
type = "spatial"
axial_convention = "paper003"
mass = 10.0
A = 0.3
C = 0.1
l1 = 0.2
l2 = 0.3
c1 = 2.0e4
c2 = 3.0e4
balancer_positions = [-0.15, 0.2]
unbalance = 2.0e-3
unbalance_position = 0.2
[[weights]]
plane = "balancer1"
type = "balls"
count = 2
mass = 0.02
radius = 0.1
drag = 0.5
[[weights]]
plane = "balancer2"
type = "balls"
count = 2
mass = 0.02
radius = 0.1
drag = 0.5
[drive]
type = "speed"
programme = [[0.0, 0.0], [3.0, 15.0]]
[run]
duration = 5.0
sample_rate = 100.0
"""


def _definite(rot, planes, w):
    return bool(np.all(np.linalg.eigvalsh(rot.criterion_matrix(w, planes)) < 0))


@pytest.fixture(scope="module")
def scene003(tmp_path_factory):
    import stand

    p = tmp_path_factory.mktemp("s17") / "paper003.toml"
    p.write_text(SCENE_003)
    return p, stand.load(str(p))


def test_theory_json_holds_the_generalised_criterion(scene003):
    """``stand theory --json``: the generalised criterion's onsets are where
    criterion_matrix changes definiteness (bracketed to 1e-6 relative), they are paper
    003's critical speeds (40) (K_xi negative definite only above both), and the
    working ranges are where the matrix is negative definite."""
    import json

    from stand.model.rotors.spatial import two_support_rotor
    path, sc = scene003
    with theory_computed_once():    # the JSON and the text below: one theory of the scene
        out = stand_stdout("theory", path, "--json", "--no-floquet")
        txt = stand_stdout("theory", path, "--no-floquet")
    doc = json.loads(out)
    gc = doc["generalised_criterion"]
    assert gc["planes"] == ["balancer1", "balancer2"]
    assert "K_xi and K_eta negative definite" in gc["condition"]
    from stand.integrate.coupled import with_locked_weights
    rot = with_locked_weights(sc.linear_rotor(), sc.weights, sc.bodies)
    planes = ["balancer1", "balancer2"]
    assert gc["onsets_hz"]
    for f in gc["onsets_hz"]:
        w = f * HZ
        assert _definite(rot, planes, w * (1 - 1e-6)) != _definite(rot, planes, w * (1 + 1e-6))
    for a, b in gc["working_ranges_hz"]:
        hi = b if b is not None else 4 * a
        for w in np.geomspace(a * HZ * (1 + 1e-6), hi * HZ * (1 - 1e-6), 50):
            assert _definite(rot, planes, w)
    # without the weights' mass the onset is the larger critical speed (40) of paper 003
    bare = sc.linear_rotor()
    crit, ranges = generalised_working_ranges(bare, planes, 1.0, 2000.0)
    ts = two_support_rotor(P003["c1"], P003["c2"], P003["l1"], P003["l2"], P003["mass"],
                           P003["A"], P003["A"], P003["C"])
    w40 = ts.critical_speeds("xi")
    assert len(ranges) == 1 and math.isinf(ranges[0][1])
    assert ranges[0][0] == pytest.approx(w40[-1], rel=1e-10)
    for w in (0.5 * w40[0], 0.5 * (w40[0] + w40[1]), 1.5 * w40[1]):
        assert _definite(bare, planes, w) == ts.is_stable(w)
    # and the text of stand theory prints it
    assert "generalised criterion, planes balancer1, balancer2" in txt
    assert f"{gc['onsets_hz'][0]:.6g}" in txt


def test_criterion_matrices_equal_criterion_matrix(scene003):
    _, sc = scene003
    rot = sc.linear_rotor()
    om = np.array([10.0, 55.5, 300.0])
    Q = criterion_matrices(rot, om, ["balancer1", "balancer2"])
    for w, q in zip(om, Q):
        np.testing.assert_allclose(q, rot.criterion_matrix(w, ["balancer1", "balancer2"]),
                                   rtol=1e-12, atol=1e-15 * np.abs(q).max())


def test_generalised_onsets_of_a_damped_flexible_shaft_bracket_definiteness():
    """Three planes on the 8-mode shaft (damped): every onset bracketed to 1e-6."""
    rot = flexible_shaft(L, MPL, EJ8, 8, damping_ratio=0.01,
                         planes={"b1": 0.25, "b2": 0.5, "b3": 0.8})
    planes = ["b1", "b2", "b3"]
    crit, ranges = generalised_working_ranges(rot, planes, HZ * 1.0, HZ * 2000.0)
    edges = {x for r in ranges for x in r if math.isfinite(x) and x > HZ * 1.0}
    assert edges
    for w in edges:
        assert _definite(rot, planes, w * (1 - 1e-6)) != _definite(rot, planes, w * (1 + 1e-6))


# ------------------------------------------------------ part 5: axial convention
def test_axial_convention_paper003_is_the_mirrored_book_rotor():
    from stand.scene.structure_tables import build_rotor

    base = dict(mass=10.0, A=0.3, C=0.1, balancer_positions=[0.1])
    pap = build_rotor("spatial", dict(base, l1=0.2, l2=0.3, c1=2e4, c2=3e4,
                                      axial_convention="paper003"))
    book = build_rotor("spatial", dict(base, l1=0.3, l2=0.2, c1=3e4, c2=2e4))
    np.testing.assert_allclose(pap.K, book.K, rtol=1e-14)
    # support 1 at -l1 (paper (14)): c14 = c2 l2 - c1 l1; the book's: c1 l1 - c2 l2
    assert pap.K[0, 3] == pytest.approx(3e4 * 0.3 - 2e4 * 0.2, rel=1e-14)
    bk = build_rotor("spatial", dict(base, l1=0.2, l2=0.3, c1=2e4, c2=3e4, axial_convention="book"))
    assert bk.K[0, 3] == pytest.approx(2e4 * 0.2 - 3e4 * 0.3, rel=1e-14)
    default = build_rotor("spatial", dict(base, l1=0.2, l2=0.3, c1=2e4, c2=3e4))
    np.testing.assert_array_equal(default.K, bk.K)
    from stand.scene.model import SceneError
    with pytest.raises(SceneError, match="axial_convention"):
        build_rotor("spatial", dict(base, l1=0.2, l2=0.3, c1=2e4, axial_convention="left"))


# ------------------------------------- part 5: every builder argument in [structure]
ALL_KEYS = {
    "spatial": dict(mass=10.0, A=0.3, C=0.1, l1=0.2, l2=0.3, c1=2.0e4, c2=3.0e4,
                    balancer_positions=[-0.15, 0.2], unbalance=2e-3, unbalance_position=0.2,
                    unbalance_angle=0.5, couple_unbalance=1e-3, couple_positions=[-0.1, 0.1],
                    stiffness_damping=1e-3, screen_positions=[0.4, 0.6],
                    axial_convention="paper003"),
    "flexible": dict(length=1.0, mass_per_length=10.0, EJ=2000.0, n_modes=8,
                     damping_ratio=[0.01] * 8, planes={"balancer": 0.5, "b2": 0.25},
                     unbalances={"balancer": 2e-3, "b2": [1e-3, 0.5]}, g=[0.0, -9.81]),
    "platform": dict(paper_exact=False, delta_offset_term=True, m=70.0, m2=15.0, I_a1=2.6,
                     I_b1=2.7, I_c1=3.1, I_p=0.5, S1=1.0, S2=1.1, b1=0.8, b2=0.85, h=2.1,
                     z_k=0.3, c2x=200.0, c2y=210.0, c2z=1000.0, x_M=0.0, y_M=0.01, z_M=0.4,
                     x_D=0.02, y_D=-0.01, z_D=0.35, e=5e-4, g=9.81, z_B=0.3,
                     rod_stiffness=3.0e6, rod_damping=700.0, rim_damping=12.0, rim_radius=0.45,
                     rim_length=0.5),
}


#: the angles of ALL_KEYS (degrees in the scene file) as the builders take them (rad)
IN_RAD = {"spatial": {"unbalance_angle": math.radians(0.5)},
          "flexible": {"unbalances": {"balancer": 2e-3, "b2": [1e-3, math.radians(0.5)]}}}


def _toml(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_toml(x)}" for k, x in v.items()) + " }"
    return repr(float(v)) if isinstance(v, float) else str(v)


@pytest.mark.parametrize("kind", sorted(ALL_KEYS))
def test_every_builder_argument_is_a_scene_key(kind, tmp_path):
    """Each keyword of the builder (but the platform's Python-only ``params``) given in a
    scene file reaches the builder: the scene's rotor equals the builder's."""
    import inspect

    import stand
    from stand.scene.structure_tables import ROTOR_TYPES, _builder

    fn = _builder(kind)
    names = set(inspect.signature(fn).parameters) - {"params"}
    assert names == set(ALL_KEYS[kind]), names ^ set(ALL_KEYS[kind])
    body = "\n".join(f"{k} = {_toml(v)}" for k, v in ALL_KEYS[kind].items())
    p = tmp_path / f"{kind}.toml"
    p.write_text(f'[scene]\nlanguage = 2\n[structure]\ntype = "{kind}"\n{body}\n[drive]\ntype = "speed"\n'
                 'programme = [[0.0, 0.0], [1.0, 1.0]]\n[run]\nduration = 1.0\nsample_rate = 50.0\n')
    rot = stand.load(str(p)).linear_rotor()
    # the scene's angles are in degrees, the builder's in rad
    want = fn(**dict(ALL_KEYS[kind], **IN_RAD.get(kind, {})))
    for key in ("M", "G", "D", "K"):
        np.testing.assert_array_equal(getattr(rot, key), getattr(want, key))
    assert set(rot.planes) == set(want.planes)
    assert [(u.plane, u.s) for u in rot.unbalances] == [(u.plane, u.s) for u in want.unbalances]
    np.testing.assert_allclose([u.angle for u in rot.unbalances],
                               [u.angle for u in want.unbalances], rtol=1e-15)
    assert ROTOR_TYPES[kind]


def test_platform_keywords_default_to_the_current_platform():
    from stand.model.rotors.platform import default_params, platform_rotor, scene_params

    assert scene_params() == default_params()
    a, b = platform_rotor(), platform_rotor(m=60.0, S1=1.0, rod_stiffness=3.75e6, rim_damping=10.0)
    for key in ("M", "G", "D", "K"):
        np.testing.assert_array_equal(getattr(a, key), getattr(b, key))
    with pytest.raises(ValueError, match="not both"):
        platform_rotor(default_params(), m=50.0)


def test_platform_keywords_act_on_the_physics():
    """The rods enter A (42) linearly, c_1i v v^T / l^2: K(2c) - K(c) = K(c) - K(0)
    (1e-9 relative: three sums of O(1e6) entries); the balancer plane follows z_B ((5):
    dx = (1 + z d_3) x + z beta - y_D gamma); the unbalance is m2 e."""
    from stand.model.rotors.platform import platform_rotor

    K0, K1, K2 = (platform_rotor(rod_stiffness=c).K for c in (0.0, 2.0e6, 4.0e6))
    np.testing.assert_allclose(K2 - K1, K1 - K0, atol=1e-9 * np.abs(K2).max())
    assert np.abs(K1 - K0).max() > 1e5
    r = platform_rotor(z_B=0.1, m2=10.0, e=1e-3)
    r0 = platform_rotor(z_B=0.2, m2=10.0, e=1e-3)
    dT = r0.planes["balancer"] - r.planes["balancer"]
    assert dT[0, 4] == pytest.approx(0.1, rel=1e-12) and dT[1, 3] == pytest.approx(-0.1, rel=1e-12)
    assert r.unbalances[0].s == pytest.approx(1e-2, rel=1e-15)
    with pytest.raises(ValueError, match="rod_stiffness|c"):
        platform_rotor(rod_stiffness=-1.0)
