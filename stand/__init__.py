"""The virtual autobalancer test stand: scenes, physics, instruments, recordings.

The flat API (imported on first use, so ``import stand`` is cheap)::

    stand.load(path_or_text) -> Scene       stand.run(scene) -> Run
    stand.read(path) -> Recording           stand.theory(scene) -> Theory
    stand.analyze(run | recording | path)   stand.report(run | recording | path, html_path=...)
    stand.track(recording | video)          stand.fit(scene, record, free=[...]) -> Fit

The answers are result objects (docs/results.md): attributes, ``to_dict()``,
``to_frame()``, ``plot(ax=)``.
"""
from stand.io import __version__

__all__ = ["load", "run", "read", "theory", "analyze", "report", "track", "balance", "fit", "Scene", "Run", "Recording",
           "SceneError", "RecordingError", "__version__"]

_LAZY = {"load": "api", "run": "api", "read": "api", "theory": "api", "analyze": "api",
         "report": "api", "track": "api", "balance": "api", "fit": "api", "Scene": "scene.model", "SceneError": "scene.model", "Run": "integrate.result",
         "Recording": "recording.hdf5", "RecordingError": "recording.hdf5"}


def __getattr__(name):  # PEP 562: import the API on first use
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'stand' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_LAZY))
