"""Field balancing from a job file of readings (``stand balance``; :func:`balance_job`).

Every run ``k`` at one speed is modelled as ``V_k = V0 + A W_k`` (S sensors, P planes), with
``W_k`` the trial masses on the rotor during that run (its own trial, plus the trials left on
by earlier runs with ``removed = false``) and the slow-roll vector subtracted from ``V_k``.
``[V0, A] = D M^+`` with ``D`` the readings and ``M = [1; W_k]``: exact for one reference and
one trial run per plane, least squares with more runs.  A known influence matrix
(``[[influence]]``, ``--influence``) replaces ``A`` (trial runs at that speed are then not
used); ``V0`` is the reference run's ``V - A W``.  A job of amplitude-only readings goes to
:mod:`stand.analysis.field_amplitude` (the four-run method).  The speeds are solved together (their rows stacked), and the corrections
(for the rotor with every trial removed) come from :mod:`dsp.influence_solve`.

Uncertainties are propagated to first order from the repeated readings' scatter (central
differences of the whole chain, readings to corrections).
"""
from __future__ import annotations

import math

import numpy as np

from dsp.influence_solve import conditioning, cvxpy_available, least_squares, min_max, \
    split_onto_holes, split_onto_weights
from stand.io.result import Result

from .field_job import FieldJob, read_job, reference_sensors
from .field_trials import TRIAL_RULE, trial_mass, trial_validity
from .field_verdict import field_verdict, iso_grades

__all__ = ["FieldBalance", "balance_job", "influence_toml"]

_RPM = 60.0 / (2.0 * math.pi)
SPEED_RTOL = 0.01


class FieldBalance(Result):
    """A field-balancing job's answer (``stand balance --json``): ``corrections`` keyed by
    plane (mass in the job's mass unit, angle_deg, their uncertainties, hole split),
    ``residuals`` per sensor and speed (before / predicted after, the job's vibration unit),
    the ``influence`` matrix, its ``condition`` and ``warnings``."""

    _title = "field balancing"
    _summary_keys = ("method", "corrections", "condition", "warnings")

    def _draw(self, ax) -> None:
        for r in self["residuals"]:
            for key, mk in (("before", "o"), ("after", "x")):
                th = math.radians(r[f"{key}_deg"] or 0.0)      # None: exactly zero
                ax.plot([0, r[key] * math.cos(th)], [0, r[key] * math.sin(th)], marker=mk,
                        label=f"{r['sensor']} {key}")
        ax.set_aspect("equal")
        ax.set_xlabel(f"Re [{self['vibration_unit']}]")
        ax.set_ylabel(f"Im [{self['vibration_unit']}]")
        ax.legend(fontsize="small")
        ax.set_title(self._title)


def _speed_groups(job: FieldJob) -> list:
    """Distinct speeds [rad/s] (within SPEED_RTOL), NaN alone when no run gives one."""
    ws = sorted({r.speed for r in job.runs if r.kind != "slow_roll" and not math.isnan(r.speed)}
                | {w for w, _ in job.influence if not math.isnan(w)})
    groups = []
    for w in ws:
        if groups and abs(w - groups[-1]) <= SPEED_RTOL * groups[-1]:
            continue
        groups.append(w)
    return groups or [math.nan]


def _group_of(w, groups, what):
    if math.isnan(w):
        if len(groups) == 1:
            return 0
        raise ValueError(f"{what}: give its speed (the job has runs at "
                         f"{', '.join(f'{g * _RPM:.6g} rpm' for g in groups)})")
    for k, g in enumerate(groups):
        if not math.isnan(g) and abs(w - g) <= SPEED_RTOL * g:
            return k
    return None


class _Chain:
    """Readings (a flat complex vector) -> stacked V0, A -> corrections; built once per job."""

    def __init__(self, job: FieldJob):
        self.job = job
        P = len(job.planes)
        self.groups = _speed_groups(job)
        self.x, self.sig, self.pos = [], [], {}
        for r in job.runs:
            for s, v in r.readings.items():
                self.pos[(r.index, s)] = len(self.x)
                self.x.append(v)
                self.sig.append(r.std[s])
        for r in job.runs:            # the trial masses too: their weighing is a reading
            for p, t in r.trial.items():
                self.pos[("trial", r.index, p)] = len(self.x)
                self.x.append(t)
                self.sig.append(r.trial_std.get(p, 0.0))
        self.added = self._added(self.x)
        self.plan = []
        self.notes = []
        for g, speed in enumerate(self.groups):
            runs = [r for r in job.runs if r.kind not in ("slow_roll", "check")
                    and _group_of(r.speed, self.groups, r.label) == g]
            at = "" if math.isnan(speed) else f" at {speed * _RPM:.6g} rpm"
            ref, sensors = reference_sensors(runs, job.sensors, at)
            slow = [r for r in job.runs if r.kind == "slow_roll"
                    and (math.isnan(r.speed) or _group_of(r.speed, self.groups, r.label) == g)]
            own = [r for r in slow if not math.isnan(r.speed)]
            slow = own or slow
            if len(slow) > 1:
                raise ValueError(f"run: {len(slow)} slow-roll runs apply{at} "
                                 f"({', '.join(r.label for r in slow)}); give one per speed")
            known = [k for k, (w, _) in enumerate(job.influence)
                     if _group_of(w, self.groups, "influence") == g]
            if len(known) > 1:
                raise ValueError(f"influence: {len(known)} tables{at}; give one per speed")
            if known:
                ignored = [r for r in runs if r.kind == "trial"]
                if ignored:
                    self.notes.append(f"trial runs{at} ({', '.join(r.label for r in ignored)}) "
                                      f"not used: the influence matrix{at} is given")
                runs = [ref]
                m = job.influence[known[0]][1]
                sd = job.influence_std[known[0]] if job.influence_std else {}
                for s in sensors:
                    for p in job.planes:
                        if p not in m.get(s, {}):
                            raise ValueError(f"influence{at}: no coefficient of sensor {s} for "
                                             f"plane {p}")
                # the coefficients are inputs with their ± (a saved influence's), like readings
                Ak = np.array([[self._input(("A", g, s, p), m[s][p], sd.get(s, {}).get(p, 0.0))
                                for p in job.planes] for s in sensors])
            else:
                Ak = None
                M = np.array([[1.0] + list(self.added[r.index]) for r in runs], dtype=complex).T
                if len(runs) < P + 1 or np.linalg.matrix_rank(M) < P + 1:
                    moved = [p for j, p in enumerate(job.planes)
                             if any(self.added[r.index][j] != 0 for r in runs)]
                    lack = [p for p in job.planes if p not in moved] or job.planes
                    raise ValueError(f"run{at}: the trial runs do not separate plane(s) "
                                     f"{', '.join(lack)}: give one trial run per plane (or an "
                                     f"[[influence]] table / --influence FILE)")
            self.plan.append((speed, runs, sensors, slow[0] if slow else None, Ak))
        self.x = np.array(self.x, dtype=complex)
        self.sig = np.array(self.sig, dtype=float)
        self.rows = [(s, speed) for speed, _, sensors, _, _ in self.plan for s in sensors]
        if len(self.rows) < P:
            ref = [r for r in job.runs if r.kind == "reference"]
            miss = [s for s in job.sensors if not any(s in r.readings for r in ref)]
            raise ValueError(f"run: {len(self.rows)} reference reading(s) for {P} planes "
                             f"({', '.join(job.planes)}): underdetermined, infinitely many "
                             f"corrections fit" + (f"; give the reference run's reading of "
                                                   f"{', '.join(miss)}" if miss else
                                                   "; add a sensor"))
        self._check_trials()
        self.notes += _repeated(job)

    def _input(self, key, value, std) -> int:
        self.pos[key] = len(self.x)
        self.x.append(value)
        self.sig.append(std)
        return self.pos[key]

    def baselines(self, runs) -> list:
        """``[(trial run, the run before its trial)]``: the latest earlier run with the masses
        on the rotor but the trial's (the reference, or a trial run left on)."""
        out = []
        for r in runs:
            if r.kind != "trial":
                continue
            own = np.zeros(len(self.job.planes), dtype=complex)
            for p, t in r.trial.items():
                own[self.job.planes.index(p)] += t
            base = [b for b in runs if b.index < r.index
                    and np.allclose(self.added[b.index], self.added[r.index] - own)]
            if base:
                out.append((r, base[-1]))
        return out

    def _check_trials(self):
        """Refuse a trial run whose change from the run before its trial (the reference, or the
        trial run left on before it) is within 2 standard uncertainties at every sensor: its
        influence column would be noise (or zero)."""
        for speed, runs, sensors, _, Ak in self.plan:
            for r, b in self.baselines(runs) if Ak is None else ():
                d = np.array([abs(r.readings[s] - b.readings[s]) for s in sensors])
                u = np.array([math.hypot(r.std[s], b.std[s]) for s in sensors])
                if np.all(d <= 2.0 * math.sqrt(2.0) * u):
                    k = int(np.argmax(d))
                    raise ValueError(
                        f"{r.label}: trial {', '.join(r.trial)} had no measurable effect (largest "
                        f"change from {b.label}: {self.job.to_display(d[k]):.3g} "
                        f"{self.job.vibration_unit} at {sensors[k]}, within 2 standard "
                        f"uncertainties of the readings): trial mass too small, repeat the run "
                        f"with a larger one")

    def _added(self, x) -> dict:
        """Run index -> the trial masses on the rotor during it [kg, complex per plane]
        (a trial left on stays for the runs after it), from the trial entries of ``x``."""
        job = self.job
        on = np.zeros(len(job.planes), dtype=complex)
        added = {}
        for r in job.runs:
            w = on.copy()
            for p in r.trial:
                w[job.planes.index(p)] += x[self.pos[("trial", r.index, p)]]
            added[r.index] = w
            if r.kind in ("trial", "check") and not r.removed:
                on = w.copy()
        return added

    def matrices(self, x):
        """Stacked (A, V0) from the readings and trial masses ``x``."""
        added = self._added(x)
        A_all, V_all = [], []
        for speed, runs, sensors, slow, Ak in self.plan:
            sr = np.array([x[self.pos[(slow.index, s)]] if slow is not None
                           and (slow.index, s) in self.pos else 0.0 for s in sensors])
            D = np.array([[x[self.pos[(r.index, s)]] for r in runs] for s in sensors]) - sr[:, None]
            W = np.array([added[r.index] for r in runs], dtype=complex)          # K x P
            if Ak is None:
                M = np.vstack([np.ones(len(runs)), W.T])
                X = D @ np.linalg.pinv(M)
                V0, A = X[:, 0], X[:, 1:]
            else:
                A = x[Ak]
                V0 = (D - A @ W.T)[:, 0]          # the reference run alone
            A_all.append(A)
            V_all.append(V0)
        return np.vstack(A_all), np.concatenate(V_all)

    def solve(self, x, method):
        A, V0 = self.matrices(x)
        job = self.job
        lim = np.array([job.max_mass.get(p, math.inf) for p in job.planes])
        w = np.array([job.weight.get(s, 1.0) for s, _ in self.rows])
        caps = np.array([job.cap.get(s, math.inf) for s, _ in self.rows])
        if method == "min_max":
            U = min_max(A, V0, weights=w, caps=caps, max_mass=lim)
        else:
            U = least_squares(A, V0, weights=w if method == "weighted" else None, max_mass=lim)
        return A, V0, U


def _repeated(job: FieldJob) -> list:
    """Warnings for a sensor's reading written identically in several runs (a copied line?)."""
    out = []
    for s in job.sensors:
        seen = {}
        for r in job.runs:
            if s in r.readings:
                seen.setdefault(r.readings[s], []).append(r.label)
        out += [f"{s}: the same reading in {', '.join(labels)} (a copied reading? a trial "
                f"changes every sensor's vibration a little): check it" for labels in
                seen.values() if len(labels) > 1]
    return out


def _deg(z):
    return float(np.degrees(np.angle(z)) % 360.0)


def _vector(u, g, mf) -> dict:
    """A correction-like vector ``u`` [kg] with its first-order changes ``g`` (one per standard
    uncertainty of an input) -> mass (job unit), angle_deg and their standard uncertainties
    (along the vector and across it)."""
    a = abs(u)
    cov = np.vstack([g.real, g.imag]) @ np.vstack([g.real, g.imag]).T
    if a > 0:
        gr, gn = np.array([u.real, u.imag]) / a, np.array([-u.imag, u.real]) / (a * a)
        m_std = math.sqrt(max(float(gr @ cov @ gr), 0.0))
        a_std = math.degrees(math.sqrt(max(float(gn @ cov @ gn), 0.0)))
    else:
        m_std, a_std = math.sqrt(max(np.trace(cov) / 2, 0.0)), 180.0
    return {"mass": float(a / mf), "angle_deg": _deg(u), "mass_std": m_std / mf,
            "angle_std_deg": a_std}


def _perturbed(chain, f):
    """First-order propagation, one uncertain input at a time: for each reading (or known
    coefficient) ``k`` with ``sig > 0`` and each of its real and imaginary parts, yields
    ``(f(x + h u e_k), f(x - h u e_k), sig_k / 2h)`` -- the caller's central difference times that
    scale is the output's change per standard uncertainty of the input."""
    for k in np.flatnonzero(chain.sig > 0):
        for unit in (1.0, 1j):
            h = 1e-6 * max(abs(chain.x[k]), chain.sig[k])
            xp, xm = chain.x.copy(), chain.x.copy()
            xp[k] += unit * h
            xm[k] -= unit * h
            yield f(xp), f(xm), chain.sig[k] / (2 * h)


def balance_job(job, influence=None, method=None) -> FieldBalance:
    """Corrections of a field-balancing job.

    Parameters
    ----------
    job : str, path or FieldJob
        The job file (or a parsed :class:`~stand.analysis.field_job.FieldJob`).
    influence : str or path, optional
        A saved influence file (``--save-influence``) that replaces the job's influence.
    method : str, optional
        Overrides ``job.method`` ("least_squares", "weighted", "min_max").

    Returns
    -------
    FieldBalance
    """
    if not isinstance(job, FieldJob):
        job = read_job(job, influence)
    if job.amplitude_only:
        from .field_amplitude import balance_amplitude_only

        return _judged(job, balance_amplitude_only(job, method or job.method), [math.nan])
    method = method or job.method
    if not job.planes:
        raise ValueError("job: no correction plane (add [planes.P1] and a trial run per plane)")
    chain = _Chain(job)
    A, V0, U = chain.solve(chain.x, method)
    P = len(job.planes)
    J = np.zeros((0, P), dtype=complex)   # d corrections per standard uncertainty, n x P
    A_var = np.zeros(A.shape)             # pooled variance of each of Re and Im of A
    # ... of V0, and of the vibration the correction's uncertainty leaves on the machine (A dU)
    V_var, R_var = np.zeros(len(V0)), np.zeros(len(V0))
    if np.any(chain.sig > 0):
        J = []
        for (Ap, Vp, Up), (Am, Vm, Um), s in _perturbed(chain, lambda x: chain.solve(x, method)):
            J.append((Up - Um) * s)
            A_var += np.abs((Ap - Am) * s) ** 2 / 2.0
            V_var += np.abs((Vp - Vm) * s) ** 2 / 2.0
            R_var += np.abs(A @ (Up - Um) * s) ** 2 / 2.0
        J = np.array(J)
    mf = job.mass_factor
    corrections = {}
    for j, p in enumerate(job.planes):
        c = _vector(U[j], J[:, j], mf)
        if p in job.radius:
            c["radius_mm"] = job.radius[p] * 1e3
            c["unbalance_g_mm"] = abs(U[j]) * job.radius[p] * 1e6
        if p in job.max_mass:
            c["max_mass"] = job.max_mass[p] / mf
        if p in job.holes:
            c["holes"] = job.holes[p]
            c["split"] = [{"hole": k, "angle_deg": math.degrees(ang), "mass": m / mf}
                          for k, ang, m in split_onto_holes(U[j], job.holes[p])]
        if p in job.weights:
            placed, err = split_onto_weights(U[j] / mf, [w / mf for w in job.weights[p]],
                                             job.holes.get(p), max_pieces=job.max_pieces.get(p, 3))
            c["weights"] = {"placed": [{"hole": h, "angle_deg": math.degrees(ang), "mass": m,
                                        "pieces": list(pc)} for h, ang, m, pc in placed],
                            "error": err}
        corrections[p] = c
    R = V0 + A @ U

    def rdeg(z):                      # a vibration's angle in the readings' own convention
        return _deg(z if job.phase == "lead" else np.conj(z))

    residuals = []
    for i, (s, speed) in enumerate(chain.rows):
        r = {"sensor": s, "speed_rpm": None if math.isnan(speed) else speed * _RPM,
             "before": float(job.to_display(abs(V0[i]))), "before_deg": rdeg(V0[i]),
             "before_std": float(job.to_display(math.sqrt(V_var[i]))),
             "after": float(job.to_display(abs(R[i]))), "after_deg": rdeg(R[i]),
             "after_std": float(job.to_display(math.sqrt(R_var[i])))}
        if s in job.cap:
            r["max_vibration"] = float(job.to_display(job.cap[s]))
        residuals.append(r)
    scale = job.vib_factor * job.amp_factor / mf
    infl = [{"speed_rpm": None if math.isnan(speed) else speed * _RPM, "sensor": s, "plane": p,
             "amplitude": float(abs(A[i, j]) / scale), "angle_deg": _deg(A[i, j]),
             "std": float(math.sqrt(A_var[i, j]) / scale)}
            for i, (s, speed) in enumerate(chain.rows) for j, p in enumerate(job.planes)]
    multi = len(chain.plan) > 1
    names = [f"{s}@{speed * _RPM:.6g}rpm" if multi else s for s, speed in chain.rows]
    cond = conditioning(A, job.planes, names)
    if not math.isfinite(cond.condition):
        raise ValueError(f"influence matrix is singular (condition inf): plane(s) "
                         f"{', '.join(cond.planes)} have no effect distinct from the others' at "
                         f"the sensors; repeat their trial runs with a larger trial mass, or "
                         f"move a correction plane")
    # the ill-conditioned planes' corrections lost in their ± (2 sigma above the largest
    # correction: a plane needing almost none is not a reason to refuse)
    big = max(c["mass"] for c in corrections.values())
    vague = [p for p in cond.planes if corrections[p]["mass_std"] * 2.0 >= big]
    if cond.ill and vague:
        told = ", ".join(f"{p}: {corrections[p]['mass']:.3g} ± {corrections[p]['mass_std']:.2g} "
                         f"{job.mass_unit}" for p in vague)
        raise ValueError(f"influence matrix nearly singular (condition {cond.condition:.3g}): "
                         f"planes {', '.join(cond.planes)} act nearly alike and the readings do "
                         f"not determine the corrections ({told}): move a correction plane, "
                         f"use larger trial masses or add a sensor")
    warnings = ([cond.message()] if cond.ill else []) + chain.notes
    solver = "numpy lstsq"
    if method == "min_max" or any(corrections[p]["mass"] >= corrections[p].get("max_mass", math.inf)
                                  * (1 - 1e-9) for p in job.planes):
        solver = "cvxpy CLARABEL" if cvxpy_available() else "scipy SLSQP"
    doc = {"job": job.source, "influence_measured_by": job.influence_source or job.source,
           "method": method, "solver": solver, "phase": job.phase,
           "vibration_unit": job.vibration_unit, "amplitude": job.amplitude,
           "mass_unit": job.mass_unit,
           "corrections": corrections, "residuals": residuals,
           "worst_before": max(r["before"] for r in residuals),
           "worst_after": max(r["after"] for r in residuals),
           "influence": infl, "condition": cond.condition,
           "ill_conditioned": {"planes": list(cond.planes), "sensors": list(cond.sensors)},
           "warnings": warnings,
           "runs": [{"run": r.index, "kind": r.kind,
                     "speed_rpm": None if math.isnan(r.speed) else r.speed * _RPM,
                     "trial": {p: {"mass": abs(t) / mf, "angle_deg": _deg(t)}
                               for p, t in r.trial.items()}, "removed": r.removed,
                     "readings": {s: {"amplitude": float(job.to_display(abs(v))),
                                      "angle_deg": _deg(v if job.phase == "lead" else v.conjugate()),
                                      "std": float(job.to_display(r.std[s]))}
                                  for s, v in r.readings.items()}}
                    for r in job.runs]}
    if P == 2:                        # static part in both planes, couple part +-
        doc["static_couple"] = {"static": _vector((U[0] + U[1]) / 2, (J[:, 0] + J[:, 1]) / 2, mf),
                                "couple": _vector((U[0] - U[1]) / 2, (J[:, 0] - J[:, 1]) / 2, mf)}
    doc["check"] = _check_and_trim(job, chain, A, V0, method)
    doc["trial_validity"] = trial_validity(chain)
    doc["warnings"] += [f"{v['run']}: trial {', '.join(v['planes'])} changed the vibration by at "
                        f"most {v['amplitude_change_pct']:.3g} % and {v['phase_change_deg']:.3g} deg "
                        f"(rule: {TRIAL_RULE}): its influence is uncertain, repeat it with a larger "
                        f"trial mass" for v in doc["trial_validity"] if not v["valid"]]
    doc["trial_mass"] = trial_mass(job, chain.groups)
    return _judged(job, doc, chain.groups)


def _judged(job, doc, groups) -> FieldBalance:
    """The answer with its ISO 21940-11 grades and its verdict (:mod:`.field_verdict`) at the
    service speed (default: the highest run speed); a predicted vibration that is round-off
    (below 1e-9 of the largest before: as many readings as planes) is an exact 0 without angle."""
    doc["exactly_determined"] = _exact(doc["residuals"], "before", "after")
    if doc["exactly_determined"]:
        doc["worst_after"] = 0.0
    if doc.get("check"):
        _exact(doc["check"]["sensors"], "measured", "after_trim")
    w = job.service_speed if not math.isnan(job.service_speed) else max(
        (g for g in groups if not math.isnan(g)), default=math.nan)
    doc["iso"] = iso_grades(job, doc["corrections"], w)
    doc["verdict"] = field_verdict(job, doc, w)
    return FieldBalance(doc)


def _check_and_trim(job: FieldJob, chain, A, V0, method) -> dict | None:
    """The last ``check`` run (per speed): its measured vibration against the one predicted
    with the corrections installed, ``V0 + A C``, and the trim ``T`` that minimises the
    residual ``V_check + A T`` (the job's method; the influence of its trial runs or the given
    one, not updated with the check run); None without a check run."""
    last = []
    for g in range(len(chain.plan)):
        runs = [r for r in job.runs if r.kind == "check"
                and _group_of(r.speed, chain.groups, r.label) == g]
        last.append(runs[-1] if runs else None)
    if not any(last):
        return None
    if not all(last):
        at = [f"{e[0] * _RPM:.6g} rpm" for e, r in zip(chain.plan, last) if r is None]
        raise ValueError(f"run: no check run at {', '.join(at)}; give one at every speed")
    pc, C = [], chain.added[last[-1].index]       # positions in x of (check, slow roll)
    for (speed, _, sensors, slow, _), r in zip(chain.plan, last):
        miss = [s for s in sensors if s not in r.readings]
        if miss:
            raise ValueError(f"{r.label}.readings: no reading of {', '.join(miss)} (the "
                             f"reference run has them)")
        if not np.allclose(chain.added[r.index], C):
            raise ValueError(f"{r.label}.corrections: differ from {last[-1].label}'s; the check "
                             f"runs at the speeds must have the same masses on the rotor")
        pc += [(chain.pos[(r.index, s)], chain.pos.get((slow.index, s)) if slow else None)
               for s in sensors]
    w = np.array([job.weight.get(s, 1.0) for s, _ in chain.rows])
    caps = np.array([job.cap.get(s, math.inf) for s, _ in chain.rows])

    def trim(x):
        A_ = chain.matrices(x)[0]
        vc = np.array([x[i] - (x[k] if k is not None else 0.0) for i, k in pc])
        if method == "min_max":
            return vc, min_max(A_, vc, weights=w, caps=caps)
        return vc, least_squares(A_, vc, weights=w if method == "weighted" else None)

    Vc, T = trim(chain.x)
    var = np.zeros(len(T))       # first order, along each trim (as the corrections' mass_std)
    for Tp, Tm, s in _perturbed(chain, lambda x: trim(x)[1]):
        var += ((Tp - Tm) * s * np.exp(-1j * np.angle(T))).real ** 2
    pred, after, mf = V0 + A @ C, Vc + A @ T, job.mass_factor
    rdeg = (lambda z: _deg(z)) if job.phase == "lead" else (lambda z: _deg(np.conj(z)))
    disp = lambda z: float(job.to_display(abs(z)))  # noqa: E731
    return {"run": last[-1].index,
            "installed": {p: {"mass": abs(C[j]) / mf, "angle_deg": _deg(C[j])}
                          for j, p in enumerate(job.planes) if C[j] != 0},
            "sensors": [{"sensor": s, "speed_rpm": None if math.isnan(sp) else sp * _RPM,
                         "measured": disp(Vc[i]), "measured_deg": rdeg(Vc[i]),
                         "predicted": disp(pred[i]), "predicted_deg": rdeg(pred[i]),
                         "after_trim": disp(after[i]), "after_trim_deg": rdeg(after[i])}
                        for i, (s, sp) in enumerate(chain.rows)],
            "trim": {p: {"mass": abs(T[j]) / mf, "angle_deg": _deg(T[j]),
                         "mass_std": math.sqrt(var[j]) / mf}
                     for j, p in enumerate(job.planes)}}


def _exact(rows, ref, key) -> bool:
    """Predicted vibrations ``key`` all round-off (below 1e-9 of the largest ``ref``) are set to
    an exact 0 without angle; whether they were."""
    big = max(r[ref] for r in rows)
    exact = all(r[key] <= 1e-9 * big for r in rows)
    for r in rows if exact else ():
        r[key], r[f"{key}_deg"] = 0.0, None
    return exact
