"""A saved influence file (``stand balance --save-influence``) and its reuse (``--influence``).

The file holds each speed's ``[[influence]]`` table (coefficients with the std of each of Re and
Im and the job that measured them) and, as ``[[measured_run]]`` tables, that job's reference and
trial runs as they were written.  The runs keep what a table of coefficients loses: in the
measuring job the reference reading enters both the coefficients ``A = (V_trial - V_ref) / T``
and the vibration to cancel, a correlation of the coefficients' errors with the reference's.
A next machine's reference does not share it, and the coefficients with their ± are the right
input (:func:`stand.analysis.field_job.parse_job`); but a one-shot job whose reference *is* the
measuring job's (the same readings, written the same way, in the same units) is that job, and
:func:`linked_runs` gives it back its trial runs, so that it gets the measuring job's answer and
± -- not a smaller one from treating correlated errors as independent.
"""
from __future__ import annotations

import json

__all__ = ["influence_toml", "linked_runs"]

_UNITS = {"vibration_unit": "um", "amplitude": "pk", "mass_unit": "g"}   # field_job defaults
_KEPT = ("reference", "trial")          # the runs that measured the influence


def _inline(v) -> str:
    """A TOML inline value of a run table's value (strings, numbers, booleans, tables, lists)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{json.dumps(str(k))} = {_inline(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_inline(x) for x in v) + "]"
    if isinstance(v, (int, float)):
        return repr(v)
    return json.dumps(str(v))


def influence_toml(res, runs=None) -> str:
    """The result's influence matrix as a job file's ``[[influence]]`` tables (with its
    ``[job]`` units, each coefficient's ``std`` (each of Re and Im) and the job that measured
    it), for ``--influence FILE`` on the next machine of the type.

    Parameters
    ----------
    res : FieldBalance
        The measuring job's answer.
    runs : list of dict, optional
        The measuring job's ``[[run]]`` tables as written; its reference and trial runs are
        kept as ``[[measured_run]]`` (see the module docstring).
    """
    lines = ["# influence coefficients saved by stand balance --save-influence",
             "# std: standard uncertainty of each of Re and Im of a coefficient (its unit)",
             "[job]", f'vibration_unit = "{res["vibration_unit"]}"',
             f'amplitude = "{res["amplitude"]}"', f'mass_unit = "{res["mass_unit"]}"', ""]
    speeds = []
    for e in res["influence"]:
        if e["speed_rpm"] not in speeds:
            speeds.append(e["speed_rpm"])
    for sp in speeds:
        lines.append("[[influence]]")
        if sp is not None:
            lines.append(f'speed = "{sp:.10g} rpm"')
        lines.append(f'measured_by = {json.dumps(res["influence_measured_by"])}')
        rows, std = {}, {}
        for e in res["influence"]:
            if e["speed_rpm"] == sp:
                rows.setdefault(e["sensor"], []).append(
                    f'"{e["plane"]}" = "{e["amplitude"]:.10g} @ {e["angle_deg"]:.10g}"')
                std.setdefault(e["sensor"], []).append(f'"{e["plane"]}" = {e["std"]:.4g}')
        for s, cells in rows.items():
            lines.append(f'"{s}" = {{ {", ".join(cells)} }}')
        lines.append("std = { " + ", ".join(f'"{s}" = {{ {", ".join(c)} }}'
                                             for s, c in std.items()) + " }")
        lines.append("")
    kept = [r for r in runs or () if isinstance(r, dict) and r.get("kind") in _KEPT
            and "readings" in r and "recording" not in r]
    if kept:
        lines.append("# the runs that measured it (a one-shot job on the same reference readings "
                     "is that job)")
    for r in kept:
        lines.append("[[measured_run]]")
        lines += [f"{k} = {_inline(v)}" for k, v in r.items()]
        lines.append("")
    return "\n".join(lines)


def linked_runs(doc: dict, influence_doc: dict):
    """The job's runs completed with the influence file's trial runs when the job is a one-shot
    job on the measuring job's own reference run (only reference runs, each equal -- speed and
    readings as written -- to a saved reference run, in the same units); else None."""
    saved = influence_doc.get("measured_run")
    runs = doc.get("run")
    if not isinstance(saved, list) or not isinstance(runs, list) or not runs:
        return None
    job, own = doc.get("job", {}), influence_doc.get("job", {})
    if not isinstance(job, dict) or not isinstance(own, dict) \
            or any(job.get(k, d) != own.get(k, d) for k, d in _UNITS.items()):
        return None
    refs = [r for r in saved if isinstance(r, dict) and r.get("kind") == "reference"]
    key = (lambda r: (r.get("speed"), r.get("readings")))
    if not all(isinstance(r, dict) and r.get("kind") == "reference"
               and any(key(r) == key(s) for s in refs) for r in runs):
        return None
    if len(runs) != len(refs):
        return None
    return list(runs) + [r for r in saved if isinstance(r, dict) and r.get("kind") == "trial"]
