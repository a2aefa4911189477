"""The stand's input errors (imported by everything that validates input; imports nothing)."""

__all__ = ["SceneError", "NotApplicable"]


class SceneError(ValueError):
    """A scene (or another input table) is invalid.  The message names the key, the value
    and the unit."""


class NotApplicable(ValueError):
    """A command that does not apply to this scene or recording (e.g. a DAQ export of a
    run without probes); the CLI prints ``not applicable: <why>`` and succeeds."""
