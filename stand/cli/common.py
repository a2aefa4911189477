"""What the commands share: JSON output, "not applicable" lines, and one way to
print a value: its human label (:mod:`stand.io.labels`) and its ± rounded to it in the label's
unit (:func:`stand.io.numbers.with_uncertainty`) (stand.cli)."""
from __future__ import annotations

import sys

__all__ = ["print_json", "say_not_applicable", "print_recognised", "shown", "labelled",
           "print_warnings"]


def print_json(doc) -> None:
    """``--json``: the document on stdout (one JSON converter, strict JSON)."""
    from stand.io.jsonable import dumps

    print(dumps(doc, indent=2))


def say_not_applicable(command: str, why: str) -> int:
    """A command that does not apply to a scene says so and why, and succeeds."""
    print(f"stand {command}: not applicable: {why}")
    return 0


def print_recognised(doc) -> None:
    """A table read without a map: which column was taken for what (stderr)."""
    inp = doc.get("input") or {}
    if inp.get("recognised"):
        print("columns recognised (give --columns or --map to choose): "
              + "; ".join(inp["recognised"]), file=sys.stderr)
    for e in inp.get("excluded") or []:
        print(f"excluded rows {e['rows']}: {e['reason']}", file=sys.stderr)


def shown(doc, key: str, *, angle: bool = False, std_key: str = ""):
    """``doc[key]`` with its ± (``doc[key + "_std"]``) in the display unit of
    :mod:`stand.io.labels`, rounded to the ±; None when the document does not give the value.
    ``angle``: an angle is never "below resolution" (its size means nothing)."""
    from stand.io.labels import unit
    from stand.io.numbers import with_uncertainty

    v = doc.get(key)
    if v is None:
        return None
    u, factor = unit(key)
    sd = doc.get(std_key or f"{key}_std")
    if isinstance(v, (bool, str)):
        return str(v)
    return with_uncertainty(v * factor, None if sd is None else sd * factor, u,
                            resolution=not angle)


def labelled(doc, key: str, *, angle: bool = False, std_key: str = ""):
    """``Label: value ± u unit`` (:func:`shown`), or None when the document does not give it."""
    from stand.io.labels import label

    text = shown(doc, key, angle=angle, std_key=std_key)
    return None if text is None else f"{label(key)}: {text}"


def print_warnings(command: str, warnings) -> None:
    """Each warning on its own line (stderr), by its message: ``stand report: warning: ...``."""
    for w in warnings or ():
        text = w.get("message") or w.get("code") if isinstance(w, dict) else w
        print(f"stand {command}: warning: {text}", file=sys.stderr)
