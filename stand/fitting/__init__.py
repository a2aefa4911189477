"""``stand fit``: a scene calibrated to a lab's recording (issue 39).

:func:`stand.fitting.solve.fit_scene` (``stand.fit`` in the flat API) adjusts the values a user
frees -- any numeric key of any scene file, by its dotted TOML path -- so that the simulation,
driven by the recorded rotor angle, reproduces the recorded channels; it returns a
:class:`stand.fitting.result.Fit` with each value's ± and identifiability, their correlations,
the fit's chi^2 and the theory-against-experiment comparison.  Modules, one idea each:
``paths`` (free values), ``record`` (the record and its drive), ``model_run`` (one
simulation), ``linear`` (the linear nuisance), ``objective`` (residuals, Jacobian),
``solve`` (starts, continuation, least squares), ``uncertainty`` (covariance, profile,
identifiability), ``compare`` (theory against experiment), ``result`` (:class:`Fit`).
"""
from stand.fitting.paths import FitError

__all__ = ["FitError"]
