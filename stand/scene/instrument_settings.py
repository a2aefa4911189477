"""Settings of the virtual instruments: one validator for the dataclasses and their TOML tables.

The instruments' settings readers (the settings are scene data).  Each settings dataclass
(:class:`~stand.scene.screen_camera.ScreenCamera`,
:class:`~stand.scene.strobe_settings.Stroboscope`,
:class:`~stand.scene.gate_settings.PhotoGate`,
:class:`~stand.scene.probe_settings.Keyphasor`,
:class:`~stand.scene.probe_settings.Tachometer`,
:class:`~stand.scene.probe_settings.DisplacementProbes`) declares every checked
field once, with :func:`number`, :func:`integer`, :func:`boolean`,
:func:`choice` or :func:`numbers`; the unit, the bounds and the unit of the
TOML file travel in the field's metadata.  Then

* :func:`check` validates the attributes in ``__post_init__`` and stores them
  normalised (``float``, ``int``, ``bool``, a tuple of ``float``);
* :func:`read_table` reads the same fields from an ``[instruments.<name>]``
  table (:class:`stand.scene.parse.Table`), each in its TOML unit (e.g. degrees
  for an angle kept in radians);
* :func:`rebased` constructs the dataclass so that the messages of its own
  checks name the table's dotted path.

Every problem raises :class:`stand.scene.model.SceneError` (a ``ValueError``) whose
message names the field (dotted path), the value and the unit, e.g.
``instruments.stroboscope.slot_width = -0.002: must be > 0 (m)``.
"""
from __future__ import annotations

import dataclasses
from dataclasses import MISSING, dataclass
from typing import Callable, Iterable, Optional

import numpy as np

from stand.errors import SceneError

__all__ = ["REQUIRED", "number", "integer", "boolean", "choice", "numbers", "keys", "check",
           "read_table", "rebased", "check_number", "check_integer", "table_boolean",
           "table_numbers"]

REQUIRED = MISSING       #: default of a field that must be given
_KEY = "stand.scene.instrument_setting"   #: metadata key of the field's specification


# ---------------------------------------------------------------- single values
def check_number(name: str, value, unit: str, *, gt=None, ge=None, lt=None, le=None,
                 optional: bool = False) -> Optional[float]:
    """One finite number within bounds, as ``float`` (``None`` passes when ``optional``).

    Parameters
    ----------
    name : str
        Dotted name for the message, e.g. ``instruments.probes.lsb``.
    value : object
        The value to check.
    unit : str
        Unit quoted in the message, e.g. ``"m"``.
    gt, ge, lt, le : float, optional
        Bounds: value > gt, >= ge, < lt, <= le.

    Raises
    ------
    SceneError
        ``"<name> = <value>: must be a number (<unit>)"``, ``... must be finite``,
        ``... must be > <bound>`` (or >=, <, <=).
    """
    if value is None and optional:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.number)):
        raise SceneError(f"{name} = {value!r}: must be a number ({unit})")
    v = float(value)
    if not np.isfinite(v):
        raise SceneError(f"{name} = {value!r}: must be finite ({unit})")
    for bound, ok, sign in ((gt, lambda: v > gt, ">"), (ge, lambda: v >= ge, ">="),
                            (lt, lambda: v < lt, "<"), (le, lambda: v <= le, "<=")):
        if bound is not None and not ok():
            raise SceneError(f"{name} = {value!r}: must be {sign} {bound:g} ({unit})")
    return v


def check_integer(name: str, value, minimum: int, maximum: Optional[int] = None,
                  optional: bool = False) -> Optional[int]:
    """One integer in ``minimum..maximum``, as ``int`` (``None`` passes when ``optional``).

    Raises
    ------
    SceneError
        ``"<name> = <value>: must be an integer"``, ``... must be >= <minimum>``
        or ``... must be in <minimum>..<maximum>``.
    """
    if value is None and optional:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise SceneError(f"{name} = {value!r}: must be an integer")
    if value < minimum or (maximum is not None and value > maximum):
        rng = f">= {minimum}" if maximum is None else f"in {minimum}..{maximum}"
        raise SceneError(f"{name} = {value!r}: must be {rng}")
    return int(value)


def _check_boolean(name: str, value) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise SceneError(f"{name} = {value!r}: must be true or false")
    return bool(value)


# ---------------------------------------------------------------- field declarations
@dataclass(frozen=True)
class _Spec:
    """How to check a field's value (``check(name, value)`` -> normalised value) and
    read it from a TOML table (``read(t, key)``; None: the caller reads it)."""

    check: Callable
    read: Optional[Callable]


def _field(default, check, read=None):
    return dataclasses.field(default=default, metadata={_KEY: _Spec(check, read)})


def number(default, unit: str, *, gt=None, ge=None, lt=None, optional: bool = False,
           toml: Optional[tuple] = None):
    """A number field [``unit``].

    Parameters
    ----------
    default : float, None or REQUIRED
    unit : str
        Unit of the attribute (SI, angles in rad).
    gt, ge, lt : float, optional
        Bounds, applied to the attribute and to the TOML value.
    optional : bool
        ``None`` is a valid value.
    toml : (str, float), optional
        Unit of the TOML value and the factor to the attribute's unit, e.g.
        ``("deg", pi / 180)``; only bounds at 0 survive the scaling.
    """
    bounds = {k: b for k, b in (("gt", gt), ("ge", ge), ("lt", lt)) if b is not None}
    toml_unit, scale = toml if toml is not None else (unit, 1.0)
    if scale != 1.0 and any(b != 0 for b in bounds.values()):
        raise ValueError(f"number({unit!r}): scaled TOML values take only bounds at 0")
    return _field(default,
                  lambda name, v: check_number(name, v, unit, optional=optional, **bounds),
                  lambda t, key: t.number(key, toml_unit, **bounds) * scale)


def integer(default, minimum: int, maximum: Optional[int] = None, *, optional: bool = False):
    """An integer field in ``minimum..maximum``."""
    return _field(default,
                  lambda name, v: check_integer(name, v, minimum, maximum, optional),
                  lambda t, key: t.integer(key, minimum, maximum=maximum))


def boolean(default: bool):
    """A true/false field."""
    return _field(default, _check_boolean, lambda t, key: table_boolean(t, key, None))


def choice(default: str, options: tuple):
    """A string field, one of ``options``."""
    def check_choice(name, value):
        if value not in options:
            raise SceneError(f"{name} = {value!r}: must be one of "
                             + ", ".join(f'"{a}"' for a in options))
        return value

    return _field(default, check_choice, lambda t, key: t.string(key, options))


def numbers(default, unit: str, *, ge=None, optional: bool = False):
    """A non-empty list of numbers [``unit``], stored as a tuple.

    Read from TOML by the caller (:func:`table_numbers`): the lists of an
    instrument have forms of their own (a number for a one-element list, a
    length fixed by another list).
    """
    def check_numbers(name, values):
        if values is None and optional:
            return None
        if not isinstance(values, (tuple, list)) or not values:
            raise SceneError(f"{name} = {values!r}: must be a non-empty list ({unit})")
        return tuple(check_number(f"{name}[{i}]", v, unit, ge=ge) for i, v in enumerate(values))

    return _field(default, check_numbers)


def _specs(cls) -> dict:
    return {f.name: f.metadata[_KEY] for f in dataclasses.fields(cls) if _KEY in f.metadata}


def keys(cls) -> tuple:
    """The declared fields of a settings class, in order: the keys of its TOML table."""
    return tuple(_specs(cls))


# ---------------------------------------------------------------- the validator
def check(obj, path: str, names: Optional[Iterable[str]] = None) -> None:
    """Validate the declared fields of a settings dataclass and store them normalised.

    Parameters
    ----------
    obj : dataclass instance (frozen or not)
    path : str
        Dotted name of the settings table, e.g. ``"instruments.stroboscope"``.
    names : iterable of str, optional
        The fields to check, in this order; default all declared fields in
        declaration order.

    Raises
    ------
    SceneError
        The first invalid field: ``"<path>.<field> = <value>: must be ... (<unit>)"``.
    """
    specs = _specs(type(obj))
    for name in (specs if names is None else names):
        value = specs[name].check(f"{path}.{name}", getattr(obj, name))
        object.__setattr__(obj, name, value)


def read_table(t, cls) -> dict:
    """Keyword arguments of ``cls`` from a TOML table (:class:`stand.scene.parse.Table`).

    Every declared field present in the table is read in its TOML unit and
    converted (a required field must be present); absent ones are left to the
    dataclass defaults.  Lists (:func:`numbers`) are left to the caller.
    Messages are those of the ``Table`` getters: dotted key, value, TOML unit.
    """
    kw = {}
    for f in dataclasses.fields(cls):
        spec = f.metadata.get(_KEY)
        if spec is None or spec.read is None:
            continue
        required = f.default is MISSING and f.default_factory is MISSING
        if f.name in t or required:
            kw[f.name] = spec.read(t, f.name)
    return kw


def rebased(cls, kwargs: dict, default_path: str, path: str):
    """Construct ``cls(**kwargs)``; messages of its own checks name ``path``.

    ``cls`` checks its fields under ``default_path`` (e.g.
    ``instruments.keyphasor``); a table read from elsewhere has another dotted
    path, which the message then names instead.
    """
    try:
        return cls(**kwargs)
    except SceneError as exc:
        msg = str(exc)
        if path != default_path:
            msg = msg.replace(default_path + ".", path + ".")
        raise SceneError(msg) from None


# ---------------------------------------------------------------- TOML values
# The public :class:`stand.scene.parse.Table` has no boolean or variable-length list getter.
def table_boolean(t, key: str, default: Optional[bool]) -> Optional[bool]:
    """``t[key]`` as ``bool`` (``default`` when absent); must be true or false."""
    if key not in t:
        return default
    return _check_boolean(t.name(key), t.data[key])


def table_numbers(t, key: str, unit: str, default, *, length: Optional[int] = None,
                  ge: Optional[float] = None, gt: Optional[float] = None) -> Optional[list]:
    """``t[key]`` as a list of finite numbers [``unit``] (``default`` when absent).

    Optionally of a given ``length`` and bounded below (``ge``, ``gt``).
    """
    if key not in t:
        return default
    value = t.data[key]
    name = t.name(key)
    if not isinstance(value, (list, tuple)):
        raise SceneError(f"{name} = {value!r}: must be a list of numbers ({unit})")
    if length is not None and len(value) != length:
        raise SceneError(f"{name} = {value!r}: expected {length} numbers ({unit}), "
                         f"got {len(value)}")
    return [check_number(f"{name}[{i}]", v, unit, ge=ge, gt=gt) for i, v in enumerate(value)]
