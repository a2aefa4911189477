"""Numbers as a report shows them: rounded to their uncertainty, or to a sensible precision.

* :func:`with_uncertainty` -- ``value ± uncertainty`` with the uncertainty
  rounded to two significant digits and the value to the same decimal place
  (the last digit shown is the same in both, GUM 7.2.6); a value smaller than
  its own uncertainty is shown as "below resolution (< u)".  Values of 10⁻³ .. 10⁶
  (as :func:`plain`) are written out however many decimals the uncertainty needs
  (``4.7750434 ± 0.0000078``); very large or small numbers share one power of ten:
  ``(8.1 ± 1.9) × 10⁻⁶`` (smaller ones written out while their last digit is 10⁻⁶
  or above: ``0.000500 ± 0.000020``).  An uncertainty below 1e-9 of its value is
  round-off, not a measurement's: the value alone, as :func:`plain`.
* :func:`resolved` -- whether a value stands above its uncertainty (an angle of a value
  that does not means nothing and is not shown);
* :func:`plain` -- a value without an uncertainty, to 4 significant digits
  without trailing zeros (integers as they are), with a power of ten outside
  10⁻³ .. 10⁶.
"""
from __future__ import annotations

import math

__all__ = ["with_uncertainty", "plain", "resolved", "SUPERSCRIPT"]

SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _pow10(e: int) -> str:
    return f"10{str(e).translate(SUPERSCRIPT)}"


def _join(text: str, unit: str) -> str:
    return f"{text} {unit}".rstrip() if unit else text


def plain(v, unit: str = "", sig: int = 4) -> str:
    """A number without uncertainty (``sig`` significant digits) with its unit."""
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return _join(f"{v:d}", unit)
    v = float(v)
    if not math.isfinite(v):
        return _join(str(v), unit)
    if v == 0:
        return _join("0", unit)
    e = math.floor(math.log10(abs(v)))
    if -3 <= e < 6:
        decimals = max(sig - 1 - e, 0)
        text = f"{v:.{decimals}f}"
        if "." in text:     # no uncertainty: trailing zeros would claim a precision
            text = text.rstrip("0").rstrip(".")
        return _join(text, unit)
    m = v / 10 ** e
    if abs(round(m, sig - 1)) >= 10:
        m, e = m / 10, e + 1
    text = f"{m:.{sig - 1}f}".rstrip("0").rstrip(".")
    return _join(f"{text} × {_pow10(e)}", unit)


def _rounded_u(u: float) -> tuple:
    """(last decimal place shown, u rounded to two significant digits, a float: an int
    would be printed digit by digit by :func:`plain`)."""
    place = math.floor(math.log10(u)) - 1          # last digit: two significant digits of u
    if round(u / 10 ** place) >= 100:              # 99.5 -> 100: one more digit left
        place += 1
    return place, float(round(u / 10 ** place) * 10 ** place)


def _noise(v, u) -> bool:
    """No uncertainty to show: missing, zero, not finite, or below 1e-9 of ``v`` (round-off)."""
    return u is None or not math.isfinite(float(u)) or float(u) <= 0 \
        or float(u) < 1e-9 * abs(float(v))


def resolved(v, u) -> bool:
    """Whether ``v`` is at least its uncertainty ``u`` as shown (two significant digits):
    False is what :func:`with_uncertainty` shows as "below resolution"; True without a
    ``u`` to show.  A None value is not resolved."""
    if v is None:
        return False
    return _noise(v, u) or abs(float(v)) >= _rounded_u(float(u))[1]


def with_uncertainty(v, u, unit: str = "", resolution: bool = True) -> str:
    """``v ± u`` rounded to the uncertainty (module docstring); ``plain(v)`` when ``u`` is
    missing, zero, not finite, or below 1e-9 of ``v`` (floating-point noise).
    ``resolution=False``: a value whose size means nothing (an angle) is never "below
    resolution"."""
    if v is None:
        return "—"
    if _noise(v, u):          # rounding noise, not a measurement's
        return plain(v, unit)
    v, u = float(v), float(u)
    place, u_r = _rounded_u(u)
    if resolution and abs(v) < u_r:
        return f"below resolution (< {plain(u_r, unit, sig=2)})"
    v_r = round(v / 10 ** place) * 10 ** place
    big = max(abs(v_r), u_r)
    e = math.floor(math.log10(big))
    if e < 6 and (e >= -3 or place >= -6):    # plain's range, or few decimals: never × 10⁰
        d = max(-place, 0)
        return _join(f"{v_r:.{d}f} ± {u_r:.{d}f}", unit)
    d = max(e - place, 0)
    return _join(f"({v_r / 10 ** e:.{d}f} ± {u_r / 10 ** e:.{d}f}) × {_pow10(e)}", unit)
