"""``[instruments.<name>]`` tables: each instrument's settings and where it is attached.

One reader for every scene form (:func:`instrument_tables`): the settings class of each
instrument (:data:`INSTRUMENTS`, found through :mod:`stand.model.registry`) validates its
own keys (``from_table``); ``plane`` / ``axial_position`` are taken out first and
checked against the scene's planes (:mod:`stand.scene.placement`).
"""
from __future__ import annotations

from stand.io.validate import _Table, _suggest
from stand.errors import SceneError

__all__ = ["INSTRUMENTS", "NAMED_INSTRUMENTS", "instrument_tables"]

#: [instruments.<name>] -> ("module:settings class" with ``from_table``, section) (stand.model.registry)
INSTRUMENTS = dict(
    screen=("stand.scene.screen_camera:ScreenCamera", "4.3.2"),
    stroboscope=("stand.scene.strobe_settings:Stroboscope", "4.3"),
    photogate=("stand.scene.gate_settings:PhotoGate", "4.3, FPM-09"),
    keyphasor=("stand.scene.probe_settings:Keyphasor", ""),
    tachometer=("stand.scene.probe_settings:Tachometer", ""),
    probes=("stand.scene.probe_settings:DisplacementProbes", ""),
)


def instrument_tables(t: _Table, planes=("balancer",), kind: str = "planar") -> dict:
    """Parse ``[instruments.<name>]`` tables with each instrument's own validator.

    Shared by every scene form: ``plane`` / ``axial_position`` (where the instrument
    is attached, :mod:`stand.scene.placement`) are taken out of each table and
    checked against the scene's ``planes`` and rotor ``kind``; the rest is the
    instrument's own settings.
    """
    from stand.scene.placement import attach, check_placement, split_placement
    from stand.model.registry import resolve

    out = {}
    for key, value in t.data.items():
        if key not in INSTRUMENTS:
            raise SceneError(f"unknown instrument [instruments.{key}]: {_suggest(key, INSTRUMENTS)}"
                             f"valid instruments: {', '.join(INSTRUMENTS)}")
        settings_cls = resolve(INSTRUMENTS, key, f"[instruments.{key}]", "instrument")
        for name, table in _named_instances(key, value, t.name(key)):
            table, where = split_placement(table, t.name(name))
            out[name] = attach(settings_cls.from_table(_Table(table, t.name(name))), where)
            check_placement(out[name], planes, kind)
    return out


#: instruments of which a scene may hold several named instances, ``[instruments.<type>.<name>]``
NAMED_INSTRUMENTS = ("screen",)


def _named_instances(key: str, value, path: str) -> list:
    """``[(instrument name, table)]`` of one ``[instruments.<key>]`` table.

    One instance (``[instruments.screen]``, name ``"screen"``), or -- for the types of
    :data:`NAMED_INSTRUMENTS` -- named instances ``[instruments.screen.front]``,
    ``[instruments.screen.rear]`` (names ``"screen.front"``, ``"screen.rear"``): the
    sub-tables; the keys of ``[instruments.screen]`` itself are then the settings they
    share (each sub-table overrides them).
    """
    if not isinstance(value, dict):
        return [(key, value)]
    subs = {k: v for k, v in value.items() if isinstance(v, dict)}
    if not subs:
        return [(key, value)]
    if key not in NAMED_INSTRUMENTS:
        k = next(iter(subs))
        raise SceneError(f"[{path}.{k}]: [instruments.{key}] takes no named sub-tables (only "
                         f"{', '.join(NAMED_INSTRUMENTS)} may have several named instances)")
    shared = {k: v for k, v in value.items() if k not in subs}
    if "plane" in shared or "axial_position" in shared:
        raise SceneError(f"[{path}]: plane / axial_position belong to each named instance "
                         f"([{path}.<name>]), not to the shared settings")
    out = []
    for name, sub in subs.items():
        if not name.isidentifier():
            raise SceneError(f"[{path}.{name}]: the instance name must be a plain identifier "
                             "(letters, digits, _)")
        out.append((f"{key}.{name}", {**shared, **sub}))
    return out
