"""Rotating-frame form of the running models at constant speed, derived from the fixed frame.

At a constant dimensionless speed R on isotropic supports the equations in a
frame turning with the rotor are autonomous (book (5.44)-(5.48), digest ch5
section 2.4; (6.12), (7.2), (7.51)).  Rather than coding them a second time,
the rotating-frame right-hand side is obtained from the fixed-frame one that
runs -- the planar kernel (:func:`stand.model.planar.rhs_planar`) or the
generic kernel with its bodies (:func:`stand.model.rotors.coupled_kernel.rhs_generic`)
-- at the instant tau = 0 where the two frames coincide (rotor angle 0).  With
``Z = z e^{i R tau}`` for every planar vector (the shaft ``u + i v``)::

    xi = u,  eta = v,  xi' = u' - R v,  eta' = v' + R u,
    u'' = xi'' + 2 R v' + R^2 u,   v'' = eta'' - 2 R u' + R^2 v,

The rest of the state depends on the kernel:

* planar kernel: the weights' relative angles alpha_j are the same in both frames.
  State ``[u, v, alpha_1..alpha_n, u', v', alpha_1'..alpha_n']`` in units of L
  (= r*).  Equilibria are the book's steady motions (5.49); the eigenvalues of the
  Jacobian decide their stability (5.87)-(5.90).
* generic kernel (planar rotor x weights x bodies): the point weights' and tilting
  bodies' azimuths relative to the rotor (``alpha = psi``, ``alpha' = psi' + R``);
  a damper's ``n``, ``W`` and a liquid's offset keep their components at tau = 0 and
  turn back with ``- R e_z x``.  State: the model's layout (scaled as the model's
  state) with these rotating components; the equilibria are the steady motions of
  the books ((5.49), (6.12) steady states, (7.6), (7.51)) -- the tests check them
  against it, which ties the books' rotating-frame equations to the one fixed frame.
"""
from __future__ import annotations

import numpy as np

from stand.integrate.kernel_set import kernels
from stand.model.kernels import GENERIC, PLANAR
from stand.model.planar import COAST_T0, FREE, N_FORCE, N_PROG, N_UB, PlanarModel
from stand.model.programme import build_table
from stand.model.rotors import bodies_kernel as bk

__all__ = ["constant_speed_programme", "rotating_rhs", "rotating_to_fixed", "rotating_jacobian",
           "rotating_rhs_and_jacobian",
           "main_motion_state"]


def constant_speed_programme(R: float) -> np.ndarray:
    """Programme table for constant speed R with phi(0) = 0."""
    return build_table(np.array([0.0]), np.array([float(R)]))


def _shaft_to_fixed(z: np.ndarray, ns: int, R) -> np.ndarray:
    """A copy of ``z`` with the shaft velocity (at ``ns``, ``ns + 1``) in fixed components;
    ``z`` one state, or states as rows with ``R`` a speed per row."""
    z = np.asarray(z)
    y = np.array(z, dtype=np.float64, order="C", copy=True)
    u, v, du, dv = z[..., 0], z[..., 1], z[..., ns], z[..., ns + 1]
    y[..., ns], y[..., ns + 1] = du - R * v, dv + R * u
    return y


def _shaft_to_rotating(dy: np.ndarray, z: np.ndarray, ns: int, R: float) -> np.ndarray:
    """The fixed-frame derivative ``dy`` with the shaft rows in rotating components."""
    z = np.asarray(z)
    dz = np.array(dy, dtype=float, copy=True)
    u, v, du, dv = z[..., 0], z[..., 1], z[..., ns], z[..., ns + 1]
    dz[..., 0], dz[..., 1] = du, dv
    dz[..., ns] = dy[..., ns] + 2 * R * dv + R * R * u             # z'' = Z'' - 2 i R z' + R^2 z
    dz[..., ns + 1] = dy[..., ns + 1] - 2 * R * du + R * R * v
    return dz


def _check_generic(model):
    if model.n != 2 or model.rotor.name != "planar":
        raise ValueError("rotating frame: defined for the planar rotor (two coordinates) here")
    if model.n_adhesion:
        raise ValueError("rotating frame: weights with adhesion states are not autonomous")


def rotating_to_fixed(model, R: float, z: np.ndarray) -> np.ndarray:
    """The generic model's fixed-frame state at tau = 0 of the rotating-frame state ``z``
    (speed ``R``)."""
    _check_generic(model)
    n, nw = model.n, model.nw
    ns = n + nw
    y = _shaft_to_fixed(z, ns, R)
    y[ns + n:ns + n + nw] = np.asarray(z[ns + n:ns + n + nw], float) + R
    for row in model.bt:
        o, kind = int(row[bk.B_OFF]), int(row[bk.B_KIND])
        if kind == bk.TILT:
            y[o + 3] = z[o + 3] + R
    return y


def _planar_rotating_rhs_at(model: PlanarModel, R: float):
    """``z -> rotating_rhs(model, R, z)`` for the planar kernel, with the kernel, the
    constant-speed parameters and the programme table set up once (a Jacobian evaluates it
    at 2 x state-size points; the values are those of :func:`rotating_rhs`, bit for bit)."""
    setup = _planar_setup(model)
    prog = np.ascontiguousarray(constant_speed_programme(R), dtype=np.float64)
    Rrow = np.array([float(R)])
    return lambda z: _planar_rows(setup, np.asarray(z, dtype=float)[None, :], Rrow, [prog], 1)[0]



def _generic_rotating_rhs(model, R: float, z: np.ndarray) -> np.ndarray:
    n, nw = model.n, model.nw
    ns = n + nw
    y = rotating_to_fixed(model, R, z)
    dy = np.zeros_like(y)
    kernels(GENERIC).evaluate(0.0, y, dy, model.sp, model.wt, model.prog)
    dz = _shaft_to_rotating(dy, z, ns, R)
    dz[n:ns] = z[ns + n:ns + n + nw]                 # psi' (relative)
    for row in model.bt:
        o, kind = int(row[bk.B_OFF]), int(row[bk.B_KIND])
        if kind == bk.TILT:
            dz[o + 1] = z[o + 3]                         # psi' = alpha' - R
        elif kind == bk.SPHERE:
            for a in (o, o + 3):                         # - R e_z x (a0, a1, a2)
                dz[a] += R * y[a + 1]
                dz[a + 1] -= R * y[a]
        elif kind == bk.LAG:
            dz[o] += R * y[o + 1]
            dz[o + 1] -= R * y[o]
    return dz


def rotating_rhs(model, R: float, z: np.ndarray) -> np.ndarray:
    """d/dtau of the rotating-frame state ``z`` at constant speed ``R`` (module docstring).

    ``model`` is a :class:`~stand.model.planar.PlanarModel` with a prescribed speed
    (the support stiffness and damping should be isotropic for the result to be
    autonomous; not checked here: an anisotropic model gives the instantaneous
    value at phi = 0), or a generic model
    (:class:`~stand.model.rotors.coupled_kernel.CoupledModel`) of the planar rotor
    built with the constant programme ``R * omega_ref`` rad/s.

    For the generic model ``R`` is the speed of the frame only: the rotor turns as
    the model's programme says.  A frame speed other than the rotor's gives the frame
    of a quasi-periodic motion (book (6.19)-(6.22); autonomous when nothing on the
    rotor is unbalanced); the relative azimuths and rates of the state are then
    measured in that frame.
    """
    return _rotating_rhs_at(model, R)(z)


def _rotating_rhs_at(model, R: float):
    """``z -> rotating_rhs(model, R, z)``, with what does not depend on ``z`` set up once (a
    Jacobian evaluates it at 2 x state-size points)."""
    if isinstance(model, PlanarModel):
        return _planar_rotating_rhs_at(model, R)
    _check_generic(model)
    return lambda z: _generic_rotating_rhs(model, R, z)


def _planar_setup(model: PlanarModel) -> tuple:
    """What :func:`_planar_rows` needs of the model at any speed: (number of coordinates,
    constant-speed parameters, weight table, the kernel's entry point)."""
    if model.sp[FREE] != 0.0:
        raise ValueError("rotating frame: the rotor speed must be prescribed (speed drive)")
    sp = np.array(model.sp, dtype=np.float64, order="C")
    sp[COAST_T0] = np.inf  # no coast-down
    sp[N_PROG], sp[N_UB], sp[N_FORCE] = 1, 0, 0  # constant speed and unbalance, no side force
    wt = np.ascontiguousarray(model.wt, dtype=np.float64)
    ks = kernels(PLANAR).evaluate
    return 2 + model.n, sp, wt, getattr(ks, "unchecked", ks)   # arrays made C-contiguous float64


def _planar_rows(setup: tuple, Z: np.ndarray, Rrow: np.ndarray, progs: list, per: int):
    """:func:`rotating_rhs` at each row ``Z[k]`` at the speed ``Rrow[k]`` (the programme
    table ``progs[k // per]``, that of ``constant_speed_programme(Rrow[k])``): the shaft
    conversions on whole columns (the same operations, element by element), the kernel's
    entry point per row."""
    nq, sp, wt, ev = setup
    Z = np.asarray(Z, dtype=float)
    Y = _shaft_to_fixed(Z, nq, Rrow)
    DY = np.empty_like(Y)
    for k in range(Y.shape[0]):
        ev(0.0, Y[k], DY[k], sp, wt, progs[k // per])
    return _shaft_to_rotating(DY, Z, nq, Rrow)


def _rhs_and_jacobians_speeds(setup: tuple, Rs, zs, step: float) -> list:
    """(rhs, Jacobian) of :func:`rotating_rhs_and_jacobian` at each pair (speed ``Rs[i]``,
    state ``zs[i]``) of a planar model (:func:`_planar_setup`), all the evaluations in one
    kernel loop (bit for bit those of the one-state functions)."""
    if not zs:
        return []
    m = np.asarray(zs[0]).size
    per = 2 * m + 1
    progs, blocks, steps = {}, [], []
    for R, z in zip(Rs, zs):
        if R not in progs:
            progs[R] = np.ascontiguousarray(constant_speed_programme(R), dtype=np.float64)
        z = np.asarray(z, dtype=float)
        Zp, Zm, dzi = _fd_states(z, step)
        blocks += [z[None, :], Zp, Zm]
        steps.append(dzi)
    F = _planar_rows(setup, np.concatenate(blocks), np.repeat(np.asarray(Rs, float), per),
                     [progs[R] for R in Rs], per)
    return _split_rows(F, steps, m)


def _split_rows(F: np.ndarray, steps: list, m: int) -> list:
    """(rhs, Jacobian) of each block of 2 m + 1 rows of ``F`` (state, + steps, - steps)."""
    out = []
    for i, dzi in enumerate(steps):
        Fi = F[i * (2 * m + 1):(i + 1) * (2 * m + 1)]
        J = ((Fi[1:m + 1] - Fi[m + 1:]) / (2 * dzi)[:, None]).T
        out.append((Fi[0].copy(), np.ascontiguousarray(J)))
    return out


def _fd_states(z: np.ndarray, step: float):
    """The central-difference states of :func:`rotating_jacobian`: ``z`` + / - the step of
    each coordinate (rows), and the steps."""
    dzi = step * np.maximum(1.0, np.abs(z))
    D = np.diag(dzi)
    return z + D, z - D, dzi


def rotating_rhs_and_jacobian(model, R: float, z: np.ndarray, step: float = 1e-7):
    """:func:`rotating_rhs` at ``z`` and :func:`rotating_jacobian` there, in one pass.

    For the planar kernel the 2 x state-size + 1 evaluations go through the kernel in one
    loop (:func:`_rhs_and_jacobians_speeds`); the values are those of the two functions, bit
    for bit.

    Returns
    -------
    (ndarray, ndarray)
        The right-hand side, shape ``(m,)``, and the Jacobian, shape ``(m, m)``.
    """
    z = np.asarray(z, dtype=float)
    if not isinstance(model, PlanarModel):
        return rotating_rhs(model, R, z), rotating_jacobian(model, R, z, step)
    return _rhs_and_jacobians_speeds(_planar_setup(model), [float(R)], [z], step)[0]


def rotating_jacobian(model, R: float, z: np.ndarray, step: float = 1e-7) -> np.ndarray:
    """Jacobian of :func:`rotating_rhs` by central differences.

    Column i is ``(rhs(z + dz) - rhs(z - dz)) / (2 dz_i)`` with ``dz_i = step max(1, |z_i|)``
    on coordinate i only (dimensionless, as the state).
    """
    z = np.asarray(z, dtype=float)
    if isinstance(model, PlanarModel):
        return rotating_rhs_and_jacobian(model, R, z, step)[1]
    rhs = _rotating_rhs_at(model, R)
    J = np.empty((z.size, z.size))
    for i in range(z.size):
        dz = np.zeros_like(z)
        dz[i] = step * max(1.0, abs(z[i]))
        J[:, i] = (rhs(z + dz) - rhs(z - dz)) / (2 * dz[i])
    return J


def main_motion_state(model: PlanarModel, alphas) -> np.ndarray:
    """Rotating-frame state of a main (balancing) motion: shaft on the axis,
    weights at relative angles ``alphas`` [rad], everything at rest in the frame."""
    z = np.zeros(2 * (2 + model.n))
    z[2:2 + model.n] = alphas
    return z
