"""Helpers shared by several test modules (imported as ``from _helpers import ...``;
pytest puts tests/ on sys.path since it has no __init__.py)."""
import copy
import inspect
import io
import json
import subprocess
import sys
import time
from contextlib import contextmanager, redirect_stderr, redirect_stdout

import numpy as np

from stand.model.planar import build_planar_model
from stand.scene.model import RunSettings, SpeedDrive
from stand.scene.parse import scene_from_dimensionless


# ------------------------------------------------------------------ scene and sweep texts
def toml_value(value) -> str:
    """A TOML literal for a Python value: bool, int, float (its shortest round-trip
    repr, so it parses back to the same number), str, list/tuple, dict (inline table)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"no TOML literal for {value!r}")


def toml_text(**tables) -> str:
    """The TOML text of a scene or sweep file: one ``[name]`` table per keyword, in the
    order given; a list of dicts gives an array of tables ``[[name]]``; ``__`` in a keyword
    stands for a dot (``instruments__screen`` -> ``[instruments.screen]``).

    >>> toml_text(rotor=dict(mass=4.0), run=dict(duration=5.0, sample_rate=100))
    '[rotor]\\nmass = 4.0\\n[run]\\nduration = 5.0\\nsample_rate = 100\\n'
    """
    lines = []
    for name, table in tables.items():
        name = name.replace("__", ".")
        blocks = [(f"[[{name}]]", t) for t in table] if isinstance(table, list) else [(f"[{name}]", table)]
        for head, body in blocks:
            lines.append(head)
            lines += [f"{key} = {toml_value(v)}" for key, v in body.items()]
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------ main-motion theory
def dimensionless_model(n, W, Rt, h, H, e0):
    """The planar model of n equal balls in dimensionless units at constant speed W."""
    sc = scene_from_dimensionless(n, Rt, h, H, e0, drive=SpeedDrive(np.array([[0.0, W]])),
                                  run=RunSettings(1.0, 1.0))
    return build_planar_model(sc)


def match_roots(ev, ref, tol):
    """Pair every reference root with the nearest of ev (each used once) within tol;
    returns the roots of ev left over."""
    ev = list(ev)
    for r in ref:
        i = int(np.argmin(np.abs(np.array(ev) - r)))
        assert abs(ev[i] - r) < tol, (r, ev[i])
        ev.pop(i)
    return ev


# ------------------------------------------------------------------ child processes
def wait_for(condition, proc: subprocess.Popen, timeout_s: float = 120.0, poll_s: float = 0.05) -> bool:
    """Wait until ``condition()`` is true, the child ``proc`` has ended or ``timeout_s``
    has passed; returns ``condition()``.  Between two looks at the condition the test
    waits on the child itself (``proc.wait``), not in a sleep: a child that ends (done
    or crashed) ends the wait at once."""
    end = time.monotonic() + timeout_s
    while not condition() and time.monotonic() < end:
        try:
            proc.wait(timeout=poll_s)
        except subprocess.TimeoutExpired:
            continue
        break
    return condition()


# ------------------------------------------------------------------ the stand program, in process
def stand_stdout(*argv) -> str:
    """``stand <argv>`` run in this process (stand.cli.main.main, as the ``stand`` program
    runs it): asserts exit 0 and returns what it printed on stdout."""
    from stand.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main([str(a) for a in argv])
    assert code == 0, f"stand {' '.join(map(str, argv))}: exit {code}\n{err.getvalue()}"
    return out.getvalue()


# ------------------------------------------------------------------ theory computed once
def _scene_key(scene) -> str:
    """The scene's TOML text and every field at full precision (numpy arrays unabbreviated,
    floats in their exact round-trip form): equal keys, equal theory inputs."""
    with np.printoptions(threshold=sys.maxsize, floatmode="unique"):
        return f"{scene.text}\n{scene!r}"


def _memoized(fn, cache: dict, session: bool = False):
    """``fn(scene, ...)`` once per (scene, arguments) in ``cache``; with ``session``, once per
    test session, whichever pytest-xdist worker asks first (tests/_shared.py)."""
    signature = inspect.signature(fn)

    def wrapper(*args, **kwargs):
        bound = signature.bind(*args, **kwargs)   # f(s), f(s, None), f(s, R_max=None): one key
        bound.apply_defaults()
        scene, *rest = bound.arguments.values()
        key = (fn.__module__, fn.__qualname__, _scene_key(scene), repr(rest))
        if key not in cache:                 # an exception is not stored: raised every time
            if session and " at 0x" not in key[3]:   # (an argument without a stable repr: here)
                from _shared import once

                cache[key] = once(repr(key), lambda: fn(*args, **kwargs))
            else:
                cache[key] = fn(*args, **kwargs)
        return copy.deepcopy(cache[key])     # no caller sees another caller's changes
    wrapper.__wrapped__ = fn
    return wrapper


#: the theories kept for the whole test process (``theory_computed_once(shared=True)``)
_SHARED_THEORIES: dict = {}


@contextmanager
def theory_computed_once(shared: bool = False):
    """Within the block, the chapter-5 speed map (planar_theory.speedmap.scene_theory) and
    the structure theory (rotors.run.family_theory) of a scene are computed once per
    (scene, arguments) and a deep copy of that result is handed to every later caller
    (``stand theory``, ``theory --json``, ``stand.theory``, the report's dynamics
    section): both are deterministic functions of the scene and their arguments, so a
    test that runs several commands on one scene checks each command's own code (argument
    handling, serialisation, text, report) on the same numbers without recomputing them.
    The first caller's computation is the real one; their results are checked against the
    physics, without this, in test_theory_scene.py, test_rotors_*.py, test_report_*.py.
    Every caller imports them at call time from their modules, where they are replaced;
    the originals are put back when the block ends.  ``shared``: the results are kept for
    the test session, so the modules that ask for it share them (the sample recording's
    theory: once per session, whichever pytest-xdist worker asks first: tests/_shared.py)."""
    from stand.theories.planar import speedmap
    from stand.theories import rotors as rotors_run

    cache: dict = _SHARED_THEORIES if shared else {}
    saved = speedmap.scene_theory, rotors_run.family_theory
    speedmap.scene_theory = _memoized(saved[0], cache, shared)
    rotors_run.family_theory = _memoized(saved[1], cache, shared)
    try:
        yield cache
    finally:
        speedmap.scene_theory, rotors_run.family_theory = saved


#: a cheap, well-conditioned stress case (8 balls balance in 100 tau, well under a second once
#: compiled); fields: name, tol, e0, extra (more case keys, or "")
CHEAP_STRESS_CASE = """
[[case]]
name = "{name}"
kind = "dimensionless"
check = "balanced"
tolerance = {tol}
time_budget_s = 60.0
{extra}
[case.params]
n = 8
Rt = 0.01
h = 0.5
H = 0.1
e0 = {e0}
R = 3.0
duration_tau = 100.0
"""


# ------------------------------------------------------------------ the result contract
def _agg_axes():
    """A figure with one Axes on the Agg canvas: draws without a display or pyplot."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure()
    FigureCanvasAgg(fig)
    return fig, fig.subplots()


def assert_result_contract(res, cli_doc=None):
    """The one contract of every answer of the stand (docs/results.md): a ``stand.Result``
    importable from ``stand``; ``to_dict()`` plain strict JSON, the same through
    ``to_json()``, ``to_jsonable`` and mapping access (and equal to the command line's
    ``--json`` document ``cli_doc`` where given); ``to_frame()`` and ``to_frame(t)`` for every
    ``t`` of ``tables()`` are DataFrames (the base's ``to_frame()`` holds every number of the
    document), an unknown table is a KeyError; ``plot(ax=)`` draws on the Axes given and
    returns them, an unknown ``kind`` is a ValueError; a short ``repr`` and an HTML table."""
    import pandas as pd
    import pytest

    import stand
    from stand.io.jsonable import to_jsonable
    from stand.io.result import Result, flatten_numbers

    cls = type(res)
    assert isinstance(res, stand.Result)
    assert getattr(stand, cls.__name__) is cls, f"{cls.__name__} is not exported by stand"
    doc = res.to_dict()
    assert doc and json.loads(json.dumps(doc, allow_nan=False)) == doc
    assert json.loads(res.to_json()) == doc == to_jsonable(res)
    for key, value in doc.items():      # mapping access gives the document's values
        assert to_jsonable(res[key]) == value, key
    if cli_doc is not None:
        assert doc == cli_doc
    df = res.to_frame()
    assert isinstance(df, pd.DataFrame) and len(df) > 0
    if cls.to_frame is Result.to_frame:
        numbers = flatten_numbers(doc)
        assert list(df.columns) == ["key", "value"] and len(df) == len(numbers)
        assert dict(zip(df["key"], df["value"])) == pytest.approx(dict(numbers))
    for table in res.tables():
        assert isinstance(res.to_frame(table), pd.DataFrame), table
    with pytest.raises(KeyError, match="no table"):
        res.to_frame("no_such_table")
    fig, ax = _agg_axes()
    assert res.plot(ax=ax) is ax
    fig.canvas.draw()           # renders without a display: the picture is complete
    assert ax.lines or ax.patches or ax.collections or ax.texts
    with pytest.raises(ValueError, match="kind = 'no_such_kind'"):
        res.plot(ax=_agg_axes()[1], kind="no_such_kind")
    text = repr(res)
    assert text.startswith(f"{cls.__name__}(") and len(text) < 400
    assert "<table>" in res._repr_html_()


# ------------------------------------------------------------------ property tests: a share by default
class Properties:
    """Hypothesis properties that try a share of their examples in the default run and all of
    them under ``-m full`` (issue 43): ``@props(SETTINGS)`` in place of ``@SETTINGS`` (outside
    ``@given``) runs the property with ``max(minimum, max_examples // divisor)`` examples
    (derandomized: the same ones each run); ``test_x = props.full_test()`` at the end of the module
    is one test per property, marked ``full``, that runs it with ``SETTINGS`` unchanged."""

    def __init__(self, divisor: int = 8, minimum: int = 8):
        self.divisor, self.minimum, self.full = divisor, minimum, {}

    def __call__(self, full_settings):
        from hypothesis import settings

        def decorate(test):
            self.full[test.__name__] = (test, full_settings)
            n = max(self.minimum, full_settings.max_examples // self.divisor)
            return settings(full_settings, max_examples=min(n, full_settings.max_examples))(test)
        return decorate

    def full_test(self):
        import pytest
        from hypothesis import given, settings

        @pytest.mark.full
        @pytest.mark.parametrize("name", sorted(self.full))
        def test_property_with_all_its_examples(name, request):
            """The property ``name`` with its full example count (its default-run test tries a
            share of them, the same code paths)."""
            test, full_settings = self.full[name]
            handle = test.hypothesis
            strategies = handle._given_kwargs       # hypothesis' record of the @given arguments
            again = settings(full_settings)(given(**strategies)(handle.inner_test))
            fixtures = [p for p in inspect.signature(handle.inner_test).parameters if p not in strategies]
            again(**{p: request.getfixturevalue(p) for p in fixtures})
        return test_property_with_all_its_examples
