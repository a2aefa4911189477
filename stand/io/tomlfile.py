"""One TOML reader for every input file (scenes, sweep specs, stress catalogues).

:func:`read_toml` reads a file (or takes TOML text) and parses it; every
problem is one line naming the file: not found, not readable, not UTF-8, or a
TOML syntax error with its line and column.
"""
from __future__ import annotations

from pathlib import Path
from typing import Type, Union

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

from stand.errors import SceneError

__all__ = ["read_toml", "tomllib"]


def read_toml(source: Union[str, Path], what: str = "scene file",
              error: Type[Exception] = SceneError) -> tuple:
    """Read and parse TOML.

    Parameters
    ----------
    source : str or pathlib.Path
        A path, or TOML text when it is a ``str`` holding a newline.
    what : str
        What the file is, for messages (``"scene file"``, ``"catalogue"``, ...).
    error : exception class
        Raised with the message (default :class:`stand.errors.SceneError`).

    Returns
    -------
    (data, text, label)
        The parsed document, the text, and ``"<path>: "`` (``""`` for text).
    """
    if isinstance(source, str) and "\n" in source:
        text, label = source, ""
    else:
        path = Path(source)
        label = f"{path}: "
        try:
            text = path.read_text(encoding="utf-8")
        except FileNotFoundError:
            raise error(f"cannot read {what} {path}: not found") from None
        except UnicodeDecodeError as exc:
            raise error(f"{label}not UTF-8 text ({exc.reason} at byte {exc.start})") from None
        except OSError as exc:
            raise error(f"cannot read {what} {path}: {exc.strerror or exc}") from None
    try:
        return tomllib.loads(text), text, label
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{label or '<string>: '}TOML syntax error: {exc}") from None
    except RecursionError:
        raise error(f"{label or '<string>: '}TOML nested too deeply (arrays or inline tables "
                    f"inside each other hundreds of levels deep): not a {what}") from None
