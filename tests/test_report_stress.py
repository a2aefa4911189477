"""`stand stress` (stand.reports.stress): the stress catalogue and its report.

The default catalogue's fast cases run once (module fixture); the parser and
the pass/fail logic are checked on small custom catalogues.
"""
import json
import re

import pytest
from _html import body_children

from _helpers import CHEAP_STRESS_CASE
from stand.reports.html import check_schema
from stand.reports.stress import (CASE_SCHEMA, DEFAULT_CATALOGUE, SCHEMA, CatalogueError,
                                  load_catalogue, run_stress)

CHEAP = CHEAP_STRESS_CASE


def write(tmp_path, text, name="cat.toml"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def cheap(name="cheap", tol=1e-3, e0=0.3, extra=""):
    return CHEAP.format(name=name, tol=tol, e0=e0, extra=extra)


def assert_valid(doc):
    assert check_schema(doc, SCHEMA) == []
    for c in doc["cases"]:
        assert check_schema(c, CASE_SCHEMA) == [], c["name"]
        assert c["reason"].strip()
    assert doc["summary"]["n_cases"] == len(doc["cases"])
    assert doc["summary"]["n_passed"] + doc["summary"]["n_failed"] == len(doc["cases"])


def assert_no_external_urls(html):
    for attr, url in re.findall(r"""(src|href)\s*=\s*["']([^"']*)["']""", html, flags=re.I):
        if attr.lower() == "href":
            assert url.startswith("#"), url
        else:
            assert url.startswith("data:image/png;base64,"), url[:60]
    assert "http://" not in html and "https://" not in html


@pytest.fixture(scope="module")
def fast_report(tmp_path_factory):
    d = tmp_path_factory.mktemp("stress")
    doc = run_stress(cases="fast", json_path=d / "stress.json", html_path=d / "stress.html")
    return doc, d


def test_default_catalogue_parses_and_covers_the_issue():
    cases = {c["name"]: c for c in load_catalogue()}
    for name in ("fast_rotor_R200", "stiff_ball_drag_h1e4", "undamped_free_energy",
                 "undamped_forced_jacobi", "balls_64", "balls_256", "capacity_exceeded_e0_2",
                 "liquid_psi_0.1", "runup_1e5_revolutions", "qp_below_escape_speed",
                 "qp_above_escape_speed", "platform_paper004_steady", "speed_jump"):
        assert name in cases, name
    assert cases["fast_rotor_R200"]["params"]["R"] == 200.0
    assert cases["stiff_ball_drag_h1e4"]["params"]["h"] == 1e4
    assert cases["balls_256"]["params"]["n"] == 256
    assert cases["qp_below_escape_speed"]["params"]["offset"] == -1e-3
    assert cases["qp_above_escape_speed"]["params"]["offset"] == 1e-3
    assert DEFAULT_CATALOGUE.name == "stress_catalogue.toml"


def test_fast_cases_pass_and_validate(fast_report):
    doc, d = fast_report
    assert_valid(doc)
    assert doc["summary"]["n_cases"] >= 8
    for c in doc["cases"]:
        assert c["pass"], (c["name"], c["reason"])
        assert c["converged"], c["name"]
        assert c["case_time_s"] <= c["time_budget_s"]
        assert c["error"] is not None and c["error"] <= c["tolerance"], c["name"]
    on_disk = json.loads((d / "stress.json").read_text())
    assert on_disk == json.loads(json.dumps(doc))


def test_fast_report_facts(fast_report):
    doc, _ = fast_report
    by = {c["name"]: c for c in doc["cases"]}
    assert by["stiff_ball_drag_h1e4"]["method"] == "Radau"
    assert "stiff" in by["stiff_ball_drag_h1e4"]["method_reason"]
    assert by["fast_rotor_R200"]["method"] == "DOP853"
    assert by["undamped_free_energy"]["drift"] < 1e-7
    assert by["undamped_forced_jacobi"]["conserved_quantity"] == "Jacobi integral"
    e2 = by["capacity_exceeded_e0_2"]
    assert e2["outside_validity"] and "e0 = 2 > 1" in e2["outside_validity"]
    assert e2["declared_outside_validity"]
    assert by["qp_above_escape_speed"]["details"]["escape_speed"] == pytest.approx(9.0)
    assert by["liquid_psi_0.1"]["conserved_quantity"].startswith("free-whirl")


def test_html_has_no_external_urls(fast_report):
    _, d = fast_report
    html = (d / "stress.html").read_text()
    assert "<img" in html
    assert_no_external_urls(html)


def test_html_verdict_first_then_one_line_per_case(fast_report):
    doc, d = fast_report
    h1, banner, cases = body_children((d / "stress.html").read_text())[:3]
    n = doc["summary"]["n_cases"]
    assert h1["tag"] == "h1"
    assert banner["attrs"] == {"id": "verdict", "class": "pass"}
    assert banner["lines"][0] == f"{n} of {n} cases passed"
    assert cases["tag"] == "ul" and cases["attrs"]["id"] == "case-list"
    assert cases["lines"] == [f"{c['name']}: passed" for c in doc["cases"]]


def test_failed_case_is_named_in_the_verdict_with_its_reason(tmp_path):
    doc = run_stress(write(tmp_path, cheap("fine") + cheap("impossible", tol=1e-30)),
                     html_path=tmp_path / "r.html")
    reason = doc["cases"][1]["reason"]
    assert "1e-30" in reason
    h1, banner, cases = body_children((tmp_path / "r.html").read_text())[:3]
    assert banner["attrs"] == {"id": "verdict", "class": "fail"}
    assert banner["lines"][0] == "1 of 2 cases failed: impossible"
    assert cases["lines"] == ["fine: passed", f"impossible: failed — {reason}"]


def test_added_case_runs(tmp_path):
    text = cheap("balanced_8_balls") + """
[[case]]
name = "energy_3_balls"
kind = "dimensionless"
check = "energy"
tolerance = 1e-7
time_budget_s = 60.0
[case.params]
n = 3
Rt = 0.02
h = 0.0
H = 0.0
e0 = 0.0
R = 2.0
duration_tau = 100.0
initial_x = 0.5
rtol = 1e-11
"""
    doc = run_stress(write(tmp_path, text), html_path=tmp_path / "r.html")
    assert_valid(doc)
    assert [c["name"] for c in doc["cases"]] == ["balanced_8_balls", "energy_3_balls"]
    assert all(c["pass"] for c in doc["cases"]), [c["reason"] for c in doc["cases"]]
    assert_no_external_urls((tmp_path / "r.html").read_text())


def test_impossible_tolerance_fails_with_reason(tmp_path):
    doc = run_stress(write(tmp_path, cheap("impossible", tol=1e-30)))
    assert_valid(doc)
    (c,) = doc["cases"]
    assert c["pass"] is False
    assert "tolerance" in c["reason"] and "1e-30" in c["reason"]
    assert doc["summary"]["all_passed"] is False and doc["summary"]["n_failed"] == 1


def test_time_budget_exceeded_fails(tmp_path):
    text = cheap("too_slow").replace("time_budget_s = 60.0", "time_budget_s = 1e-9")
    (c,) = run_stress(write(tmp_path, text))["cases"]
    assert not c["pass"] and "time budget" in c["reason"]


def test_outside_validity_must_be_declared(tmp_path):
    undeclared = cheap("e0_2", tol=1e-2, e0=2.0).replace("duration_tau = 100.0", "duration_tau = 300.0")
    declared = cheap("e0_2_declared", tol=1e-2, e0=2.0,
                     extra='outside_validity = "capacity exceeded"').replace(
        "duration_tau = 100.0", "duration_tau = 300.0")
    doc = run_stress(write(tmp_path, undeclared + declared))
    a, b = doc["cases"]
    assert not a["pass"] and "not declared" in a["reason"] and "e0 = 2 > 1" in a["reason"]
    assert b["pass"], b["reason"]
    assert "as declared" in b["reason"]


@pytest.mark.parametrize("edit, words", [
    (lambda t: t.replace("tolerance = 0.001", "tolerance = -1.0"), ["'bad'", "tolerance", "> 0"]),
    (lambda t: t.replace('kind = "dimensionless"\n', ""), ["'bad'", "kind", "missing"]),
    (lambda t: t.replace('kind = "dimensionless"', 'kind = "warp"'), ["'bad'", "kind", "dimensionless"]),
    (lambda t: t.replace('check = "balanced"', 'check = "nonsense"'), ["'bad'", "check", "balanced"]),
    (lambda t: t.replace("h = 0.5", 'h = "big"'), ["'bad'", "params.h", "number"]),
    (lambda t: t.replace("h = 0.5", "h = -0.5"), ["'bad'", "params.h", ">= 0"]),
    (lambda t: t.replace("Rt = 0.01", "Rtt = 0.01"), ["'bad'", "params.Rtt", "unknown"]),
    (lambda t: t.replace("Rt = 0.01\n", ""), ["'bad'", "params.Rt", "missing"]),
    (lambda t: t.replace("n = 8", "n = 2.5"), ["'bad'", "params.n", "integer"]),
    (lambda t: t.replace("R = 3.0", "programme = [[0.0, 1.0], [0.0, 2.0]]"), ["'bad'", "params.programme"]),
    (lambda t: t.replace("time_budget_s = 60.0", "time_budget = 60.0"), ["'bad'", "time_budget"]),
])
def test_malformed_case_names_case_and_field(tmp_path, edit, words):
    text = cheap("good") + edit(cheap("bad"))
    with pytest.raises(CatalogueError) as exc:
        run_stress(write(tmp_path, text))
    msg = str(exc.value)
    assert "case #2" in msg
    for w in words:
        assert w in msg, (w, msg)


def test_catalogue_level_errors(tmp_path):
    with pytest.raises(CatalogueError, match="duplicates case #1"):
        load_catalogue(write(tmp_path, cheap("same") + cheap("same")))
    with pytest.raises(CatalogueError, match="TOML syntax error"):
        load_catalogue(write(tmp_path, "[[case]\nname = 1"))
    with pytest.raises(CatalogueError, match=r"no \[\[case\]\]"):
        load_catalogue(write(tmp_path, "[catalogue]\n"))
    with pytest.raises(CatalogueError, match="cannot read catalogue"):
        load_catalogue(tmp_path / "missing.toml")
    with pytest.raises(CatalogueError, match="no case named 'nope'"):
        run_stress(write(tmp_path, cheap("one")), cases=["nope"])


def test_reasons_and_oracles_in_words(tmp_path):
    """The drift check prints its tolerance ('|drift| <= tolerance 1e-06'), and the balanced
    check's oracle says in words whether the main motion is stable (no '(stable: True)')."""
    text = cheap("balanced_8_balls") + """
[[case]]
name = "liquid_runup"
kind = "liquid_runup"
check = "runup_closed_form"
tolerance = 1e-6
time_budget_s = 60.0
[case.params]
psi = 0.1
n = 0.0
Omega_0 = 1000.0
e = 1e-4
omega_0 = 40.0
acceleration = 20.0
t_end = 30.0
sample_rate = 100.0
rtol = 1e-10
frame = "rotating"
"""
    doc = run_stress(write(tmp_path, text), html_path=tmp_path / "r.html")
    bal, runup = doc["cases"]
    drift = re.search(r"drift of the free-whirl amplitude \|c\+\| \(undamped\) (\S+): "
                      r"\|drift\| <= tolerance 1e-06", runup["reason"])
    assert drift and float(drift[1]) == pytest.approx(runup["drift"], rel=1e-2), runup["reason"]
    # R = 3 omega1 with h = 0.5, H = 0.1: above the balancing threshold, main motion stable (5.90)
    assert bal["oracle"].endswith("at R_omega = 3, where it is asymptotically stable"), bal["oracle"]
    assert "stable: True" not in (tmp_path / "r.html").read_text()
