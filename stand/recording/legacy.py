"""Recordings written before the one layout (rotor-family and weight-model files).

:func:`legacy_layout` recognises them by their ``format`` attribute and maps
their datasets to the fields of :class:`stand.recording.read.Recording`, with a note.
Format-version-1 files of the planar stand need no mapping (their
``shaft/x|y`` and ``weights/angle`` matrices are read directly).
"""
from __future__ import annotations

import json

import h5py
import numpy as np

__all__ = ["legacy_layout", "FAMILY_FORMAT", "WEIGHT_MODEL_FORMAT"]

FAMILY_FORMAT = "autobalancer-stand rotor-family recording 1"
WEIGHT_MODEL_FORMAT = "autobalancer-stand weight-model recording 1"


def legacy_layout(f: "h5py.Group", attrs: dict, label: str, notes: list):
    """``None`` for this version's files, else ``{"planes", "main", "coordinates", "truth"}``."""
    fmt = attrs.get("format")
    if not isinstance(fmt, str):
        return None
    if fmt == FAMILY_FORMAT:
        notes.append(f"{FAMILY_FORMAT!r}: a rotor-family file written before the one layout; "
                     "read through shaft/x|y, planes/<plane> (N, 2) and weights/relative_angle")
        planes = {p: np.asarray(d[()], float) for p, d in f["planes"].items()
                  if isinstance(d, h5py.Dataset) and d.ndim == 2 and d.shape[1] == 2} \
            if isinstance(f.get("planes"), h5py.Group) else {}
        coords = {}
        q = f.get("structure/q")
        if isinstance(q, h5py.Dataset) and q.ndim == 2:
            try:
                names = json.loads(q.attrs.get("coords", "[]"))
            except (TypeError, ValueError):
                names = []
            for i in range(q.shape[1]):
                name, _, unit = (names[i] if i < len(names) else f"q{i}").partition(" [")
                coords[f"structure/{name}"] = (np.asarray(q[:, i], float), unit.rstrip("]") or "1")
        main = next((p for p, xy in planes.items()
                     if "shaft/x" in f and np.array_equal(xy[:, 0], f["shaft/x"][()])), None)
        return {"planes": planes, "main": main, "coordinates": coords, "truth": {}}
    if fmt == WEIGHT_MODEL_FORMAT:
        notes.append(f"{WEIGHT_MODEL_FORMAT!r}: a book weight-model file written before the one "
                     "layout (a state matrix); the shaft is read from its x, y columns, "
                     "in the model's units")
        st = f.get("state")
        try:
            cols = json.loads(st.attrs.get("columns", "[]"))
        except (AttributeError, TypeError, ValueError):
            cols = []
        names = [c.split(" [")[0] for c in cols]
        planes, coords = {}, {}
        if isinstance(st, h5py.Dataset) and st.ndim == 2:
            a = np.asarray(st[()], float)
            for key in (("x", "y"), ("xi", "eta")):
                if all(k in names for k in key):
                    planes["balancer"] = a[:, [names.index(k) for k in key]]
            for i, c in enumerate(cols[:a.shape[1]]):
                name, _, unit = c.partition(" [")
                coords[f"state/{name}"] = (a[:, i], unit.rstrip("]") or "1")
        return {"planes": planes, "main": "balancer" if planes else None,
                "coordinates": coords, "truth": {}}
    return None
