"""The virtual autobalancer test stand: scenes, physics, instruments, recordings.

The flat API (imported on first use, so ``import stand`` is cheap)::

    stand.load(path_or_text) -> Scene       stand.run(scene) -> Run
    stand.save(run, path) -> path           stand.read(path) -> Recording
    stand.theory(scene) -> Theory           stand.analyze(run | recording | path) -> Analysis
    stand.report(run | recording | path, html_path=...) -> Report
    stand.track(recording | video) -> Track stand.balance(job) -> FieldBalance
    stand.fit(scene, record, free=[...]) -> Fit

The answers are result objects (docs/results.md), all importable from here: attributes,
``to_dict()``, ``to_frame(table=None)``, ``plot(ax=None, kind=...)``.
"""
from stand.io import __version__

#: name -> the module (under stand) that defines it
_LAZY = {**dict.fromkeys(("load", "run", "save", "read", "theory", "analyze", "report", "track",
                          "balance", "fit"), "api"),
         "Scene": "scene.model", "SceneError": "scene.model",
         "Recording": "recording.hdf5", "RecordingError": "recording.hdf5",
         # the result objects
         "Result": "io.result", "Run": "integrate.result", "SolverStats": "integrate.result",
         "Theory": "theories.result", "Report": "reports.result", "Fit": "fitting.result",
         "FieldBalance": "analysis.field_balance",
         **dict.fromkeys(("Analysis", "TwoPlane", "Influence", "Track"), "analysis.results")}

__all__ = [*_LAZY, "__version__"]


def __getattr__(name):  # PEP 562: import the API on first use
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'stand' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_LAZY))
