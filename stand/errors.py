"""The stand's input errors (imported by everything that validates input; imports nothing)."""

__all__ = ["SceneError"]


class SceneError(ValueError):
    """A scene (or another input table) is invalid.  The message names the key, the value
    and the unit."""
