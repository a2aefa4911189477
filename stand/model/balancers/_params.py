"""Input checks shared by the weight-family models (:mod:`stand.model.balancers`).

Every check converts the value to ``float``, rejects what is not a real
number or not finite, then tests an optional bound, and raises
:class:`ValueError` naming the parameter, the value as given and its unit.

The logic is one; the wording follows the source each module implements,
because users and tests match on it:

* :data:`BOOK` (the monograph's chapters 6-7: :mod:`.two_axis`,
  :mod:`.gravity_pair`, :mod:`.damper`)::

      c must be > 0 [N/m], got -1.0

* :data:`PAPER` (paper 001: :mod:`.liquid_float`, :mod:`.runup_closed_form`)::

      n = -1.0 [1/s]: must be >= 0

* :data:`THESIS` (thesis 002: :mod:`.liquid_chamber`)::

      m = -7.0 kg is invalid: must be > 0

Rules
-----
``"finite"`` (any finite real), ``"> 0"`` and ``">= 0"``.  Range conditions
that need an explanation (``R_m < 1``, ``psi`` in ``(0, 1]``, ...) stay in the
models; :meth:`Checker.error` builds their message in the same wording.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable

__all__ = ["Checker", "BOOK", "PAPER", "THESIS", "group"]

#: rule -> test on the converted value (True: valid)
_RULES = {
    "finite": lambda v: True,
    "> 0": lambda v: v > 0.0,
    ">= 0": lambda v: v >= 0.0,
}


@dataclass(frozen=True)
class Checker:
    """Validator with one message wording.

    Parameters
    ----------
    template : str
        Message with the fields ``{name}``, ``{value!r}`` (the value as
        given), ``{unit}`` and ``{rule}`` (what the value must be, e.g.
        ``"> 0"``, ``"finite"``, ``"a real number"``).
    """

    template: str

    def error(self, name: str, value, unit: str, rule: str) -> ValueError:
        """The :class:`ValueError` saying that ``name`` = ``value`` [``unit``] must be ``rule``."""
        return ValueError(self.template.format(name=name, value=value, unit=unit, rule=rule))

    def __call__(self, name: str, value, unit: str, rule: str = "finite") -> float:
        """``value`` as a float, checked against ``rule``.

        Parameters
        ----------
        name : str
            Parameter name used in the message.
        value : object
            Value to check (anything ``float`` accepts).
        unit : str
            Unit used in the message (``"-"`` or ``"dimensionless"`` for none).
        rule : {"finite", "> 0", ">= 0"}
            Bound to test after finiteness.

        Returns
        -------
        float

        Raises
        ------
        ValueError
            Not a real number, not finite, or outside ``rule``.
        """
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise self.error(name, value, unit, "a real number") from None
        if not math.isfinite(v):
            raise self.error(name, value, unit, "finite")
        if not _RULES[rule](v):
            raise self.error(name, value, unit, rule)
        return v

    def finite(self, name: str, value, unit: str) -> float:
        """Finite real number [``unit``]."""
        return self(name, value, unit, "finite")

    def positive(self, name: str, value, unit: str) -> float:
        """Finite and ``> 0`` [``unit``]."""
        return self(name, value, unit, "> 0")

    def nonneg(self, name: str, value, unit: str) -> float:
        """Finite and ``>= 0`` [``unit``]."""
        return self(name, value, unit, ">= 0")

    def each(self, *specs) -> list:
        """Check several arguments in order; ``specs`` are ``(name, value, unit, rule)``.

        Returns
        -------
        list of float
            The converted values, in the order given.
        """
        return [self(name, value, unit, rule) for name, value, unit, rule in specs]

    def fields(self, obj, *specs) -> None:
        """Check attributes of a (frozen) dataclass and store them as floats.

        Parameters
        ----------
        obj : dataclass instance
            Typically ``self`` in ``__post_init__``.
        *specs : tuple
            ``(name, unit, rule)`` for each attribute, checked in order
            (see :func:`group` for several names with one unit and rule).
        """
        for name, unit, rule in specs:
            object.__setattr__(obj, name, self(name, getattr(obj, name), unit, rule))


def group(names: Iterable[str], unit: str, rule: str = "finite") -> tuple:
    """``(name, unit, rule)`` specs for :meth:`Checker.fields`, one per name."""
    return tuple((name, unit, rule) for name in names)


#: the monograph's models (chapters 6-7)
BOOK = Checker("{name} must be {rule} [{unit}], got {value!r}")
#: paper 001 (liquid float balancer)
PAPER = Checker("{name} = {value!r} [{unit}]: must be {rule}")
#: thesis 002 (liquid chamber balancer)
THESIS = Checker("{name} = {value!r} {unit} is invalid: must be {rule}")
