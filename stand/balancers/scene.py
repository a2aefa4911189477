"""Scene files for the weight family: ``[weight_model]`` scenes.

The weights of chapters 6-7 and the liquid balancers are written in the
books' dimensionless forms (their own rotor models); a scene selects one and
gives its parameters by the names of the module's parameter dataclass::

    [scene]
    name = "abd"
    [weight_model]
    type = "damper"            # two_axis | gravity_pair | damper | liquid_float | liquid_chamber
    R_m = 0.05                 # the dataclass's fields (dimensionless, or SI for the liquids)
    R_omega = 3.0
    [run]                      # optional: stand run integrates the model
    duration = 200.0           # dimensionless time tau = omega_0 t (s for liquid_float)
    samples = 2001
    initial = [...]            # optional state vector (the module's documented layout)

``stand theory`` prints the model's steady motions (with stability), its
quasi-periodic motions or efficiency, or the closed-form run-up extrema;
``stand run`` integrates the model (scipy DOP853) and writes an HDF5 file with
``time``, ``state`` (columns named in the attribute ``columns``) and the
scene text.
"""
from __future__ import annotations

import dataclasses
import json
import math
import os
import tempfile
import tomllib
from pathlib import Path

import numpy as np

from ..scene import SceneError

__all__ = ["MODEL_TYPES", "load_weight_model", "is_weight_model_scene", "model_theory",
           "run_weight_model"]

MODEL_TYPES = {
    "two_axis": ("stand.balancers.two_axis", "TwoAxisParams", "ch. 6"),
    "gravity_pair": ("stand.balancers.gravity_pair", "GravityPairParams", "ch. 7.1"),
    "damper": ("stand.balancers.damper", "DamperParams", "ch. 7.2"),
    "liquid_float": ("stand.balancers.liquid_float", "LiquidFloatParams", "paper 001"),
    "liquid_chamber": ("stand.balancers.liquid_chamber", "LiquidChamberParams", "thesis 002"),
}
STATE_COLUMNS = {
    "two_axis": ["phi", "alpha", "x", "y", "phi'", "alpha'", "x'", "y'"],
    "gravity_pair": ["phi", "alpha", "x", "y", "phi'", "alpha'", "x'", "y'"],
    "damper": ["x", "y", "x'", "y'", "n_x", "n_y", "n_z", "W_x", "W_y", "W_z"],
    "liquid_float": ["xi [m]", "eta [m]", "xi' [m/s]", "eta' [m/s]"],
}


@dataclasses.dataclass(frozen=True)
class WeightModelScene:
    name: str
    kind: str
    params: object
    run: dict
    text: str = ""


def _module(kind):
    import importlib

    mod, cls, _ = MODEL_TYPES[kind]
    m = importlib.import_module(mod)
    return m, getattr(m, cls)


def is_weight_model_scene(path) -> bool:
    try:
        return "weight_model" in tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return False


def parse_weight_model(data, text="", stem="") -> WeightModelScene:
    for k in data:
        if k not in ("scene", "weight_model", "run"):
            raise SceneError(f"unknown table [{k}] in a weight-model scene; valid: scene, weight_model, run")
    if "weight_model" not in data:
        raise SceneError("missing table [weight_model]")
    wm = dict(data["weight_model"])
    kind = wm.pop("type", None)
    if kind not in MODEL_TYPES:
        raise SceneError(f"weight_model.type = {kind!r}: valid: {', '.join(MODEL_TYPES)}")
    _, cls = _module(kind)
    names = [f.name for f in dataclasses.fields(cls)]
    for k, v in wm.items():
        if k not in names:
            raise SceneError(f"weight_model.{k}: not a parameter of {kind}; valid: {', '.join(names)}")
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
            raise SceneError(f"weight_model.{k} = {v!r}: must be a finite number")
    try:
        params = cls(**{k: float(v) for k, v in wm.items()})
    except (TypeError, ValueError) as exc:
        raise SceneError(f"[weight_model] ({kind}): {exc}") from None
    run = dict(data.get("run", {}))
    for k in run:
        if k not in ("duration", "samples", "initial", "rtol"):
            raise SceneError(f"run.{k}: unknown; valid: duration, samples, initial, rtol")
    name = data.get("scene", {}).get("name", stem) if isinstance(data.get("scene"), dict) else stem
    return WeightModelScene(str(name), kind, params, run, text)


def load_weight_model(path) -> WeightModelScene:
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
        data = tomllib.loads(text)
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"{p}: not readable ({exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{p}: TOML syntax error: {exc}") from None
    try:
        return parse_weight_model(data, text, p.stem)
    except SceneError as exc:
        raise SceneError(f"{p}: {exc}") from None


def _plain(obj):
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_plain(v) for v in obj.tolist()]
    if isinstance(obj, (complex, np.complexfloating)):
        return {"re": float(obj.real), "im": float(obj.imag)}
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, (np.integer, np.bool_)):
        return obj.item()
    return obj


def model_theory(sc: WeightModelScene) -> dict:
    """Steady motions (with stability) and the model's characteristic numbers."""
    mod, _ = _module(sc.kind)
    out = {"scene": sc.name, "type": sc.kind, "source": MODEL_TYPES[sc.kind][2],
           "parameters": _plain(sc.params)}
    p = sc.params
    if sc.kind == "two_axis":
        from . import two_axis_theory as th

        out["steady_motions"] = [_plain(m) | {"stable": bool(m.stable)} for m in mod.steady_motions(p)]
        out["quasi_periodic"] = _plain(th.qp_motions(p))
    elif sc.kind == "gravity_pair":
        out["steady_motions"] = [_plain(m) | {"stable": bool(mod.is_stable(p, m))}
                                 for m in mod.steady_motions(p)]
        out["quasi_periodic_frequency"] = _plain(mod.qp_frequency(p))
        out["quasi_periodic_family_limit"] = _plain(mod.qp_family_limit(p))
    elif sc.kind == "damper":
        out["steady_motions"] = [_plain(m) | {"stable": bool(mod.is_stable(p, m))}
                                 for m in mod.steady_motions(p)]
        out["efficiency"] = _plain(mod.efficiency(p))
    elif sc.kind == "liquid_float":
        from .runup_closed_form import runup_extrema

        out["runup_extrema"] = _plain(runup_extrema(p))
    elif sc.kind == "liquid_chamber":
        w = float(sc.run.get("speed", p.critical_speed * 0.5))
        out["quasi_static_efficiency"] = _plain(mod.quasi_static_efficiency(p, w))
    return out


def _initial(sc: WeightModelScene):
    p = sc.params
    if "initial" in sc.run:
        y0 = np.asarray(sc.run["initial"], dtype=float)
        n = len(STATE_COLUMNS[sc.kind])
        if y0.shape != (n,) or not np.all(np.isfinite(y0)):
            raise SceneError(f"run.initial: {n} finite numbers ({', '.join(STATE_COLUMNS[sc.kind])})")
        return y0
    if sc.kind in ("two_axis", "gravity_pair"):   # weights slightly off neutral, turning with the rotor
        return np.array([0.3, 0.0, 0.0, 0.0, 0.0, p.R_omega, 0.0, 0.0])
    if sc.kind == "damper":
        from .damper import state_from_angles

        return state_from_angles(0.3, 0.0, p.R_omega, frame="fixed")
    if sc.kind == "liquid_float":
        from .liquid_float import initial_state

        return initial_state(p, frame="fixed")
    raise SceneError(f"stand run: {sc.kind} is a quasi-static model (use stand theory)")


def run_weight_model(sc: WeightModelScene):
    """Integrate the model; returns (t, states (k, n), stats dict)."""
    from scipy.integrate import solve_ivp

    mod, _ = _module(sc.kind)
    if sc.kind == "liquid_chamber":
        raise SceneError("stand run: liquid_chamber is a quasi-static model (use stand theory)")
    T = float(sc.run.get("duration", 100.0))
    k = int(sc.run.get("samples", 1001))
    if not (T > 0 and 2 <= k <= 10_000_000):
        raise SceneError(f"run.duration = {T!r} (> 0) and run.samples = {k!r} (2..1e7) required")
    y0 = _initial(sc)
    if sc.kind == "liquid_float":
        fun = mod.rhs_fixed(sc.params)
    else:
        fun = lambda t, y: mod.rhs(t, y, sc.params) if sc.kind != "two_axis" else mod.rhs_fixed(t, y, sc.params)  # noqa: E731
    t = np.linspace(0.0, T, k)
    sol = solve_ivp(fun, (0.0, T), y0, method="DOP853", t_eval=t, rtol=float(sc.run.get("rtol", 1e-9)),
                    atol=1e-12)
    stats = {"success": bool(sol.success), "message": sol.message, "nfev": int(sol.nfev)}
    return sol.t, sol.y.T, stats


def write_weight_model_recording(sc: WeightModelScene, t, states, stats, path) -> Path:
    import h5py

    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=str(path.resolve().parent), prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        with h5py.File(tmp, "w") as f:
            f.attrs["format"] = "autobalancer-stand weight-model recording 1"
            f.attrs["scene_text"] = sc.text
            f.attrs["model"] = sc.kind
            f.attrs["solver"] = json.dumps(stats)
            d = f.create_dataset("time", data=t)
            d.attrs["units"] = "s" if sc.kind == "liquid_float" else "tau = omega_0 t (dimensionless)"
            s = f.create_dataset("state", data=states)
            s.attrs["columns"] = json.dumps(STATE_COLUMNS[sc.kind])
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return path
