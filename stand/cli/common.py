"""What the commands share: JSON output, "not applicable" lines, CSV tables (stand.cli)."""
from __future__ import annotations

import sys

__all__ = ["print_json", "say_not_applicable", "write_csv", "print_recognised"]


def print_json(doc) -> None:
    """``--json``: the document on stdout (one JSON converter, strict JSON)."""
    from stand.io.jsonable import dumps

    print(dumps(doc, indent=2))


def say_not_applicable(command: str, why: str) -> int:
    """A command that does not apply to a scene says so and why, and succeeds."""
    print(f"stand {command}: not applicable: {why}")
    return 0


def write_csv(df, path) -> None:
    from stand.io.atomic import atomic_path

    with atomic_path(path, suffix=".csv.tmp") as tmp:
        df.to_csv(tmp, index=False)


def print_recognised(doc) -> None:
    """A table read without a map: which column was taken for what (stderr)."""
    inp = doc.get("input") or {}
    if inp.get("recognised"):
        print("columns recognised (give --columns or --map to choose): "
              + "; ".join(inp["recognised"]), file=sys.stderr)
    for e in inp.get("excluded") or []:
        print(f"excluded rows {e['rows']}: {e['reason']}", file=sys.stderr)
