"""The stress catalogue of ``stand stress``: reading and validating its ``[[case]]`` tables.

The catalogue (TOML, default :data:`DEFAULT_CATALOGUE`) is documented field by
field in docs/reports_stress.md.  :func:`load_catalogue` checks every case
before any runs; a malformed one raises :class:`CatalogueError` naming the
file, the case (number and name) and the field, e.g.
``cat.toml: case #2 'bad': field tolerance = -1.0: must be > 0 (dimensionless)``.

The checks of single values are those of the scene files
(:class:`stand.scene.parse.Table`, the same messages and unit conventions);
this module adds the catalogue's own fields, the parameter specs of each kind
(:data:`KINDS`) and the checks that involve several fields.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping


from stand.errors import SceneError
from stand.scene.parse import Table, _fmt, _kind, _suggest

__all__ = ["load_catalogue", "CatalogueError", "DEFAULT_CATALOGUE", "KINDS", "select_cases"]

DEFAULT_CATALOGUE = Path(__file__).with_name("stress_catalogue.toml")


class CatalogueError(ValueError):
    """A malformed catalogue; the message names the case and the field."""


CASE_FIELDS = ("name", "kind", "description", "check", "tolerance", "time_budget_s", "fast",
               "outside_validity", "expect_method", "reference_rtol", "convergence_tolerance",
               "params")

_NUM, _INT, _STR, _BOOL, _LIST = "number", "integer", "string", "boolean", "array"
_REQUIRED = ...  #: default of a parameter the case must give
_DIMENSIONLESS = "dimensionless"
_METHODS = ("auto", "DOP853", "Radau", "BDF", "LSODA")


def _p(kind: str, unit: str = "", default: Any = _REQUIRED, *, gt=None, ge=None, lt=None,
       choices=None) -> dict:
    """One parameter's spec: type, unit (for messages), default (``...``: required), bounds."""
    return dict(kind=kind, unit=unit, default=default, gt=gt, ge=ge, lt=lt, choices=choices)


_DIMLESS = {
    "n": _p(_INT, ge=1), "Rt": _p(_NUM, "dimensionless, R~_m", ge=0, lt=0.5),
    "h": _p(_NUM, "dimensionless ball drag", ge=0), "H": _p(_NUM, "dimensionless support damping", ge=0),
    "e0": _p(_NUM, "rotor unbalance / capacity S", ge=0), "R": _p(_NUM, "units of omega_1", None, gt=0),
    "programme": _p(_LIST, "rows [tau, R_omega]", None),
    "R_omega2": _p(_NUM, "dimensionless, sqrt(c_y/c_x)", 1.0, gt=0),
    "duration_tau": _p(_NUM, "tau = s", gt=0),
    "sample_rate": _p(_NUM, "samples per tau", 1.0, gt=0),
    "rtol": _p(_NUM, _DIMENSIONLESS, 1e-9, gt=0), "atol": _p(_NUM, "dimensionless state", None, gt=0),
    "method": _p(_STR, default="auto", choices=_METHODS),
    "initial_angles_deg": _p(_LIST, "deg", None), "initial_x": _p(_NUM, "units of r*", 0.0),
    "initial_speeds": _p(_NUM, "units of omega_1, relative to the rotor", 0.0),
    "max_steps": _p(_INT, default=50_000_000, ge=1),
}
_SCENE_FILE = {
    "path": _p(_STR), "duration": _p(_NUM, "s (or the book model's time)", None, gt=0),
    "rtol": _p(_NUM, _DIMENSIONLESS, None, gt=0),
    "atol": _p(_NUM, "dimensionless state", None, gt=0),
    "method": _p(_STR, default="auto", choices=_METHODS),
}
#: kind body_scene (stand.reports.stress_bodies): a scene with body weights, same fields
_BODY_SCENE = dict(_SCENE_FILE)
_LIQUID = {
    "psi": _p(_NUM, "m1/m", gt=0), "n": _p(_NUM, "1/s", 0.0, ge=0),
    "Omega_0": _p(_NUM, "rad/s", 1000.0, gt=0), "e": _p(_NUM, "m", 1e-4, gt=0),
    "omega_0": _p(_NUM, "rad/s", 40.0, ge=0), "acceleration": _p(_NUM, "rad/s^2", gt=0),
    "t_end": _p(_NUM, "s", gt=0), "sample_rate": _p(_NUM, "Hz", 100.0, gt=0),
    "rtol": _p(_NUM, _DIMENSIONLESS, 1e-10, gt=0),
    "frame": _p(_STR, default="rotating", choices=("rotating", "fixed")),
    "method": _p(_STR, default="DOP853", choices=("DOP853", "RK45", "Radau", "BDF", "LSODA")),
}
_PLATFORM = {
    "speed": _p(_NUM, "rad/s", gt=0), "duration": _p(_NUM, "s", gt=0),
    "sample_rate": _p(_NUM, "Hz", 100.0, gt=0), "rtol": _p(_NUM, _DIMENSIONLESS, 1e-10, gt=0),
    "atol": _p(_NUM, "m, rad", None, gt=0),
    "ball_mass": _p(_NUM, "kg", 0.1, gt=0), "ball_radius": _p(_NUM, "m", 0.1, gt=0),
    "ball_drag": _p(_NUM, "N*s/m", 2.0, ge=0), "initial_angles_deg": _p(_LIST, "deg", [60.0, 250.0]),
    "max_rotation": _p(_NUM, "rad", 0.05, gt=0),
}
_QP = {
    "Rt": _p(_NUM, "dimensionless, R~_m", gt=0, lt=0.5), "h": _p(_NUM, "dimensionless ball drag", gt=0),
    "H": _p(_NUM, "dimensionless support damping", gt=0),
    "offset": _p(_NUM, "units of omega_1: R_omega = R*_omega + offset"),
    "duration_tau": _p(_NUM, "tau = s", gt=0), "separation": _p(_NUM, "rad", 1e-3, ge=0),
    "sample_rate": _p(_NUM, "samples per tau", 1.0, gt=0),
    "rtol": _p(_NUM, _DIMENSIONLESS, 1e-10, gt=0), "atol": _p(_NUM, "dimensionless state", None, gt=0),
    "method": _p(_STR, default="auto", choices=_METHODS),
}

#: kind -> (parameter spec, valid checks)
KINDS = {
    "dimensionless": (_DIMLESS, ("balanced", "locked", "energy", "jacobi", "reference")),
    "scene_file": (_SCENE_FILE, ("runup_closed_form", "closed_form", "reference")),
    "liquid_runup": (_LIQUID, ("runup_closed_form",)),
    "platform": (_PLATFORM, ("steady_response", "balanced")),
    "qp_threshold": (_QP, ("qp_persists", "escape")),
    "body_scene": (_BODY_SCENE, ("runup_closed_form", "steady_theory", "reference")),
}


class _Fields(Table):
    """A case table or its ``[case.params]``; messages name ``field <prefix><key>``."""

    def __init__(self, data: Any, table: str, prefix: str = ""):
        super().__init__(data, table)
        self.prefix = prefix

    def name(self, key: str) -> str:
        return f"field {self.prefix}{key}"

    def allow_fields(self, keys, what: str = "") -> None:
        """Reject every field not in ``keys`` (``what``: e.g. " for kind 'platform'")."""
        self.allow(keys, lambda k: (f"unknown field {self.prefix}{k}{what}: {_suggest(k, keys)}"
                                    f"valid: {', '.join(keys)}"))

    def boolean(self, key: str, default: bool) -> bool:
        value = self.data.get(key, default)
        if not isinstance(value, bool):
            raise SceneError(f"{self.name(key)} = {_fmt(value)}: must be true or false, "
                             f"not {_kind(value)}")
        return value

    def array(self, key: str, unit: str, default: Any) -> Any:
        value = self._get(key, default, unit)
        if key in self.data and not isinstance(value, list):
            raise SceneError(f"{self.name(key)} = {_fmt(value)}: must be an array ({unit}), "
                             f"not {_kind(value)}")
        return value

    def value(self, key: str, spec: Mapping) -> Any:
        """The field checked against its spec (:func:`_p`), or its default."""
        k, unit = spec["kind"], spec["unit"]
        given = {} if spec["default"] is _REQUIRED else {"default": spec["default"]}
        if k == _NUM:
            bounds = {b: spec[b] for b in ("gt", "ge", "lt") if spec[b] is not None}
            return self.number(key, unit or _DIMENSIONLESS, **given, **bounds)
        if k == _INT:
            return self.integer(key, minimum=spec["ge"] if spec["ge"] is not None else -2 ** 63,
                                **given)
        if k == _STR:
            return self.string(key, spec["choices"], **given)
        if k == _BOOL:
            return self.boolean(key, spec["default"])
        return self.array(key, unit, spec["default"])


def _case_where(i: int, name) -> str:
    """``case #<i + 1> '<name>'`` (the name only when it is a string)."""
    return f"case #{i + 1}" + (f" {name!r}" if isinstance(name, str) else "")


def _parse_case(i: int, raw, source: str) -> dict:
    if not isinstance(raw, Mapping):
        raise CatalogueError(f"{source}: case #{i + 1}: must be a table [[case]], not {_kind(raw)}")
    where = f"{source}: {_case_where(i, raw.get('name'))}"
    try:
        return _case(_Fields(raw, "case"), where)
    except SceneError as exc:
        raise CatalogueError(f"{where}: {exc}") from None


def _case(t: _Fields, where: str) -> dict:
    t.allow_fields(CASE_FIELDS)
    c = {"name": t.string("name")}
    if not c["name"].strip():
        raise CatalogueError(f"{where}: field name is empty")
    c["kind"] = t.string("kind", tuple(KINDS))
    spec, checks = KINDS[c["kind"]]
    c["check"] = t.string("check", checks)
    c["tolerance"] = t.number("tolerance", _DIMENSIONLESS, gt=0)
    c["time_budget_s"] = t.number("time_budget_s", "s", gt=0)
    c["description"] = t.string("description", default="")
    c["fast"] = t.boolean("fast", False)
    c["outside_validity"] = t.string("outside_validity", default=None)
    c["expect_method"] = t.string("expect_method", default=None)
    c["reference_rtol"] = t.number("reference_rtol", _DIMENSIONLESS, None, gt=0)
    c["convergence_tolerance"] = t.number("convergence_tolerance", _DIMENSIONLESS, 1e-3, gt=0)
    params = t.data.get("params", {})
    if not isinstance(params, Mapping):
        raise CatalogueError(f"{where}: field params must be a table [case.params], not "
                             f"{_kind(params)}")
    pt = _Fields(params, "case.params", "params.")
    pt.allow_fields(tuple(spec), f" for kind {c['kind']!r}")
    p = {key: pt.value(key, s) for key, s in spec.items()}
    _cross_check(where, c, p)
    c["params"] = p
    return c


def _cross_check(where: str, c: dict, p: dict) -> None:
    """Checks that involve several fields of a case."""
    if c["kind"] == "dimensionless":
        if (p["R"] is None) == (p["programme"] is None):
            raise CatalogueError(f"{where}: fields params.R and params.programme: give exactly one "
                                 "(constant speed R_omega, or [[tau, R_omega], ...])")
        if p["programme"] is not None:
            rows = p["programme"]
            ok = (len(rows) >= 1 and all(isinstance(r, list) and len(r) == 2 and all(
                isinstance(x, (int, float)) and not isinstance(x, bool) for x in r) for r in rows))
            if not ok or any(b[0] <= a[0] for a, b in zip(rows[:-1], rows[1:])):
                raise CatalogueError(f"{where}: field params.programme = {_fmt(rows)}: must be rows "
                                     "[tau, R_omega] with increasing tau")
        if p["initial_angles_deg"] is not None and len(p["initial_angles_deg"]) != p["n"]:
            raise CatalogueError(f"{where}: field params.initial_angles_deg has "
                                 f"{len(p['initial_angles_deg'])} entries, params.n = {p['n']}")
        if c["check"] in ("energy", "jacobi") and p["R"] is None:
            raise CatalogueError(f"{where}: field params.R: check {c['check']!r} needs a constant speed")
    if c["kind"] == "platform" and len(p["initial_angles_deg"]) != 2 and c["check"] == "balanced":
        raise CatalogueError(f"{where}: field params.initial_angles_deg: two balls, two angles")


def load_catalogue(path=DEFAULT_CATALOGUE) -> list:
    """Read and validate a catalogue file.

    Parameters
    ----------
    path : str or Path
        The catalogue (TOML, UTF-8): ``[[case]]`` tables and an optional
        ``[catalogue]`` table.

    Returns
    -------
    list of dict
        One dict per case, in file order: the fields of :data:`CASE_FIELDS`
        with their defaults filled in (``tolerance`` dimensionless,
        ``time_budget_s`` in s), ``params`` checked against the kind's spec in
        :data:`KINDS` (units as there), and ``_dir``, the catalogue's folder
        (relative scene paths are looked up there).

    Raises
    ------
    CatalogueError
        Unreadable file, TOML syntax error, or a malformed case: the message
        names the file, the case (number and name) and the field.
    """
    from stand.io.tomlfile import read_toml

    path = Path(path)
    data, _, _ = read_toml(path, "catalogue", CatalogueError)
    for key in data:
        if key not in ("case", "catalogue"):
            raise CatalogueError(f"{path}: unknown top-level key {key!r}: "
                                 f"{_suggest(key, ('case', 'catalogue'))}valid: [catalogue], [[case]]")
    raw = data.get("case")
    if not isinstance(raw, list) or not raw:
        raise CatalogueError(f"{path}: no [[case]] tables")
    cases = [_parse_case(i, r, str(path)) for i, r in enumerate(raw)]
    seen: dict = {}
    for i, c in enumerate(cases):
        if c["name"] in seen:
            raise CatalogueError(f"{path}: {_case_where(i, c['name'])}: field name duplicates "
                                 f"case #{seen[c['name']] + 1}")
        seen[c["name"]] = i
    for c in cases:
        c["_dir"] = str(path.resolve().parent)
    return cases


def select_cases(all_cases: list, cases, source) -> list:
    """The cases to run, in catalogue order.

    Parameters
    ----------
    all_cases : list of dict
        From :func:`load_catalogue`.
    cases : None, "fast", str or sequence of str
        All cases, the cases marked ``fast = true``, or these names.
    source : str or Path
        The catalogue, for messages.

    Raises
    ------
    CatalogueError
        An unknown name (the message suggests a close one).
    """
    if cases is None:
        return all_cases
    if isinstance(cases, str) and cases == "fast":
        return [c for c in all_cases if c["fast"]]
    if isinstance(cases, str):
        cases = [cases]
    names = {c["name"] for c in all_cases}
    for nm in cases:
        if nm not in names:
            raise CatalogueError(f"{source}: no case named {nm!r} ({_suggest(str(nm), names)}"
                                 f"cases: {', '.join(sorted(names))})")
    want = set(cases)
    return [c for c in all_cases if c["name"] in want]
