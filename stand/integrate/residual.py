"""The residual unbalance of a run as a balancing engineer states it: static and couple.

A run's truth (:attr:`stand.integrate.result.Run.truth`, recording datasets
``truth/residual/<plane>``, :mod:`stand.recording.layout`) holds, for every plane of a
rotor of the family, the plane's own unbalance in the rotor frame [kg m]: the rotor's
unbalances listed in that plane plus the weights and bodies sitting in it,
``U_p = sum_i m_i r_i e^{i phi_i}`` (phi_i from the reference mark).  A rotor whose
unbalance sits in a plane of its own (the grinding rotor's ``"unbalance"``, the spatial
rotor's ``"unbalance1"``) therefore has its rotor unbalance in one dataset and the
balls' static moment in another; neither alone is the residual.  A planar rotor has one
plane and no such datasets: its residual is ``M e e^{i beta} + sum m_j l_j e^{i alpha_j}``
from the scene and the weights' angles.

What is reported (ISO 21940-2 terms):

* the **static residual** ``U_s = sum_p U_p`` [kg m]: the vector sum of every
  unbalance and every weight's static moment over all planes -- the resultant of
  the centrifugal forces, ``Omega^2 U_s``.  This is "the residual unbalance" of the
  run's summary; it vanishes when the weights cancel the unbalance wherever it sits;
* the **couple residual** ``U_c = sum_p z_p U_p`` [kg m^2] where the loaded planes (those
  with an unbalance, a weight or a body) lie at different axial positions z_p, measured
  from the rotor type's axial origin (the centre of mass of ``spatial``, the fixed point
  O of the hinged rotors and ``fixed_point_stand``, the left support of ``flexible``,
  :mod:`stand.scene.placement`).  A rigid rotor is balanced when both vanish.  For the
  flexible rotor they are its rigid-body (low-speed) balance; above its first critical
  speeds the modal unbalances decide as well (the per-plane truth gives them).  Rotors
  without tilt (planar, two-mass, grinding) have no couple: every plane moves alike.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

__all__ = ["plane_residuals", "plane_positions", "static_residual", "couple_residual",
           "loaded_planes"]

PREFIX = "residual/"


def plane_residuals(run, index=slice(None)) -> dict:
    """Each plane's unbalance (rotor + its weights), complex, rotor frame [kg m].

    Parameters
    ----------
    run : stand.integrate.result.Run
        A run or a recording.
    index : slice or index array
        The samples wanted (default all); ``slice(-1, None)`` for the last one.

    Returns
    -------
    dict of str -> ndarray (n,) complex
        ``truth/residual/<plane>`` of a rotor of the family; the main plane's formula
        (module docstring) of a planar scene; ``{}`` when the run cannot say (a
        recording whose weights its scene does not match, no scene).
    """
    out = {key[len(PREFIX):]: np.asarray(U, float)[index]
           for key, (U, _) in run.truth.items() if key.startswith(PREFIX)}
    if out:
        return {p: U[..., 0] + 1j * U[..., 1] for p, U in out.items()}
    scene = run.scene
    if getattr(scene, "kind", None) != "planar":
        return {}
    from stand.model.planar import rotor_unbalance

    t = np.asarray(run.t)[index]
    psi = np.asarray(rotor_unbalance(scene, t), complex)
    b = scene.balancer
    if b.count:
        a = run.weight_angle[index] - np.asarray(run.rotor_angle)[index][:, None]
        if a.shape[-1] != b.count:
            return {}
        psi = psi + np.sum(b.mass * b.radius * np.exp(1j * a), axis=-1)
    return {run.main_plane: psi}


def plane_positions(scene, planes) -> Optional[dict]:
    """Axial positions z_p [m] of ``planes`` on the rotor's axis, or None.

    Each plane's map is matched to the rotor type's map of an axis point
    (:func:`stand.scene.placement.axis_map`).  A rigid axis has an affine map,
    ``T(z) = T(0) + z (T(1) - T(0))``, from which z_p follows; the flexible rotor's map
    (mode shapes at z) is not affine: its planes' positions are the scene's
    ``[structure] planes`` table, each checked against the map.  None when the type has no
    map of its axis points (no tilt: planar, two-mass, grinding) or a plane is not a point
    of the axis.
    """
    from stand.errors import SceneError
    from stand.scene.placement import axis_map

    if getattr(scene, "structure", None) is None:
        return None
    rotor = scene.linear_rotor()
    maps = {p: rotor.planes.get(p) for p in planes}
    if any(T is None for T in maps.values()):
        return None
    try:
        T0, T1, T2 = (axis_map(scene, d) for d in (0.0, 1.0, 2.0))
    except (SceneError, ValueError):
        T0 = None
    if T0 is not None:
        B = T1 - T0
        bb = float(np.sum(B * B))
        if bb == 0.0 or not np.allclose(T2, T0 + 2.0 * B, rtol=1e-9, atol=1e-12):
            return None
        z = {p: float(np.sum((T - T0) * B)) / bb for p, T in maps.items()}
        ok = all(np.allclose(T, T0 + z[p] * B, rtol=1e-9, atol=1e-12 * (1.0 + abs(z[p])))
                 for p, T in maps.items())
        return z if ok else None
    stated = (getattr(scene.structure, "params", None) or {}).get("planes")
    if not isinstance(stated, dict) or not set(maps) <= set(stated):
        return None
    z = {p: float(stated[p]) for p in maps}
    try:
        ok = all(np.allclose(axis_map(scene, z[p]), T, rtol=1e-9, atol=1e-12)
                 for p, T in maps.items())
    except (SceneError, ValueError):
        return None
    return z if ok else None


def static_residual(run, index=slice(None)):
    """Static residual ``sum_p U_p`` [kg m], complex, rotor frame (module docstring); None
    when the run cannot say."""
    U = plane_residuals(run, index)
    return sum(U.values()) if U else None


def couple_residual(run, index=slice(None), positions=None):
    """Couple residual ``sum_p z_p U_p`` [kg m^2], complex, rotor frame, about the rotor
    type's axial origin; None when the loaded planes share one position (the couple is then
    z U_s, nothing beyond the static residual), without tilt, for the flexible rotor, or
    when the run cannot say (module docstring).  ``positions``: the caller's
    :func:`plane_positions` of the run's residual planes [m] (computed when None)."""
    U = plane_residuals(run, index)
    z = positions if positions is not None else plane_positions(run.scene, U) if U else None
    if z is None or len({round(z[p], 12) for p in loaded_planes(run.scene, U)}) < 2:
        return None
    return sum(z[p] * u for p, u in U.items())


def loaded_planes(scene, planes) -> list:
    """The ``planes`` that carry an unbalance, a weight or a body of the scene (not the
    instruments' axis points nor other probe planes)."""
    rotor = scene.linear_rotor()
    used = {u.plane for u in rotor.unbalances}
    used |= {w.plane for w in scene.weights} | {b.plane for b in getattr(scene, "bodies", ())}
    return [p for p in planes if p in used]
