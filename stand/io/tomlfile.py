"""One TOML reader for every input file (scenes, sweep specs, stress catalogues).

:func:`read_toml` reads a file (or takes TOML text) and parses it; every
problem is one line naming the file: not found, not readable, not UTF-8, a
TOML syntax error with its line and column, or a file over the limits below.
The standard parser recurses once per level of nested arrays and inline tables,
so the size and the nesting depth are checked on the text *before* it is parsed
(strings and comments skipped), the parse is guarded, and the depth of the parsed
document (dotted keys and table headers nest too) is checked after it.
"""
from __future__ import annotations

import re
from pathlib import Path
from typing import Type, Union

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

from stand.errors import SceneError

__all__ = ["read_toml", "tomllib", "MAX_TOML_BYTES", "MAX_TOML_DEPTH"]

MAX_TOML_BYTES = 16 << 20    #: largest input TOML file [B] (a scene is a few kB)
MAX_TOML_DEPTH = 64          #: deepest nesting of tables and arrays (a scene has 4)
#: strings and comments, whose brackets do not nest
_NOT_BRACKETS = re.compile(r'"""[\s\S]*?"""|\'\'\'[\s\S]*?\'\'\'|"(?:\\.|[^"\\\n])*"'
                           r"|'[^'\n]*'|#[^\n]*")
_BRACKETS = re.compile(r"[\[\]{}]")
_DOTTED = re.compile(r"[\w-]+(?:[ \t]*\.[ \t]*[\w-]+)+")


def _text_depth(text: str) -> int:
    """Deepest nesting of ``[`` / ``{`` in TOML text outside strings and comments, or its
    longest dotted key (``a.b.c``: 3), whichever is deeper."""
    text = _NOT_BRACKETS.sub("", text)
    depth = deepest = 0
    for m in _BRACKETS.finditer(text):
        depth += 1 if m.group() in "[{" else -1
        deepest = max(deepest, depth)
    return max([deepest] + [m.group().count(".") + 1 for m in _DOTTED.finditer(text)])


def _data_depth(data) -> int:
    """Deepest nesting of dicts and lists in a parsed document, the document itself 0
    (iterative: no recursion)."""
    deepest, stack = 0, [(data, 0)]
    while stack:
        obj, d = stack.pop()
        deepest = max(deepest, d)
        if d <= MAX_TOML_DEPTH:
            stack.extend((v, d + 1) for v in (obj.values() if isinstance(obj, dict) else obj)
                         if isinstance(v, (dict, list)))
    return deepest


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
            size = path.stat().st_size
            if size > MAX_TOML_BYTES:
                raise error(f"{label}{size} bytes, over the limit of {MAX_TOML_BYTES} bytes for "
                            f"a {what}")
            text = path.read_text(encoding="utf-8")
        except FileNotFoundError:
            raise error(f"cannot read {what} {path}: not found") from None
        except UnicodeDecodeError as exc:
            raise error(f"{label}not UTF-8 text ({exc.reason} at byte {exc.start})") from None
        except OSError as exc:
            raise error(f"cannot read {what} {path}: {exc.strerror or exc}") from None
    name = label or "<string>: "
    if len(text) > MAX_TOML_BYTES:
        raise error(f"{name}{len(text)} characters, over the limit of {MAX_TOML_BYTES} for a {what}")
    depth = _text_depth(text)
    try:
        if depth <= MAX_TOML_DEPTH:
            data = tomllib.loads(text)
            depth = _data_depth(data)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{name}TOML syntax error: {exc}") from None
    except (RecursionError, MemoryError):     # a guard: the pre-scan should have caught it
        raise error(f"{name}tables or arrays nested too deeply to parse, over the limit of "
                    f"{MAX_TOML_DEPTH} levels: not a {what}") from None
    if depth > MAX_TOML_DEPTH:
        raise error(f"{name}tables or arrays nested too deeply: at least {depth} levels, over the "
                    f"limit of {MAX_TOML_DEPTH}: not a {what}")
    return data, text, label
