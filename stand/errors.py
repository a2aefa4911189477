"""The stand's input errors and its work budget (imported by everything that validates
input or iterates; imports nothing)."""

__all__ = ["SceneError", "NotApplicable", "BudgetExceeded", "Budget"]


class SceneError(ValueError):
    """A scene (or another input table) is invalid.  The message names the key, the value
    and the unit."""


class NotApplicable(ValueError):
    """A command that does not apply to this scene or recording (e.g. a DAQ export of a
    run without probes); the CLI prints ``not applicable: <why>`` and succeeds."""


class BudgetExceeded(RuntimeError):
    """An iterative computation ran out of its work budget (issue 34: no input makes the
    stand hang).  The message says what ran out and the budget; the CLI prints it as one
    line and exits with 1 (the computation stopped early)."""


class Budget:
    """A count of work units (evaluations, steps, runs) that an iterative computation may
    spend; :meth:`spend` raises :class:`BudgetExceeded` once it is used up.

    Parameters
    ----------
    what : str
        The computation, as the message names it (e.g. ``"generalised criterion: bisection"``).
    limit : int
        Work units allowed.
    unit : str
        What one unit is (``"evaluations"``, ``"steps"``, ...).
    """

    def __init__(self, what: str, limit: int, unit: str = "evaluations"):
        self.what, self.limit, self.unit, self.used = what, int(limit), unit, 0

    def spend(self, n: int = 1) -> None:
        """Count ``n`` units; raise :class:`BudgetExceeded` beyond the limit."""
        self.used += n
        if self.used > self.limit:
            raise BudgetExceeded(f"{self.what} ran out of its budget of {self.limit} {self.unit} "
                                 "(the input is too ill-conditioned to resolve)")
