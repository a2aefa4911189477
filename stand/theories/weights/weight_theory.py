"""What the theory says of one book weight model: pure functions of its parameters.

:func:`weight_theory` takes a model kind and the model's parameter dataclass
(:class:`~stand.model.balancers.two_axis.TwoAxisParams`,
:class:`~stand.model.balancers.gravity_pair.GravityPairParams`,
:class:`~stand.model.balancers.damper.DamperParams`,
:class:`~stand.model.balancers.liquid_float.LiquidFloatParams`,
:class:`~stand.model.balancers.liquid_chamber.LiquidChamberParams`) and returns one
JSON-able dict.  It knows nothing of scenes: ``stand theory`` reaches it
through :func:`stand.theories.scene.model_theory`, and a rotor carrying body
weights can call it with the weight's parameters directly.

What each model gets
--------------------
* ``two_axis`` (ch. 6): steady motions with stability (6.29)-(6.40), the
  efficiency ``n = r~/r~0`` (6.40) of the stable main motion with its
  approximation (6.114), the quasi-periodic motions (6.115)-(6.162) with their
  precession and nutation amplitudes.
* ``gravity_pair`` (ch. 7.1): steady motions with stability (7.6)-(7.28), the
  side-motion gap (7.8), the stable quasi-periodic family (7.38)-(7.46):
  frequency, precession and nutation amplitudes, orbit radius range, speed
  range (7.41) and the shape of the shaft trace (digest section 1.6).
* ``damper`` (ch. 7.2): steady motions with stability (7.51)-(7.53), the
  efficiency (7.54) with the approximation (6.114) and the undamped existence
  boundaries (7.55)-(7.56).
* ``liquid_float`` (paper 001): critical speed with the liquid, the steady
  amplitude laws at the speed and the closed-form run-up extrema.
* ``liquid_chamber`` (thesis 002): the quasi-static efficiency lambda0 (2.14)
  with the corrected (2.13), its extremum (section 2.3.3) and its values at
  the speeds of Table 3.2, the optimal fill volume (section 3.3) and the
  choice of the liquid by the width of its equilibrium zone (2.15) among
  :data:`LIQUIDS`.

Units
-----
The chapter 6-7 models are dimensionless (speeds and frequencies in units of
``omega0``, shaft deflections in the book's scaled units, angles in rad); the
``units`` entry of the result says so.  The liquid models are SI; their keys
carry the unit (``_m3``, ``_kg_m``, ``_rad_s``, ...).  Non-finite numbers are
``None`` in the result (JSON has no NaN).  A part that does not apply to the
parameters is left out and explained in ``notes``.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from stand.io.jsonable import to_jsonable

__all__ = ["KINDS", "LIQUIDS", "DESIGN_RESERVE", "TABLE_3_2_GAMMAS", "weight_theory"]

#: the book weight models and their sources
KINDS = {
    "two_axis": "ch. 6",
    "gravity_pair": "ch. 7.1",
    "damper": "ch. 7.2",
    "liquid_float": "paper 001",
    "liquid_chamber": "thesis 002",
}

#: common balancing liquids: kinematic viscosity ``nu_m2_per_s`` [m^2/s] and
#: density ``rho_kg_per_m3`` [kg/m^3] at ``temperature_C`` [deg C].  Water,
#: ethanol and glycerol at 25 deg C: dynamic viscosities 0.890 mPa s, 1.074 mPa s
#: (Kaye & Laby, *Tables of Physical and Chemical Constants*, 2.2.3; CRC
#: Handbook of Chemistry and Physics, "Viscosity of liquids") and 934 mPa s
#: (CRC Handbook), densities 997.0, 785.1 and 1258 kg/m^3 (CRC Handbook);
#: ``nu = mu/rho``.  Mineral oil: ISO VG 32 (ISO 3448: 32 mm^2/s at 40 deg C,
#: grade range 28.8-35.2; about 2.5 times thicker at 20 deg C), a typical
#: density 860 kg/m^3.
LIQUIDS = {
    "water": {"nu_m2_per_s": 0.890e-3 / 997.0, "rho_kg_per_m3": 997.0, "temperature_C": 25.0,
              "source": "Kaye & Laby 2.2.3 (Kestin et al. 1978): 0.8902 mPa s; CRC density"},
    "ethanol": {"nu_m2_per_s": 1.074e-3 / 785.1, "rho_kg_per_m3": 785.1, "temperature_C": 25.0,
                "source": "Kaye & Laby 2.2.3 / CRC Handbook: 1.074 mPa s, 785.1 kg/m^3"},
    "glycerol": {"nu_m2_per_s": 0.934 / 1258.0, "rho_kg_per_m3": 1258.0, "temperature_C": 25.0,
                 "source": "CRC Handbook: 934 mPa s, 1258 kg/m^3"},
    "mineral oil ISO VG 32": {"nu_m2_per_s": 32e-6, "rho_kg_per_m3": 860.0, "temperature_C": 40.0,
                              "source": "ISO 3448 grade VG 32: 32 mm^2/s at 40 deg C; typical density"},
}

#: energy-capacity reserve factor of the design fill (thesis l.1315: 1.1-1.25)
DESIGN_RESERVE = 1.2
#: the speeds gamma = omega/omega_cr of Table 3.2 (thesis l.1494-1499)
TABLE_3_2_GAMMAS = (0.4, 0.6, 0.8, 1.0, 1.2, 1.4)
#: the steady and quasi-periodic motions are called stable when every
#: characteristic root has a real part below -STABILITY_TOL (as ``is_stable``)
STABILITY_TOL = 1e-7
#: run-up extrema are searched on a grid; beyond this many points they are skipped
MAX_RUNUP_POINTS = 5_000_000

_BOOK_UNITS = {
    "speed": "R_omega = omega/omega0 [-]",
    "frequency": "omega0 units [-]",
    "angle": "rad",
    "deflection": "dimensionless shaft deflection (the model's length scale) [-]",
    "efficiency": "n = r/r0, deflection with the balancer over without it [-] (smaller is better)",
}


def _eig_summary(lam) -> dict:
    """``stable`` and ``max_real_part`` [-] of characteristic roots."""
    re = np.real(np.asarray(lam))
    return {"stable": bool(np.all(re < -STABILITY_TOL)), "max_real_part": float(re.max())}

def _steady(p, notes, motions_of, row, equations: str) -> list:
    """``row(m)`` of each steady motion ``motions_of(p)`` (mapped for JSON); a failure becomes a
    note naming the book's ``equations``."""
    out = []
    try:
        for m in motions_of(p):
            out.append(to_jsonable(m) | row(m))
    except (ValueError, ArithmeticError) as exc:
        notes.append(f"steady motions {equations}: {_why(exc, p)}")
    return out


def _why(exc: Exception, p) -> str:
    """Why a part of the theory failed, for ``notes``."""
    if isinstance(exc, ArithmeticError) and getattr(p, "H", None) == 0.0 \
            and getattr(p, "R_omega", None) == 1.0:
        return "singular at the undamped resonance (R_omega = 1 with H = 0)"
    return str(exc) or type(exc).__name__


# --------------------------------------------------------------------------- ch. 7.1
def _trace(Ap, An, Omega, R_omega, R_m, H) -> dict:
    """Shape of the shaft trace of a QP motion (digest ch7 section 1.6, items 2-6).

    Two co-rotating circles, radius ``Ap`` at ``Omega`` and ``An`` at ``R_omega``
    [omega0 units]: ``R_omega/Omega - 1`` petals (rounded), cusps where
    ``An R_omega = Ap Omega`` (shortened below, elongated above), the pattern
    turning at ``Omega - (R_omega - Omega)/petals``; ``cusp_unbalance_e0`` is
    the unbalance [capacity units] at which the cusps appear.
    """
    k = R_omega / Omega
    petals = max(int(round(k - 1.0)), 0)
    a, b = An * R_omega, Ap * Omega         # speeds of the two co-rotating circles
    if abs(a - b) <= 1e-3 * max(a, b):
        shape = "normal (cusps)"
    else:
        shape = "shortened (no loops)" if a < b else "elongated (loops)"
    cusp = (Ap * Omega * math.sqrt(_D(R_omega, H)) / (R_m * R_omega ** 3)
            if R_m > 0 and R_omega > 0 else math.nan)
    return {"frequency_ratio": k, "petals": petals, "shape": shape,
            "pattern_rotation": Omega - (R_omega - Omega) / petals if petals else math.nan,
            "cusp_unbalance_e0": cusp}


def _D(w, H):
    return (w * w - 1.0) ** 2 + H * H * w * w


def _gravity_pair(p, notes) -> dict:
    from stand.theories.weights import gravity_pair_steady as gst
    from stand.theories.weights import gravity_pair_qp as gqp

    out = {"speed_R_omega": p.R_omega, "units": _BOOK_UNITS}
    motions = _steady(p, notes, gst.steady_motions, lambda m: {"deflection": m.deflection}
                      | _eig_summary(gst.eigenvalues(p, m)), "(7.6)-(7.9)")
    out["steady_motions"] = motions
    if 0.0 < p.e0 < 1.0:
        lo, hi = gst.side_band(p)
        out["side_motion_gap_R_omega"] = [lo, hi]
    r0 = p.R_m * p.R_omega ** 2 * p.e0 / math.sqrt(_D(p.R_omega, p.H)) if _D(p.R_omega, p.H) > 0 \
        else math.inf
    main = [m for m in motions if m["kind"] == "main" and m["stable"]]
    eff = {"deflection_without_balancer": r0,
           "definition": "n = r/r0 on the stable main motion (the ch. 6 / 7.2 measure; the "
                         "main motions of 7.1 balance exactly while e0 < 1)"}
    if main and r0 > 0 and math.isfinite(r0):
        best = min(main, key=lambda m: m["deflection"])
        eff |= {"value": best["deflection"] / r0, "motion": best["label"],
                "deflection": best["deflection"]}
    else:
        eff["value"] = None
        notes.append("efficiency: " + ("no stable main motion at this speed" if not main
                                       else "no unbalance to compare with (r0 = 0)" if r0 == 0
                                       else "undamped resonance (r0 infinite)"))
    out["balancing_efficiency"] = eff
    qp = {"equations": "(7.38)-(7.46) with errata E3-E5 (digest ch7 section 1.6)",
          "phi_rad": math.pi / 2, "family_limit_R_omega": gqp.qp_family_limit(p)}
    if p.h2 == 0.0:
        notes.append("quasi-periodic motions: h2 = 0, the frequency equation (7.39) needs h2 > 0")
        qp["exists"] = False
        out["quasi_periodic"] = qp
        return out
    Omega = gqp.qp_frequency(p)
    lim_exact, _ = gqp.qp_family_limit_exact(p)
    qp["family_limit_exact_R_omega"] = lim_exact
    qp["frequency_Omega"] = Omega
    qp["frequency_small_H_approx"] = gqp.qp_frequency_approx(p)
    in_range = 1.0 < p.R_omega < lim_exact
    qp["in_stable_range"] = bool(in_range)
    qp["exists"] = bool(math.isfinite(Omega) and in_range)
    if math.isfinite(Omega):
        try:
            Ap, An = gqp.qp_amplitudes(p, Omega)
            qp |= {"precession_amplitude": Ap, "nutation_amplitude": An,
                   "orbit_radius_min": abs(Ap - An), "orbit_radius_max": Ap + An}
            qp["trace"] = _trace(Ap, An, Omega, p.R_omega, p.R_m, p.H)
        except (ValueError, ArithmeticError) as exc:
            notes.append(f"quasi-periodic amplitudes (7.43)-(7.46): {_why(exc, p)}")
    if not in_range:
        notes.append(f"quasi-periodic family (7.40): stable only for 1 < R_omega < "
                     f"{lim_exact:.4g}; R_omega = {p.R_omega:.4g} is outside")
    out["quasi_periodic"] = qp
    return out


# --------------------------------------------------------------------------- ch. 6
def _two_axis(p, notes) -> dict:
    from stand.theories.weights import two_axis_steady as st
    from stand.theories.weights import two_axis_theory as th

    out = {"speed_R_omega": p.R_omega, "units": _BOOK_UNITS}
    motions = _steady(p, notes, st.steady_motions, lambda m: {"stable": bool(m.stable),
                                                              "max_real_part": m.max_re},
                      "(6.29)-(6.51)")
    out["steady_motions"] = motions
    r0 = st.r0(p) if _D(p.R_omega, p.H) > 0 else math.inf
    eff = {"equation": "(6.40): n = r~/r~0 of a first-group motion", "deflection_without_balancer": r0}
    main = [m for m in motions if m["kind"].startswith("main") and m["stable"]]
    below = [m for m in main if m["kind"] == "main_below"]
    pick = below or sorted(main, key=lambda m: m["n"] if m["n"] is not None else math.inf)
    if pick and pick[0]["n"] is not None:
        eff |= {"value": pick[0]["n"], "motion": pick[0]["kind"]}
    else:
        eff["value"] = None
        notes.append("efficiency (6.40): " + ("no stable main motion at this speed" if not main
                                              else "undefined without unbalance (e0 = 0)"))
    eff["by_motion"] = {m["kind"]: m["n"] for m in motions if m["group"] == 1}
    if p.R_g > 0 and p.e0 < 1.0:
        eff["approx_6_114"] = th.efficiency_approx(p)
        eff["n_max_near_sqrt2_estimate"] = th.n_max_estimate(p.R_gm)
    out["balancing_efficiency"] = eff
    qps = []
    try:
        for q in th.qp_motions(p):
            Ap, An = th.qp_amplitudes(p, q.Omega, q.phi)
            qps.append(to_jsonable(q) | {"stable": bool(q.stable), "precession_amplitude": Ap,
                                         "nutation_amplitude": An,
                                         "trace": _trace(Ap, An, q.Omega, p.R_omega, p.R_m, p.H)})
    except (ValueError, ArithmeticError) as exc:
        notes.append(f"quasi-periodic motions (6.115)-(6.162): {_why(exc, p)}")
    out["quasi_periodic"] = qps
    out["quasi_periodic_existence_limit_R_omega"] = th.qp_existence_limit(p)
    if p.R_g > 0:
        out["quasi_periodic_gravity_allows"] = bool(th.qp_gravity_allows(p))
    return out


# --------------------------------------------------------------------------- ch. 7.2
def _damper(p, notes) -> dict:
    from stand.theories.weights import damper_steady as dst
    from stand.theories.weights.damper_steady import _Delta

    out = {"speed_R_omega": p.R_omega, "units": _BOOK_UNITS}
    motions = _steady(p, notes, dst.steady_motions, lambda m: {"deflection": m.deflection}
                      | _eig_summary(dst.eigenvalues(p, m)), "(7.51)-(7.53)")
    out["steady_motions"] = motions
    eff = {"equation": "(7.54): n = sqrt(Delta(0)/Delta(u)), u = cos(phi) the largest positive root "
                       "of (7.53) (the branch stable by (7.68))"}
    try:
        eff["value"] = dst.efficiency(p)
        roots = dst.steady_quartic_roots(p)
        roots = roots[roots > 0]
        if roots.size:
            u = float(roots.max())
            D0, Du = _Delta(0.0, p), _Delta(u, p)
            scale = p.R_m * p.R_omega ** 2 * p.e0
            eff |= {"u": u, "phi_rad": math.acos(u), "deflection": scale / math.sqrt(Du),
                    "deflection_without_balancer": scale / math.sqrt(D0) if D0 > 0 else math.inf}
            same = [m for m in motions if abs(m["u"] - u) < 1e-9]
            if same:
                eff["motion_stable"] = bool(same[0]["stable"])
        else:
            notes.append("efficiency (7.54): no steady motion with the weight below the "
                         "suspension point (u > 0)")
        if p.e0 < 1.0:
            eff["approx_6_114"] = dst.efficiency_approx(p)
            if p.R_m > 0 and p.R_omega > 0:
                eff["fast_rotor_asymptote"] = p.R_g ** 2 / (p.R_m * p.R_omega ** 2
                                                            * math.sqrt(1 - p.e0 ** 2))
    except (ValueError, ArithmeticError) as exc:
        eff["value"] = None
        notes.append(f"efficiency (7.54): {_why(exc, p)}")
    out["balancing_efficiency"] = eff
    if p.R_m > 0 and p.R_g > 0 and 0.0 <= p.e0 < 1.0:
        out["existence_boundaries_undamped"] = dst.critical_speeds_undamped(p.R_m, p.R_g, p.e0) \
            | {"equations": "(7.55)-(7.56), for H = 0"}
    return out


# --------------------------------------------------------------------------- paper 001
def _liquid_float(p, omega, notes) -> dict:
    from stand.model.balancers.liquid_float import steady_amplitudes
    from stand.model.balancers.runup_closed_form import runup_extrema

    de, d = steady_amplitudes(p, omega)
    out = {"speed_rad_s": omega, "critical_speed_rad_s": p.Omega,
           "critical_speed_bare_rotor_rad_s": p.Omega_0,
           "steady": {"delta_over_e": float(de), "deflection_m": float(de) * p.e, "d": float(d),
                      "equations": "steady laws of digest 1.5 (paper 001 (5))"}}
    notes.append("efficiency: paper 001 defines none; the steady laws and run-up extrema are its "
                 "measures")
    if p.epsilon <= 0:
        notes.append(f"run-up extrema: epsilon = {p.epsilon:g} rad/s^2, the closed form is for a "
                     "run-up (epsilon > 0)")
        return out
    t_end = p.time_at_z(2.0) if p.omega_0 < 2.0 * p.Omega_0 else 0.0
    n = t_end / (2 * math.pi / (p.Omega + 2.0 * p.Omega_0) / 3.0)
    if t_end <= 0:
        notes.append("run-up extrema: the run starts above 2 Omega_0")
    elif n > MAX_RUNUP_POINTS:
        notes.append(f"run-up extrema: {n:.3g} grid points to 2 Omega_0 (> {MAX_RUNUP_POINTS:g}); "
                     "not computed")
    else:
        out["runup_extrema"] = to_jsonable(runup_extrema(p))
    return out


# --------------------------------------------------------------------------- thesis 002
def _liquid_chamber(p, omega, notes) -> dict:
    from stand.model.balancers import liquid_chamber as lc
    from stand.theories.weights import liquid_chamber_quasi_static as lqs

    out = {"speed_rad_s": omega, "gamma": omega / p.critical_speed}
    R, h, rho, V = p.chamber_radius, p.chamber_height, p.liquid_density, p.liquid_volume
    D0 = p.rotor_unbalance
    if omega > 0:
        qs = lqs.quasi_static_efficiency(p, omega)
        out["quasi_static_efficiency"] = to_jsonable(qs)
        eff = {"lambda0": qs.lambda0, "k": qs.k, "alpha0_rad": qs.alpha0,
               "alpha0_deg": math.degrees(qs.alpha0), "delta_rad": qs.delta,
               "equation": "(2.14) lambda0 = zeta0/zeta = k/sqrt(1 + 2k cos(alpha0) + k^2), "
                           "alpha0 from the corrected (2.13)",
               "valid": qs.valid, "flags": list(qs.flags)}
        if math.isfinite(qs.alpha0):
            ex = lqs.efficiency_extremum(qs.alpha0)
            eff |= {"k_star": ex.k_star, "lambda0_max": ex.lambda_max}
        out["balancing_efficiency"] = eff
    else:
        notes.append("quasi-static efficiency (2.14): needs a speed > 0 rad/s")
    rows = []
    for g in TABLE_3_2_GAMMAS:
        r = lqs.quasi_static_efficiency(p, g * p.critical_speed)
        rows.append({"gamma": g, "omega_rad_s": g * p.critical_speed, "lambda0": r.lambda0,
                     "k": r.k, "valid": r.valid})
    out["efficiency_by_speed"] = rows
    if D0 <= 0:
        notes.append("optimal volume (section 3.3): no rotor unbalance (unbalance_mass * "
                     "unbalance_radius = 0 kg m)")
    else:
        ov = lc.optimal_volume(D0, R, h, rho, reserve=DESIGN_RESERVE)
        ann = lc.optimal_volume(D0, R, h, rho, model="annulus")
        out["optimal_volume"] = {
            "equation": "section 3.3: liquid unbalance capacity D(V) = D0 (k = 1), then the "
                        "reserve factor",
            "D0_kg_m": D0, "D0_g_cm": D0 * 1e5, "V_opt_m3": ov.V_opt, "V_opt_ml": ov.V_opt * 1e6,
            "reserve": DESIGN_RESERVE, "V_design_m3": ov.V_design, "capacity_kg_m": ov.capacity,
            "max_capacity_kg_m": ov.max_capacity, "V_max_capacity_m3": ov.V_max_capacity,
            "lower_bound_m3": ov.lower_bound, "chamber_volume_m3": ov.chamber_volume,
            "fill_fraction": ov.fill_fraction, "layer_m": ov.layer,
            "V_opt_annulus_m3": ann.V_opt, "annulus_valid": ann.valid,
            "liquid_volume_m3": V, "liquid_over_optimal": V / ov.V_opt if ov.V_opt > 0 else None,
            "model": ov.model, "valid": ov.valid, "flags": list(ov.flags)}
    out["liquid_choice"] = _liquid_choice(p, omega, D0, notes)
    return out


def _liquid_choice(p, omega, D0, notes) -> dict:
    """Width of the equilibrium zone (2.15) of each liquid of :data:`LIQUIDS`."""
    from stand.model.balancers import liquid_chamber as lc

    R, h = p.chamber_radius, p.chamber_height
    out = {"equation": "(2.15): sin(beta*) = 8 pi nu R xi/(V omega), xi = 2 pi (whole wall); "
                       "each liquid filled to its own optimal volume (capacity = D0)",
           "speed_rad_s": omega, "liquids": {}}
    if omega <= 0:
        notes.append("liquid choice (2.15): needs a speed > 0 rad/s")
        out["chosen"] = None
        return out
    for name, liq in LIQUIDS.items():
        if D0 > 0:
            ov = lc.optimal_volume(D0, R, h, liq["rho_kg_per_m3"])
            Vl, vol_ok = ov.V_opt, ov.valid
        else:
            Vl, vol_ok = p.liquid_volume, True
        row = dict(liq) | {"V_m3": Vl, "volume_valid": vol_ok}
        if Vl > 0:
            z = lc.viscous_zone(liq["nu_m2_per_s"], R, Vl, omega, D=D0)
            row |= {"sin_beta_star": z.sin_beta_star, "beta_star_deg": math.degrees(z.beta_star),
                    "residual_unbalance_kg_m": z.residual_unbalance, "keeps_zone": z.valid}
        else:
            row |= {"sin_beta_star": math.nan, "keeps_zone": False}
        out["liquids"][name] = row
    ok = {k: v for k, v in out["liquids"].items() if v["keeps_zone"]}
    out["chosen"] = min(ok, key=lambda k: ok[k]["sin_beta_star"]) if ok else None
    if out["chosen"] is None:
        notes.append("liquid choice (2.15): no liquid of the table keeps a bounded equilibrium zone "
                     "(sin(beta*) >= 1 for all)")
    if p.liquid_volume > 0:
        z = lc.viscous_zone(p.kinematic_viscosity, R, p.liquid_volume, omega, D=D0)
        out["scene_liquid"] = {"nu_m2_per_s": p.kinematic_viscosity, "V_m3": p.liquid_volume,
                               "sin_beta_star": z.sin_beta_star,
                               "beta_star_deg": math.degrees(z.beta_star), "keeps_zone": z.valid}
    return out


# --------------------------------------------------------------------------- entry point
_PARAMS = {
    "two_axis": ("two_axis", "TwoAxisParams"),
    "gravity_pair": ("gravity_pair", "GravityPairParams"),
    "damper": ("damper", "DamperParams"),
    "liquid_float": ("liquid_float", "LiquidFloatParams"),
    "liquid_chamber": ("liquid_chamber", "LiquidChamberParams"),
}


def _params_class(kind):
    """The parameter dataclass of a model kind."""
    import importlib

    mod, name = _PARAMS[kind]
    return getattr(importlib.import_module(f"stand.model.balancers.{mod}"), name)


def weight_theory(kind: str, params, speed: float | None = None) -> dict:
    """The theory of one book weight model (module docstring), as a JSON-able dict.

    Parameters
    ----------
    kind : {"two_axis", "gravity_pair", "damper", "liquid_float", "liquid_chamber"}
        The model.
    params : dataclass
        The model's parameters (``TwoAxisParams``, ``GravityPairParams``,
        ``DamperParams``, ``LiquidFloatParams`` or ``LiquidChamberParams``).
    speed : float, optional
        The speed at which to evaluate, in the model's own unit: ``R_omega =
        omega/omega0`` [-] for the chapter 6-7 models (replaces
        ``params.R_omega``), ``omega`` [rad/s] for the liquids (default
        ``params.omega_0`` for ``liquid_float``, half the critical speed for
        ``liquid_chamber``).  >= 0.

    Returns
    -------
    dict
        Always ``model``, ``source``, ``parameters`` (the dataclass as a dict)
        and ``notes`` (what did not apply and why), plus per model:

        * two_axis: ``speed_R_omega``, ``units``, ``steady_motions`` (each:
          phi, psi, xi, eta, group, kind, n, eig, stable, max_real_part),
          ``balancing_efficiency`` (value, motion, by_motion,
          deflection_without_balancer, approx_6_114,
          n_max_near_sqrt2_estimate), ``quasi_periodic`` (each: Omega, phi,
          family, eig, stable, precession_amplitude, nutation_amplitude,
          trace), ``quasi_periodic_existence_limit_R_omega``,
          ``quasi_periodic_gravity_allows``.
        * gravity_pair: ``speed_R_omega``, ``units``, ``steady_motions``
          (label, kind, phi, psi, xi, eta, deflection, stable,
          max_real_part), ``side_motion_gap_R_omega``,
          ``balancing_efficiency`` (value, deflection,
          deflection_without_balancer), ``quasi_periodic`` (exists,
          frequency_Omega, frequency_small_H_approx, precession_amplitude,
          nutation_amplitude, orbit_radius_min/max, family_limit_R_omega,
          family_limit_exact_R_omega, in_stable_range, trace: frequency_ratio,
          petals, shape, pattern_rotation, cusp_unbalance_e0).
        * damper: ``speed_R_omega``, ``units``, ``steady_motions`` (label,
          kind, phi, psi, u, xi, eta, deflection, stable, max_real_part),
          ``balancing_efficiency`` (value (7.54), u, phi_rad, deflection,
          deflection_without_balancer, motion_stable, approx_6_114,
          fast_rotor_asymptote), ``existence_boundaries_undamped``.
        * liquid_float: ``speed_rad_s``, ``critical_speed_rad_s``,
          ``critical_speed_bare_rotor_rad_s``, ``steady`` (delta_over_e,
          deflection_m, d), ``runup_extrema``.
        * liquid_chamber: ``speed_rad_s``, ``gamma``,
          ``quasi_static_efficiency``, ``balancing_efficiency`` (lambda0, k,
          alpha0_rad, alpha0_deg, delta_rad, k_star, lambda0_max, valid,
          flags), ``efficiency_by_speed`` (gamma, omega_rad_s, lambda0, k,
          valid per Table 3.2 speed), ``optimal_volume`` (D0_kg_m, D0_g_cm,
          V_opt_m3, V_opt_ml, reserve, V_design_m3, capacity_kg_m,
          max_capacity_kg_m, V_max_capacity_m3, lower_bound_m3,
          chamber_volume_m3, fill_fraction, layer_m, V_opt_annulus_m3,
          liquid_volume_m3, liquid_over_optimal, valid, flags),
          ``liquid_choice`` (liquids: name -> nu_m2_per_s, rho_kg_per_m3,
          temperature_C, source, V_m3, sin_beta_star, beta_star_deg,
          residual_unbalance_kg_m, keeps_zone; chosen; scene_liquid).

    Raises
    ------
    ValueError
        An unknown ``kind``, ``params`` of another model, or a negative or
        non-finite ``speed`` (naming the value and its unit).
    """
    if kind not in KINDS:
        raise ValueError(f"kind = {kind!r} is invalid: valid: {', '.join(KINDS)}")
    cls = _params_class(kind)
    if not isinstance(params, cls):
        raise ValueError(f"params = {type(params).__name__} is invalid for kind = {kind!r}: "
                         f"must be a {cls.__name__}")
    unit = "rad/s" if kind.startswith("liquid") else "R_omega = omega/omega0 [-]"
    if speed is not None:
        if isinstance(speed, bool) or not isinstance(speed, (int, float, np.floating, np.integer)) \
                or not math.isfinite(float(speed)) or float(speed) < 0:
            raise ValueError(f"speed = {speed!r} {unit} is invalid: must be a finite number >= 0")
        speed = float(speed)
    notes: list = []
    if kind in ("two_axis", "gravity_pair", "damper") and speed is not None:
        params = dataclasses.replace(params, R_omega=speed)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):   # singular points -> NaN
        if kind == "two_axis":
            body = _two_axis(params, notes)
        elif kind == "gravity_pair":
            body = _gravity_pair(params, notes)
        elif kind == "damper":
            body = _damper(params, notes)
        elif kind == "liquid_float":
            body = _liquid_float(params, params.omega_0 if speed is None else speed, notes)
        else:
            body = _liquid_chamber(params, 0.5 * params.critical_speed if speed is None else speed,
                                   notes)
    out = {"model": kind, "source": KINDS[kind], "parameters": params} | body | {"notes": notes}
    return to_jsonable(out)
