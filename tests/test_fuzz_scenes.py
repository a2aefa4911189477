"""Property-based hardening of the scene readers (issue 10 item 5).

Every input path that reads a scene -- ``parse_scene`` (a parsed TOML
document), ``load_scene`` (TOML text or a file) and ``parse_family_scene``
(rotor-family ``[structure]`` scenes) -- must either return a scene or raise
``SceneError`` whose message names the offending key; never another exception,
never a hang.  Valid scenes with tiny durations must also run through
``stand.integrate.simulate.simulate`` to success or a clear failed status, in bounded time.

The suites are derandomized (reproducible in CI) and sized to run in well under
90 s together.
"""
from __future__ import annotations

import copy
import math
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from stand.scene.structure_tables import parse_family_scene
from stand.scene.model import Scene as FamilyScene
from stand.scene.model import METHODS, Scene, SceneError
from stand.scene.parse import load_scene, parse_scene

from _helpers import Properties

FAST = settings(max_examples=200, deadline=10_000, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                       HealthCheck.filter_too_much])
SLOW = settings(FAST, max_examples=30, deadline=None)
#: each property: an eighth of its examples by default, all under ``-m full`` (issue 43)
PROPS = Properties()

DEG = math.pi / 180
TWO_PI = 2 * math.pi


# ---------------------------------------------------------------- TOML writer (tests only)
def _toml_string(s: str) -> str:
    out = []
    for ch in s:
        o = ord(ch)
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif o < 0x20 or o == 0x7F:
            out.append(f"\\u{o:04X}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _toml_string(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_string(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def to_toml(doc: dict) -> str:
    """A scene document as TOML text (top-level arrays first, then one [table] each)."""
    lines = []
    for k, v in doc.items():
        if not isinstance(v, dict):
            lines.append(f"{_toml_string(k)} = {toml_value(v)}")
    for k, v in doc.items():
        if isinstance(v, dict):
            lines.append(f"[{_toml_string(k)}]")
            lines += [f"{_toml_string(kk)} = {toml_value(x)}" for kk, x in v.items()]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- strategies: valid scenes
def fl(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


def per_weight(n, lo, hi):
    """One number for every weight, or a list of n numbers."""
    return st.one_of(fl(lo, hi), st.lists(fl(lo, hi), min_size=n, max_size=n))


@st.composite
def programmes(draw, speed_max=30.0):
    k = draw(st.integers(1, 4))
    steps = draw(st.lists(fl(0.001, 0.05), min_size=k, max_size=k))
    t0 = draw(fl(0.0, 0.01))
    times = list(np.cumsum([t0] + steps[1:]))
    speeds = draw(st.lists(fl(0.0, speed_max), min_size=k, max_size=k))
    return [[float(t), s] for t, s in zip(times, speeds)]


@st.composite
def balancer_tables(draw):
    kind = draw(st.sampled_from(["balls", "pendulums", "none", None]))
    if kind is None:
        return None
    if kind == "none":
        return {"type": "none"}
    n = draw(st.integers(1, 4))
    b = {"type": kind, "count": n, "mass": draw(per_weight(n, 1e-3, 0.5)),
         "radius": draw(per_weight(n, 0.01, 0.3))}
    if draw(st.booleans()):
        b["drag"] = draw(per_weight(n, 0.0, 1.0))
    if kind == "pendulums" and draw(st.booleans()):
        m = np.broadcast_to(np.asarray(b["mass"], float), (n,))
        r = np.broadcast_to(np.asarray(b["radius"], float), (n,))
        f = draw(st.lists(fl(1.0, 3.0), min_size=n, max_size=n))
        b["inertia"] = [float(mi * ri * ri * fi) * (1 + 1e-9) for mi, ri, fi in zip(m, r, f)]
    if draw(st.booleans()):
        b["initial_angles"] = draw(st.lists(fl(-720, 720), min_size=n, max_size=n))
    if draw(st.booleans()):
        b["initial_speeds"] = draw(per_weight(n, -5.0, 5.0))
    return b


@st.composite
def drive_tables(draw, torque_ok=True):
    kind = draw(st.sampled_from(["speed", "torque"] if torque_ok else ["speed"]))
    if kind == "speed":
        d = {"type": "speed"}
        if draw(st.booleans()):
            d["programme"] = draw(programmes())
        else:
            d["programme_dimensionless"] = draw(programmes(speed_max=3.0))
        if draw(st.booleans()):
            d["coast_down"] = {"start": draw(fl(1e-3, 0.1)), "time_constant": draw(fl(1e-3, 10.0))}
        if draw(st.booleans()):
            d["rotor_drag"] = draw(fl(0.0, 1.0))
        return d
    model = draw(st.sampled_from(["constant", "speed_feedback", "angle_feedback"]))
    d = {"type": "torque", "model": model}
    if model == "constant":
        d["torque"] = draw(fl(-10.0, 10.0))
    else:
        d["c1"] = draw(fl(0.0, 10.0))
        d["target_speed"] = draw(fl(0.0, 30.0))
    if model == "angle_feedback":
        d["c2"] = draw(fl(0.0, 100.0))
    if draw(st.booleans()):
        d["rotor_drag"] = draw(fl(0.0, 1.0))
    if draw(st.booleans()):
        d["initial_speed"] = draw(fl(0.0, 30.0))
    return d


@st.composite
def run_tables(draw):
    r = {"duration": draw(fl(1e-3, 0.05)), "sample_rate": draw(fl(20.0, 2000.0)),
         "max_steps": draw(st.integers(1000, 20000))}
    if draw(st.booleans()):
        r["rtol"] = draw(fl(1e-10, 1e-3))
        r["atol"] = draw(fl(1e-12, 1e-3))
    if draw(st.booleans()):
        r["method"] = draw(st.sampled_from([m for m in METHODS if m != "LSODA"]))
    return r


@st.composite
def perturbation_lists(draw, duration):
    out = []
    for _ in range(draw(st.integers(0, 2))):
        kind = draw(st.sampled_from(["unbalance", "impulse", "side_force"]))
        if kind == "unbalance":
            p = {"type": kind, "time": draw(fl(0.0, duration)),
                 "duration": draw(fl(0.0, duration)), "eccentricity": draw(fl(0.0, 1e-3)),
                 "unbalance_angle": draw(fl(-360, 360))}
        elif kind == "impulse":
            p = {"type": kind, "time": draw(fl(duration * 1e-3, duration)),
                 "velocity_x": draw(fl(-0.01, 0.01)), "velocity_y": draw(fl(-0.01, 0.01))}
        else:
            start = draw(fl(0.0, duration / 2))
            p = {"type": kind, "start": start, "end": start + draw(fl(1e-4, duration)),
                 "force_x": draw(fl(-10, 10)), "force_y": draw(fl(-10, 10)),
                 "stiffness_x": draw(fl(0, 1e3)), "stiffness_y": draw(fl(0, 1e3))}
        out.append(p)
    return out


@st.composite
def valid_docs(draw, dimensionless=None):
    """A physically valid scene document (values inside the documented ranges)."""
    dimless = draw(st.booleans()) if dimensionless is None else dimensionless
    doc: dict = {}
    if draw(st.booleans()):
        doc["scene"] = {"name": draw(st.text(max_size=20)),
                        "description": draw(st.text(max_size=20))}
    torque = False
    if dimless:
        n = draw(st.integers(1, 4))
        dl = {"n": n, "Rt": draw(fl(1e-4, 0.49)), "h": draw(fl(0, 1)), "H": draw(fl(0, 1)),
              "e0": draw(fl(0, 2))}
        for key, lo, hi in (("R_omega2", 0.5, 2.0), ("unbalance_angle", -360, 360),
                            ("natural_frequency", 0.5, 20.0), ("total_mass", 0.1, 50.0),
                            ("track_radius", 0.01, 1.0)):
            if draw(st.booleans()):
                dl[key] = draw(fl(lo, hi))
        if draw(st.booleans()):
            dl["initial_angles"] = draw(st.lists(fl(-360, 360), min_size=n, max_size=n))
        torque = draw(st.booleans())
        if torque:
            dl["rotor_inertia"] = draw(fl(1e-3, 1.0))
        doc["dimensionless"] = dl
    else:
        rotor = {"mass": draw(fl(0.1, 100.0))}
        if draw(st.booleans()):
            rotor["eccentricity"] = draw(fl(0.0, 1e-2))
        if draw(st.booleans()):
            rotor["unbalance_angle"] = draw(fl(-720, 720))
        torque = draw(st.booleans())
        if torque:
            rotor["inertia"] = draw(fl(1e-3, 1.0))
        doc["rotor"] = rotor
        if draw(st.booleans()):
            sup = {"stiffness": draw(fl(1e2, 1e6))}
        else:
            sup = {"stiffness_x": draw(fl(1e2, 1e6)), "stiffness_y": draw(fl(1e2, 1e6))}
        if draw(st.booleans()):
            sup["damping"] = draw(fl(0.0, 100.0))
        elif draw(st.booleans()):
            sup["damping_x"], sup["damping_y"] = draw(fl(0.0, 100.0)), draw(fl(0.0, 100.0))
        doc["supports"] = sup
        bal = draw(balancer_tables())
        if bal is not None:
            doc["balancer"] = bal
    doc["drive"] = draw(drive_tables(torque_ok=torque))
    doc["run"] = draw(run_tables())
    if draw(st.booleans()):
        doc["initial"] = {k: draw(fl(-1e-3, 1e-3)) for k in ("x", "y")}
        doc["initial"].update({k: draw(fl(-1e-2, 1e-2)) for k in ("vx", "vy")})
    if draw(st.booleans()):
        pert = draw(perturbation_lists(doc["run"]["duration"]))
        if pert:
            doc["perturbation"] = pert
    if draw(st.booleans()):
        doc["instruments"] = {"keyphasor": {"mark_angle": draw(fl(-180, 180))}}
    return doc


# ---------------------------------------------------------------- leaves and their constraints
#: dotted key (list indices dropped) -> constraint of a valid value
NUMERIC = {
    "rotor.mass": "pos", "rotor.eccentricity": "nonneg", "rotor.unbalance_angle": "any",
    "rotor.inertia": "pos",
    "supports.stiffness": "pos", "supports.stiffness_x": "pos", "supports.stiffness_y": "pos",
    "supports.damping": "nonneg", "supports.damping_x": "nonneg", "supports.damping_y": "nonneg",
    "balancer.mass": "pos", "balancer.radius": "pos", "balancer.drag": "nonneg",
    "balancer.inertia": "pos", "balancer.initial_angles": "any", "balancer.initial_speeds": "any",
    "drive.programme": "nonneg", "drive.programme_dimensionless": "nonneg",
    "drive.coast_down.start": "pos", "drive.coast_down.time_constant": "pos",
    "drive.rotor_drag": "nonneg", "drive.torque": "any", "drive.c1": "nonneg",
    "drive.c2": "nonneg", "drive.target_speed": "nonneg", "drive.initial_speed": "nonneg",
    "run.duration": "pos", "run.sample_rate": "pos", "run.rtol": "pos", "run.atol": "pos",
    "initial.x": "any", "initial.y": "any", "initial.vx": "any", "initial.vy": "any",
    "dimensionless.Rt": "pos", "dimensionless.h": "nonneg", "dimensionless.H": "nonneg",
    "dimensionless.e0": "nonneg", "dimensionless.R_omega2": "pos",
    "dimensionless.unbalance_angle": "any", "dimensionless.initial_angles": "any",
    "dimensionless.natural_frequency": "pos", "dimensionless.total_mass": "pos",
    "dimensionless.track_radius": "pos", "dimensionless.rotor_inertia": "pos",
    "instruments.keyphasor.mark_angle": "any",
}
INTEGER = {"balancer.count", "run.max_steps", "dimensionless.n"}
STRING = {"balancer.type", "drive.type", "drive.model", "run.method", "scene.name",
          "scene.description"}


def leaves(doc):
    """(path as a list of keys/indices, dotted name without list indices, is a
    perturbation field) of every leaf value in ``doc``."""
    out = []

    def walk(v, path):
        if isinstance(v, dict):
            for k, x in v.items():
                walk(x, path + [k])
            return
        if isinstance(v, list) and v and all(isinstance(x, (list, dict)) for x in v) \
                and path[0] != "perturbation":
            for i, x in enumerate(v):
                walk(x, path + [i])
            return
        if isinstance(v, list) and path[0] == "perturbation" and len(path) == 1:
            for i, x in enumerate(v):
                walk(x, path + [i])
            return
        if path[0] == "perturbation":
            out.append((path, f"perturbation[{path[1]}].{path[2]}", True))
            return
        out.append((path, ".".join(p for p in path if isinstance(p, str)), False))

    walk(doc, [])
    return out


def set_path(doc, path, value):
    d = doc
    for p in path[:-1]:
        d = d[p]
    d[path[-1]] = value


def get_path(doc, path):
    d = doc
    for p in path:
        d = d[p]
    return d


WRONG_TYPES = st.one_of(
    st.text(max_size=8), st.booleans(), st.none(), st.just({}), st.just({"a": 1.0}),
    st.lists(st.text(max_size=3), min_size=1, max_size=2).map(lambda v: [v]),
)
NOT_FINITE = st.sampled_from([math.nan, math.inf, -math.inf])
HUGE_INT = st.sampled_from([10 ** 400, -(10 ** 400)])


def bad_value_for(key: str, current):
    """A strategy of values that are invalid for ``key`` whatever the other fields are."""
    if key in NUMERIC:
        c = NUMERIC[key]
        base = [WRONG_TYPES, NOT_FINITE, HUGE_INT]
        if c == "pos":
            base.append(st.one_of(st.just(0.0), st.just(0), fl(-1e300, -1e-300)))
        elif c == "nonneg":
            base.append(fl(-1e300, -1e-300))
        if isinstance(current, list):  # per-weight lists: wrong length, or bad elements
            return st.one_of(st.just(current + current + [1.0]), st.just([]),
                             st.one_of(*base).map(lambda b: [b] * len(current)), *base)
        return st.one_of(*base)
    if key in INTEGER:
        return st.one_of(WRONG_TYPES, NOT_FINITE, st.just(1.5), st.just(0), st.just(-3),
                         st.integers(max_value=0))
    if key in STRING:
        if key.startswith("scene."):
            return st.one_of(st.integers(), st.booleans(), st.just([]), st.just({}))
        return st.one_of(st.integers(), st.booleans(), st.just([]), st.just({}),
                         st.text(max_size=8).filter(lambda s: s not in (
                             "balls", "pendulums", "none", "speed", "torque", "constant",
                             "speed_feedback", "angle_feedback", *METHODS)))
    return None


def check_scene_error_names(exc: SceneError, *names: str):
    msg = str(exc)
    assert msg, "empty SceneError message"
    assert any(n in msg for n in names), f"message {msg!r} does not name any of {names}"


def parse_or_scene_error(doc, parse=parse_scene):
    """parse(doc), or the SceneError it raises."""
    try:
        return parse(doc)
    except SceneError as exc:
        return exc


# ---------------------------------------------------------------- properties: valid scenes
@PROPS(FAST)
@given(valid_docs())
def test_valid_documents_parse_and_keep_their_values(doc):
    sc = parse_scene(copy.deepcopy(doc), text="x")
    assert isinstance(sc, Scene)
    assert sc.run.duration == doc["run"]["duration"]
    assert sc.run.sample_rate == doc["run"]["sample_rate"]
    if "rotor" in doc:
        assert sc.rotor.mass == doc["rotor"]["mass"]
        assert sc.rotor.unbalance_angle == pytest.approx(
            doc["rotor"].get("unbalance_angle", 0.0) * DEG, abs=1e-12)
        s = doc["supports"]
        assert sc.supports.stiffness_x == s.get("stiffness", s.get("stiffness_x"))
        bal = doc.get("balancer", {"type": "none"})
        assert sc.balancer.count == (0 if bal["type"] == "none" else bal["count"])
        if bal["type"] != "none":
            np.testing.assert_allclose(sc.balancer.mass, np.broadcast_to(bal["mass"], (bal["count"],)))
            if "initial_angles" in bal:
                np.testing.assert_allclose(sc.balancer.initial_angles,
                                           np.asarray(bal["initial_angles"]) * DEG)
    else:
        assert sc.balancer.count == doc["dimensionless"]["n"]
    d = doc["drive"]
    if d["type"] == "speed" and "programme" in d:
        np.testing.assert_allclose(sc.drive.programme[:, 1],
                                   np.asarray(d["programme"])[:, 1] * TWO_PI)
    assert len(sc.perturbations) == len(doc.get("perturbation", []))


@PROPS(FAST)
@given(valid_docs())
def test_load_scene_of_the_toml_text_equals_parse_scene(doc):
    text = to_toml(doc)
    a = load_scene(text)
    b = parse_scene(copy.deepcopy(doc), text=text)
    assert a.name == b.name
    assert a.run == b.run
    np.testing.assert_array_equal(a.balancer.mass, b.balancer.mass)
    assert a.rotor == b.rotor and a.supports == b.supports


# ---------------------------------------------------------------- properties: invalid scenes
@PROPS(FAST)
@given(st.data())
def test_a_bad_value_in_any_field_is_a_scene_error_naming_the_key(data):
    doc = data.draw(valid_docs())
    candidates = [(p, key, pert) for p, key, pert in leaves(doc)
                  if not key.endswith("].type") and (key in NUMERIC or key in INTEGER
                                                     or key in STRING or pert)]
    assume(candidates)
    path, key, pert = data.draw(st.sampled_from(candidates))
    current = get_path(doc, path)
    if pert:  # perturbation numbers: wrong types and non-finite values
        strat = st.one_of(WRONG_TYPES, NOT_FINITE, HUGE_INT)
    else:
        strat = bad_value_for(key, current)
    # a bad element inside a programme pair, or the pair itself
    if key.startswith("drive.programme") and isinstance(path[-1], int):
        bad = data.draw(st.one_of(strat, st.just([1.0]), st.just([1.0, 2.0, 3.0]), st.just("x")))
        if isinstance(bad, list) and bad and not isinstance(bad[0], (int, float)):
            bad = [bad[0], 1.0]
    else:
        bad = data.draw(strat)
    set_path(doc, path, bad)
    res = parse_or_scene_error(doc)
    assert isinstance(res, SceneError), f"{key} = {bad!r} accepted"
    check_scene_error_names(res, key)


@PROPS(FAST)
@given(st.data())
def test_an_unknown_key_or_table_is_named(data):
    doc = data.draw(valid_docs())
    where = data.draw(st.sampled_from([k for k, v in doc.items() if isinstance(v, dict)] + [None]))
    name = data.draw(st.text(min_size=1, max_size=12))
    if where is None:
        assume(name not in ("scene", "rotor", "supports", "balancer", "drive", "run", "initial",
                            "dimensionless", "instruments", "perturbation"))
        doc[name] = data.draw(st.one_of(st.just({}), st.integers()))
        expect = f"[{name}]"
    else:
        assume(name not in doc[where])
        if where == "instruments":
            assume(name not in ("screen", "stroboscope", "photogate", "keyphasor",
                                "tachometer", "probes"))
        doc[where][name] = data.draw(st.one_of(fl(0, 1), st.text(max_size=3)))
        expect = f"{where}.{name}"
    res = parse_or_scene_error(doc)
    assert isinstance(res, SceneError), f"unknown {expect} accepted"
    check_scene_error_names(res, expect)


REQUIRED_KEYS = {"rotor": ["mass"], "run": ["duration", "sample_rate"], "drive": ["type"],
                 "dimensionless": ["n", "Rt", "h", "H", "e0"]}


@PROPS(FAST)
@given(st.data())
def test_a_missing_table_or_required_key_is_named(data):
    doc = data.draw(valid_docs())
    tables = [t for t in ("rotor", "supports", "drive", "run", "dimensionless") if t in doc]
    table = data.draw(st.sampled_from(tables))
    if table in REQUIRED_KEYS and data.draw(st.booleans()):
        key = data.draw(st.sampled_from(REQUIRED_KEYS[table]))
        del doc[table][key]
        expect = f"{table}.{key}"
    else:
        del doc[table]
        expect = f"[{table}]"
    res = parse_or_scene_error(doc)
    assert isinstance(res, SceneError)
    # without [dimensionless] the scene needs [rotor] and [supports]: that is what is named
    check_scene_error_names(res, expect, *(["[rotor]"] if table == "dimensionless" else []))


@PROPS(FAST)
@given(st.data())
def test_a_table_of_the_wrong_type_is_named(data):
    doc = data.draw(valid_docs())
    table = data.draw(st.sampled_from([k for k, v in doc.items() if isinstance(v, dict)]))
    doc[table] = data.draw(st.one_of(st.integers(), fl(-1, 1), st.text(max_size=4),
                                     st.lists(st.integers(), max_size=2), st.booleans()))
    res = parse_or_scene_error(doc)
    assert isinstance(res, SceneError)
    check_scene_error_names(res, table)


@PROPS(FAST)
@given(valid_docs(), st.sampled_from(["rotor.mass", "rotor.eccentricity", "supports.damping",
                                      "run.duration", "run.sample_rate", "initial.x",
                                      "drive.rotor_drag", "balancer.radius", "balancer.mass",
                                      "balancer.drag", "dimensionless.natural_frequency",
                                      "dimensionless.total_mass", "dimensionless.track_radius",
                                      "dimensionless.e0"]),
       st.sampled_from([1e-300, 1e-200, 1e30, 1e150, 1e300, 1.7e308]))
def test_extreme_magnitudes_parse_or_are_refused_clearly(doc, key, value):
    table, field = key.split(".")
    assume(table in doc and isinstance(doc[table], dict))
    assume(not (table == "balancer" and doc[table]["type"] == "none"))
    doc[table][field] = value
    res = parse_or_scene_error(doc)
    if isinstance(res, SceneError):
        assert "." in str(res) or "[" in str(res), str(res)
    else:
        assert isinstance(res, Scene)


@PROPS(FAST)
@given(st.recursive(st.none() | st.booleans() | st.integers() | fl(-1e3, 1e3) | st.text(max_size=5),
                    lambda ch: st.lists(ch, max_size=3) | st.dictionaries(st.text(max_size=6), ch,
                                                                           max_size=3),
                    max_leaves=12))
def test_arbitrary_documents_never_crash(doc):
    res = parse_or_scene_error(doc)
    assert isinstance(res, (Scene, SceneError))


@PROPS(FAST)
@given(st.dictionaries(st.sampled_from(["scene", "rotor", "supports", "balancer", "drive", "run",
                                        "initial", "dimensionless", "instruments", "perturbation"]),
                       st.dictionaries(st.sampled_from(
                           ["mass", "type", "count", "radius", "n", "Rt", "h", "H", "e0",
                            "duration", "sample_rate", "stiffness", "programme", "model",
                            "keyphasor", "probes", "screen", "x", "name"]),
                           st.none() | st.booleans() | st.integers(-3, 10 ** 6) | fl(-1e3, 1e3)
                           | st.text(max_size=4) | st.lists(fl(-1, 10), max_size=3)
                           | st.just({}) | st.just([[0.0, 1.0]]), max_size=6),
                       max_size=8))
def test_documents_with_the_right_table_names_never_crash(doc):
    res = parse_or_scene_error(doc)
    assert isinstance(res, (Scene, SceneError))


# ---------------------------------------------------------------- TOML text and files
@PROPS(FAST)
@given(valid_docs(), st.data())
def test_corrupted_toml_text_is_a_scene_error_or_a_scene(doc, data):
    text = to_toml(doc)
    op = data.draw(st.sampled_from(["truncate", "insert", "delete", "replace"]))
    i = data.draw(st.integers(0, len(text)))
    if op == "truncate":
        text = text[:i]
    elif op == "insert":
        text = text[:i] + data.draw(st.sampled_from(["[", "]", "=", '"', "{", "}", ",", "\x00",
                                                     "\\", "#", "[[", "'''", "é", "\r"])) + text[i:]
    elif op == "delete":
        text = text[:i] + text[i + data.draw(st.integers(1, 10)):]
    else:
        text = text.replace("=", data.draw(st.sampled_from([":", "==", " "])), 1)
    text += "\n"
    try:
        sc = load_scene(text)
    except SceneError as exc:
        assert str(exc)
    else:
        assert isinstance(sc, Scene)


@PROPS(FAST)
@given(st.text(max_size=200))
def test_arbitrary_text_is_a_scene_error(text):
    try:
        sc = load_scene(text + "\n")
    except SceneError as exc:
        assert str(exc)
    else:  # pragma: no cover - random text is almost never a scene
        assert isinstance(sc, Scene)


@PROPS(settings(FAST, max_examples=50))
@given(st.binary(max_size=300))
def test_scene_files_with_arbitrary_bytes_are_scene_errors_naming_the_file(tmp_path_factory, blob):
    p = tmp_path_factory.mktemp("sc") / "rig.toml"
    p.write_bytes(blob)
    with pytest.raises(SceneError) as ei:
        load_scene(p)
    assert "rig.toml" in str(ei.value)


def test_missing_and_unreadable_scene_files(tmp_path):
    with pytest.raises(SceneError, match="not found"):
        load_scene(tmp_path / "absent.toml")
    with pytest.raises(SceneError, match="scene"):
        load_scene(tmp_path)  # a directory


def test_dimensionless_ball_count_is_bounded():
    """Found by this suite: [dimensionless] n = 10**9 allocated n-element arrays until the
    process was killed; n is now bounded like balancer.count."""
    doc = {"dimensionless": {"n": 10 ** 9, "Rt": 0.01, "h": 0.1, "H": 0.1, "e0": 0.5},
           "drive": {"type": "speed", "programme": [[0.0, 1.0]]},
           "run": {"duration": 1.0, "sample_rate": 10.0}}
    with pytest.raises(SceneError, match=r"dimensionless\.n = 1000000000: must be <= 10000"):
        parse_scene(doc)


# ---------------------------------------------------------------- rotor-family scenes
@st.composite
def family_docs(draw):
    kind = draw(st.sampled_from(["planar", "two_mass"]))
    if kind == "planar":
        s = {"type": "planar", "mass": draw(fl(0.1, 50.0)), "stiffness_x": draw(fl(1e2, 1e5))}
        if draw(st.booleans()):
            s["stiffness_y"] = draw(fl(1e2, 1e5))
        if draw(st.booleans()):
            s["damping_x"] = draw(fl(0.0, 50.0))
        if draw(st.booleans()):
            s["unbalance"] = draw(fl(0.0, 1e-2))
        planes = ["balancer"]
    else:
        s = {"type": "two_mass", "body_mass": draw(fl(0.1, 10.0)), "rotor_mass": draw(fl(0.1, 10.0)),
             "body_stiffness": draw(fl(1e2, 1e5)), "rotor_stiffness": draw(fl(1e2, 1e5))}
        if draw(st.booleans()):
            s["body_damping"] = draw(fl(0.0, 50.0))
        planes = ["balancer", "body"]
    doc = {"structure": s, "drive": {"type": "speed", "programme": draw(programmes())},
           "run": {"duration": draw(fl(1e-3, 0.05)), "sample_rate": draw(fl(20.0, 1000.0))}}
    if draw(st.booleans()):
        doc["scene"] = {"name": draw(st.text(max_size=10))}
    weights = []
    for _ in range(draw(st.integers(0, 2))):
        n = draw(st.integers(1, 3))
        w = {"plane": draw(st.sampled_from(planes)), "type": "balls", "count": n,
             "mass": draw(per_weight(n, 1e-3, 0.1)), "radius": draw(per_weight(n, 0.01, 0.3))}
        if draw(st.booleans()):
            w["drag"] = draw(fl(0.0, 1.0))
        if draw(st.booleans()):
            w["rolling"] = draw(st.booleans())
        if draw(st.booleans()):
            w["friction"] = draw(fl(0.0, 0.01))
        weights.append(w)
    if weights:
        doc["weights"] = weights
    return doc


@PROPS(FAST)
@given(family_docs())
def test_valid_family_scenes_parse(doc):
    fs = parse_family_scene(copy.deepcopy(doc))
    assert isinstance(fs, FamilyScene)
    assert fs.structure_type == doc["structure"]["type"] and fs.kind == "rotor"
    assert len(fs.weights) == len(doc.get("weights", []))


FAMILY_BAD = st.one_of(WRONG_TYPES, NOT_FINITE, HUGE_INT, st.just(-1.0), st.just(0.0))


@PROPS(FAST)
@given(family_docs(), st.data())
def test_family_scene_bad_structure_values_name_the_key(doc, data):
    key = data.draw(st.sampled_from([k for k in doc["structure"] if k != "type"]))
    bad = data.draw(FAMILY_BAD)
    if key.startswith(("damping", "body_damping")) and bad == 0.0:
        bad = -1.0
    # a signed unbalance s = M e is meaningful (the heavy side turned by 180 deg)
    assume(not (key == "unbalance" and isinstance(bad, float) and math.isfinite(bad)))
    doc["structure"][key] = bad
    res = parse_or_scene_error(doc, parse_family_scene)
    assert isinstance(res, SceneError), f"structure.{key} = {bad!r} accepted"
    check_scene_error_names(res, key)


@PROPS(FAST)
@given(family_docs(), st.data())
def test_family_scene_bad_weights_and_tables_are_scene_errors(doc, data):
    what = data.draw(st.sampled_from(["structure", "weights", "plane", "friction", "rolling",
                                      "table", "drive", "run", "type", "root"]))
    bad = data.draw(st.one_of(WRONG_TYPES, NOT_FINITE, HUGE_INT, st.integers(-5, 5),
                              st.just([1, 2]), st.just([[1.0]])))
    w = {"type": "balls", "count": 1, "mass": 0.01, "radius": 0.1}
    if what == "structure":
        doc["structure"] = bad
    elif what == "weights":
        doc["weights"] = data.draw(st.one_of(st.just(bad), st.just([bad])))
    elif what in ("plane", "friction", "rolling"):
        if what == "rolling" and isinstance(bad, bool):
            bad = "yes"
        if what == "friction" and isinstance(bad, int) and not isinstance(bad, bool) \
                and -5 <= bad <= 5:
            bad = -1.0
        doc["weights"] = [dict(w, **{what: bad})]
    elif what == "table":
        doc[data.draw(st.text(min_size=1, max_size=6).filter(
            lambda s: s not in ("scene", "structure", "weights", "drive", "run")))] = {}
    elif what in ("drive", "run"):
        doc[what] = bad
    elif what == "type":
        doc["structure"]["type"] = data.draw(st.one_of(WRONG_TYPES, st.text(max_size=8)))
        assume(doc["structure"]["type"] not in ("planar", "two_mass"))
    else:
        doc = bad
    res = parse_or_scene_error(doc, parse_family_scene)
    assert isinstance(res, SceneError), f"{what}: {bad!r} accepted"
    assert str(res)


@PROPS(FAST)
@given(st.recursive(st.none() | st.booleans() | st.integers() | fl(-1e3, 1e3) | st.text(max_size=5),
                    lambda ch: st.lists(ch, max_size=3) | st.dictionaries(
                        st.sampled_from(["structure", "type", "mass", "weights", "drive", "run",
                                         "plane", "programme", "duration", "stiffness_x"]),
                        ch, max_size=4),
                    max_leaves=14))
def test_arbitrary_family_documents_never_crash(doc):
    res = parse_or_scene_error(doc, parse_family_scene)
    assert isinstance(res, (FamilyScene, SceneError))


# ---------------------------------------------------------------- simulation of valid scenes
@pytest.fixture(scope="module")
def warm():
    from stand.integrate.simulate import simulate

    simulate(load_scene(
        "[rotor]\nmass = 1.0\n[supports]\nstiffness = 1e4\n[balancer]\ntype = \"balls\"\n"
        "count = 2\nmass = 0.01\nradius = 0.1\n[drive]\ntype = \"speed\"\n"
        "programme = [[0, 5]]\n[run]\nduration = 0.01\nsample_rate = 100\n"))
    return simulate


@PROPS(SLOW)
@given(valid_docs())
def test_valid_scenes_simulate_to_a_clear_status_in_bounded_time(warm, doc):
    sc = parse_scene(doc)
    t0 = time.perf_counter()
    traj = warm(sc)
    wall = time.perf_counter() - t0
    assert wall < 60.0, f"simulate took {wall:.1f} s for a {sc.run.duration:g} s run"
    st_ = traj.stats
    assert isinstance(st_.status, int) or isinstance(st_.status, np.integer)
    assert st_.message
    if st_.success:
        assert traj.t.size >= 1 and traj.t[-1] <= sc.run.duration * (1 + 1e-9)
        assert np.all(np.isfinite(traj.x)) and np.all(np.isfinite(traj.y))
    else:
        assert st_.status < 0


# ---------------------------------------------------------------- regressions found by this suite
def test_velocity_scale_underflow_is_a_scene_error():
    """rotor.mass = 1e300 made length scale * natural frequency underflow to 0:
    ZeroDivisionError in check_derived."""
    doc = {"rotor": {"mass": 1e300}, "supports": {"stiffness": 100.0},
           "balancer": {"type": "balls", "count": 1, "mass": 0.5, "radius": 0.25},
           "drive": {"type": "speed", "programme": [[0.0, 0.0]]},
           "run": {"duration": 0.03, "sample_rate": 20.0}}
    with pytest.raises(SceneError, match="velocity scale"):
        parse_scene(doc)


@pytest.mark.parametrize("key", ["track_radius", "natural_frequency"])
def test_dimensionless_overflow_is_a_scene_error(key):
    """float ** 2 raised OverflowError in scene_from_dimensionless."""
    doc = {"dimensionless": {"n": 1, "Rt": 0.25, "h": 0.0, "H": 0.0, "e0": 0.0, key: 1e300},
           "drive": {"type": "speed", "programme_dimensionless": [[0.0, 0.0]]},
           "run": {"duration": 0.03, "sample_rate": 20.0}}
    with pytest.raises(SceneError, match="out of floating-point range"):
        parse_scene(doc)


FAMILY = {"structure": {"type": "planar", "mass": 1.0, "stiffness_x": 100.0},
          "drive": {"type": "speed", "programme": [[0.0, 0.0]]},
          "run": {"duration": 0.03, "sample_rate": 20.0}}
W = {"type": "balls", "count": 1, "mass": 0.01, "radius": 0.1}


@pytest.mark.parametrize("change, match", [
    (lambda d: d.update(structure=5), r"structure = 5: must be a table"),
    (lambda d: d.update(structure=[1, 2]), r"structure = \[1, 2\]: must be a table"),
    (lambda d: d["structure"].update(mass=10 ** 400), r"structure\.mass = 1000"),
    (lambda d: d["structure"].update(mass=True), r"structure\.mass = true: must be a number"),
    (lambda d: d["structure"].update(stiffness_y="x"), r"structure\.stiffness_y = \"x\""),
    (lambda d: d["structure"].update(g="ab"), r"structure\.g = \"ab\": must be a list"),
    (lambda d: d.update(weights=[dict(W, plane=[1])]), r"weights\[0\]\.plane = \[1\]"),
    (lambda d: d.update(weights=[dict(W, friction=10 ** 400)]), r"weights\[0\]\.friction = 1000"),
    (lambda d: d.update(weights=[dict(W, friction=math.nan)]), r"weights\[0\]\.friction = nan"),
])
def test_family_scene_crashes_found_by_the_fuzzer(change, match):
    doc = copy.deepcopy(FAMILY)
    change(doc)
    with pytest.raises(SceneError, match=match):
        parse_family_scene(doc)


def test_family_scene_that_is_not_a_table():
    with pytest.raises(SceneError, match="table of tables"):
        parse_family_scene(None)


def test_family_scene_without_a_programme():
    """Was KeyError: 'programme' (an empty [drive] table)."""
    doc = copy.deepcopy(FAMILY)
    doc["drive"] = {}
    with pytest.raises(SceneError, match=r"drive\.programme: missing required key"):
        parse_family_scene(doc)


test_property_with_all_its_examples = PROPS.full_test()
