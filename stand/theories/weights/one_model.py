"""The books' rotating-frame states evaluated on the one model (issue 29, item 4).

The steady-motion theories of the books (ch. 6, 7.1, 7.2) linearise the
rotating-frame equations about a steady motion.  Those equations are not typed
again here: :func:`rotating_form` maps the book's rotating-frame state to the
generic composition of the model (:func:`stand.model.balancers.composition.composition`,
planar rotor x one body weight, run in the book's units ``M_Sigma = 1 kg``,
``omega0 = 1 rad/s``, ``l = 1 m``) and evaluates the rotating frame derived from the
fixed-frame kernel (:func:`stand.theories.rotating.rotating_rhs`).  The map is linear
(a permutation and the model's length scale), so equilibria, Jacobians and
eigenvalues are the book's.

Book rotating-frame states:

* ``two_axis``, ``gravity_pair``: ``[phi, psi, xi, eta, phi', psi', xi', eta']``;
* ``damper``: ``[xi, eta, xi', eta', n_1, n_2, n_3, W_1, W_2, W_3]`` (``W`` absolute,
  rotating components).
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from stand.model.balancers.composition import composition
from stand.theories.rotating import rotating_rhs
from stand.model.rotors.coupled_kernel import build_model

__all__ = ["rotating_form"]


def rotating_form(kind: str, p, frame_speed: float | None = None) -> Callable[[np.ndarray], np.ndarray]:
    """``f(y) -> dy/dtau`` of the book's rotating-frame state ``y`` (module docstring),
    computed by the one model.

    Parameters
    ----------
    kind : {"two_axis", "gravity_pair", "damper"}
    p : parameters dataclass of the model
        The rotor turns at the constant speed ``p.R_omega`` [-].
    frame_speed : float, optional
        Speed of the frame [-] (``omega0`` units); default ``p.R_omega``, the book's
        rotating frame.  Another speed gives the frame of a quasi-periodic motion of
        ch. 6.5, (6.19)-(6.22) (autonomous for ``e0 = 0``); the state's azimuth and shaft
        are then measured in that frame.
    """
    comp = composition(kind, p, 1.0)
    model = build_model(comp.rotor, (), comp.programme, 1.0, (comp.body,))
    o, L = model.first_body_state, float(model.scale[0])
    R = p.R_omega if frame_speed is None else float(frame_speed)
    if kind == "damper":
        shaft, body = [0, 1, 2, 3], list(range(4, 10))
        slots = list(range(o, o + 6))
    else:                                  # tilting bodies: tilt, azimuth and their rates
        shaft, body = [2, 3, 6, 7], [0, 1, 4, 5]
        slots = [o, o + 1, o + 2, o + 3]
    ns = model.n + model.nw

    def to_model(y):
        z = np.zeros(model.size)
        z[[0, 1, ns, ns + 1]] = np.asarray(y, float)[shaft] / L
        z[slots] = np.asarray(y, float)[body]
        return z

    def f(y):
        dz = rotating_rhs(model, R, to_model(y))
        dy = np.empty(len(shaft) + len(body))
        dy[shaft] = dz[[0, 1, ns, ns + 1]] * L
        dy[body] = dz[slots]
        return dy

    return f
