"""Conditioning limits of a scene's linear structure, checked once at load (issue 34).

A scene may hold valid numbers one by one and still describe a structure no
computation can resolve: a rotor of 1e30 kg with a transverse moment of
1e-30 kg m^2 has a tilt mode that decays in 1e-31 s beside a translation mode of
a period of 1e5 years.  The integrator's step, the theory's speed scans and the
criterion's eigenvalues then drown in round-off (``stand theory`` bisected the
noise for ever).  Every command loads its scene through :func:`stand.scene.parse.parse`,
which runs :func:`check_conditioning`, so every command accepts or refuses such a
scene alike, in one line naming the keys, their values and the limit.

The measures are independent of the coordinates' units (m or rad): with
``S = diag(M)^(-1/2)`` (each coordinate scaled by its own mass),

* rates [1/s]: ``sqrt(max |S K S|)`` (the fastest uncoupled natural frequency),
  ``max |S D S|`` (damping rate) and ``top speed * max |S G S|`` (gyroscopic rate)
  are at most :data:`MAX_RATE`;
* ``cond(S M S)`` (a mass matrix near singular through its couplings) is at
  most :data:`MAX_MASS_CONDITION`;
* the coordinates' own natural frequencies ``sqrt(K_ii / M_ii)`` (those of
  supported coordinates, K_ii > 0) span at most :data:`MAX_RATE_SPREAD`: beyond it
  the responses of the light and stiff coordinates and those of the heavy and soft
  ones differ by more than the digits of a float (their squares enter the
  dynamic stiffness K - w^2 M side by side), and the criterion's eigenvalues are
  signs of round-off.

Real machines lie far inside: a CD-drive rotor (15 g, A ~ 1e-5 kg m^2, stiff
bearings) has rates below 1e5 1/s, a turbine (1e5 kg) on its foundation rates of
1e0-1e4 1/s; a finely meshed flexible shaft reaches 1e5-1e6 1/s with its
frequencies within a factor 1e4; a soft suspension (0.1 Hz) under stiff bearings
(10 kHz) spans 1e5.
"""
from __future__ import annotations

import re

import numpy as np

from stand.errors import SceneError

__all__ = ["MAX_RATE", "MAX_MASS_CONDITION", "MAX_RATE_SPREAD", "check_conditioning",
           "conditioning"]

MAX_RATE = 1e8             #: fastest natural frequency / damping / gyroscopic rate accepted [1/s]
MAX_MASS_CONDITION = 1e10  #: largest condition number of the unit-free mass matrix S M S
MAX_RATE_SPREAD = 1e7      #: largest ratio of the coordinates' own natural frequencies

#: the planar scene's keys that make its structure, with their units
_PLANAR_KEYS = {"rotor.mass": "kg", "supports.stiffness_x": "N/m", "supports.stiffness_y": "N/m",
                "supports.damping_x": "N s/m", "supports.damping_y": "N s/m"}


def conditioning(rotor, top_speed: float = 0.0) -> dict:
    """The conditioning measures of a :class:`~stand.model.rotors.structure.LinearRotor`
    (module docstring): ``{name: value}`` for ``rate_K``, ``rate_D``, ``rate_G`` [1/s],
    ``mass_condition`` and ``rate_spread`` (1); empty when the mass matrix has a
    non-positive diagonal entry (the builders refuse such structures themselves)."""
    d = np.diag(rotor.M)
    if d.size == 0 or not np.all(d > 0):
        return {}
    s = 1.0 / np.sqrt(d)
    scaled = lambda A: s[:, None] * A * s[None, :]   # noqa: E731
    with np.errstate(all="ignore"):
        out = {"rate_K": float(np.sqrt(np.max(np.abs(scaled(rotor.K))))),
               "rate_D": float(np.max(np.abs(scaled(rotor.D)))),
               "rate_G": float(abs(top_speed) * np.max(np.abs(scaled(rotor.G)))),
               "mass_condition": float(np.linalg.cond(scaled(rotor.M)))}
        own = np.sqrt(np.abs(np.diag(rotor.K)) / d)        # each coordinate's own frequency
        own = own[own > 0]
        out["rate_spread"] = float(own.max() / own.min()) if own.size else 1.0
    return out


_LIMITS = (("rate_K", MAX_RATE, "the fastest natural frequency sqrt(K/M) is {v:.3g} rad/s, "
            "above the limit {lim:.0e} rad/s (no time step resolves it)"),
           ("rate_D", MAX_RATE, "the fastest damping rate D/M is {v:.3g} 1/s, above the limit "
            "{lim:.0e} 1/s (no time step resolves it)"),
           ("rate_G", MAX_RATE, "the gyroscopic rate (top speed) G/M is {v:.3g} rad/s, above the "
            "limit {lim:.0e} rad/s (no time step resolves it)"),
           ("mass_condition", MAX_MASS_CONDITION, "the mass matrix's condition number (each "
            "coordinate scaled by its own mass) is {v:.3g}, above the limit {lim:.0e}"),
           ("rate_spread", MAX_RATE_SPREAD, "the coordinates' own natural frequencies "
            "sqrt(K_ii/M_ii) span a factor {v:.3g}, above the limit {lim:.0e}: the responses "
            "of the soft coordinates are lost in the round-off of the stiff ones"))


def _unit(fn, key: str) -> str:
    """The unit of ``key`` from its builder's docstring (``name ... [unit]``), else "SI"."""
    doc = fn.__doc__ or ""
    m = re.search(rf"(?<![\w.]){re.escape(key)}\b[^\n\[]*\[([^\]\n]+)\]", doc)
    return m.group(1) if m else "SI"


def _involved(build, params: dict, measure: str, top: float) -> list:
    """The keys of ``params`` whose value moves ``measure`` (each doubled in turn)."""
    ref = conditioning(build(params), top).get(measure)
    keys = []
    for k, v in params.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)) or v == 0:
            continue
        try:
            val = conditioning(build({**params, k: 2.0 * v}), top).get(measure)
        except Exception:  # noqa: BLE001 - a builder refusing the doubled value: not this key
            continue
        if val is not None and ref is not None and not np.isclose(val, ref, rtol=1e-6, atol=0):
            keys.append(k)
    return keys


def check_conditioning(scene):
    """Refuse (:class:`SceneError`) a scene whose linear structure is beyond the limits of
    the module docstring; return the scene.  Book weight models carry their own
    dimensionless checks and are passed through."""
    from stand.scene.model import RotorStructure

    rotor = scene.linear_rotor()
    if rotor is None:
        return scene
    top = scene.top_speed
    measures = conditioning(rotor, top)
    for name, limit, why in _LIMITS:
        value = measures.get(name)
        if value is None or value <= limit:     # (nan: refused by the builders' own checks)
            continue
        if isinstance(scene.structure, RotorStructure):
            from stand.model.registry import resolve
            from stand.scene.structure_tables import ROTOR_TYPES, build_rotor

            kind, params = scene.structure.type, dict(scene.structure.params)
            fn = resolve(ROTOR_TYPES, kind, "structure.type", "rotor type")
            keys = _involved(lambda p: build_rotor(kind, p), params, name, top)
            named = ", ".join(f"structure.{k} = {params[k]:g} {_unit(fn, k)}" for k in keys)
        else:
            from stand.model.rotors.planar_supports import planar_rotor

            r, s = scene.rotor, scene.supports
            params = {"rotor.mass": r.mass, "supports.stiffness_x": s.stiffness_x,
                      "supports.stiffness_y": s.stiffness_y, "supports.damping_x": s.damping_x,
                      "supports.damping_y": s.damping_y}
            keys = _involved(lambda p: planar_rotor(*p.values()), params, name, top)
            named = ", ".join(f"{k} = {params[k]:g} {_PLANAR_KEYS[k]}" for k in keys)
        if name == "rate_G":
            named = ", ".join(filter(None, [named, f"drive top speed {top / (2 * np.pi):g} rev/s"]))
        raise SceneError(f"{named or 'the structure'}: {why.format(v=value, lim=limit)}; check "
                         "the magnitudes of these values")
    return scene
