"""Theory against experiment (stub)."""
from __future__ import annotations


def comparison(obj, theta, unc, rec, fitted, series, progress=None) -> list:
    return []
