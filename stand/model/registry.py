"""Named kinds of the stand and where their code lives: ``"module:object"`` specs.

The rotor types of ``[structure]`` scenes (:data:`stand.scene.structure_tables.ROTOR_TYPES`)
and the book weight models of ``[weight_model]`` scenes
(:data:`stand.scene.book_tables.MODEL_TYPES`) map a name to ``(spec, source)``:
the builder or parameter class as ``"package.module:name"`` (imported only when a
scene uses it) and the book section it implements.
"""
from __future__ import annotations

import importlib

from stand.errors import SceneError

__all__ = ["resolve"]


def resolve(table: dict, kind: str, key: str, what: str = "type"):
    """The object registered as ``kind`` in ``table``, imported on demand.

    Raises
    ------
    SceneError
        ``kind`` is not in the table (the message lists the valid names and names
        ``key``, e.g. ``structure.type``), or its code is missing from this version.
    """
    if kind not in table:
        raise SceneError(f'{key} = "{kind}": unknown {what}; valid: {", ".join(table)}')
    spec = table[kind][0]
    module, _, name = spec.partition(":")
    try:
        return getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError):
        raise SceneError(f'{key} = "{kind}": this {what} is not available in this version '
                         f"({spec} missing)") from None
