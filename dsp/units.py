"""Unit-conversion properties of the result dataclasses of ``dsp``.

Results store SI values (kg m, rad); the usual lab units (g mm, degrees) are
read-only properties derived from them, made by :func:`converted`.
"""
from __future__ import annotations

import math

__all__ = ["converted", "GMM_PER_KG_M", "DEG_PER_RAD"]

GMM_PER_KG_M = 1e6               #: 1 kg m = 1e6 g mm
DEG_PER_RAD = 180.0 / math.pi


def converted(attr: str, factor: float, doc: str) -> property:
    """Read-only property: the attribute ``attr`` multiplied by ``factor``.

    Parameters
    ----------
    attr : str
        Name of the stored attribute (SI unit).
    factor : float
        Conversion factor to the property's unit (e.g. :data:`GMM_PER_KG_M`).
    doc : str
        Docstring of the property, with its unit.
    """
    return property(lambda self: getattr(self, attr) * factor, doc=doc)
