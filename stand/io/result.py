"""The one shape of every answer the stand gives: :class:`Result`.

Modelled on SciPy's ``OptimizeResult`` / ``OdeResult`` and python-control's
response objects: a result holds the JSON document the command line prints
(``stand analyze --json``, ``stand theory --json``, ``stand report --json``)
and gives it four faces:

* attribute access (``res.speed_hz``) and mapping access (``res["speed_hz"]``,
  ``res.get(...)``, ``json.dumps(res)``: a result is a ``dict``) to the same values;
* :meth:`Result.to_dict` -- the JSON document, plain types, the CLI's schema;
* :meth:`Result.to_frame` -- a pandas DataFrame: the document's numbers, one row
  per number (``to_frame()``), or one of its tables (``to_frame("components")``:
  a list of records in the document);
* :meth:`Result.plot` -- draws on a matplotlib Axes it is given (or on a new
  figure that belongs to no backend) and returns the Axes;

and a short ``repr`` (and ``_repr_html_`` for notebooks).  Subclasses name what the
document is (``_title``), the keys the JSON leaves out (``_json_exclude``) and the keys
``repr`` shows (``_summary_keys``) -- private names, so that they never hide a key of
the document -- and draw their own picture (``_draw``).

This module is a leaf: numpy, and pandas / matplotlib imported where used.
"""
from __future__ import annotations

import html
from typing import Any, Optional

__all__ = ["Result", "axes_of", "flatten_numbers", "renamed"]


def renamed(value, old_value, old: str, new: str, where: str):
    """``value``, or ``old_value`` (with a DeprecationWarning) when the caller still used the
    parameter's old name ``old`` (one name per parameter across the API, e.g. ``grade``)."""
    if old_value is None:
        return value
    import warnings

    warnings.warn(f"{where}: {old}= is deprecated, use {new}=", DeprecationWarning, stacklevel=3)
    return old_value


def axes_of(ax=None, **figure_kw):
    """``ax``, or the one Axes of a new figure that belongs to no backend and no pyplot
    state (:func:`stand.io.figures.figure_and_axes`): a library never calls ``matplotlib.use``."""
    from stand.io.figures import figure_and_axes

    return figure_and_axes(ax, **figure_kw)[1]


def flatten_numbers(doc: Any, prefix: str = "") -> list:
    """``[(dotted key, number)]`` of every int / float leaf of a JSON document (booleans and
    ``None`` left out); list items are addressed by their index (``components.0.amplitude_m``)."""
    out = []
    if isinstance(doc, dict):
        items = doc.items()
    elif isinstance(doc, list):
        items = enumerate(doc)
    else:
        if isinstance(doc, (int, float)) and not isinstance(doc, bool):
            out.append((prefix, doc))
        return out
    for k, v in items:
        out += flatten_numbers(v, f"{prefix}.{k}" if prefix else str(k))
    return out


def _is_table(v) -> bool:
    """A list of records, or a record of columns (lists of one length; ``None`` entries aside)."""
    if isinstance(v, list):
        return bool(v) and all(isinstance(r, dict) for r in v)
    if isinstance(v, dict):
        cols = [c for c in v.values() if c is not None]
        return bool(cols) and all(isinstance(c, list) for c in cols) \
            and len({len(c) for c in cols}) == 1
    return False


class Result(dict):
    """An answer of the stand: a JSON document with attribute access (module docstring).

    A ``dict`` (as SciPy's ``OptimizeResult``), so ``res["key"]``, ``json.dumps(res)`` and
    every mapping idiom keep working; the keys are also attributes.

    Parameters
    ----------
    doc : mapping
        The document (as the CLI prints it, plus any key of ``_json_exclude``).
    """

    #: what the document is (shown by ``repr``)
    _title = "result"
    #: keys held by the object but left out of :meth:`to_dict` (e.g. long timelines)
    _json_exclude: tuple = ()
    #: keys shown by ``repr`` (the first ones of the document when empty)
    _summary_keys: tuple = ()

    # ---------------------------------------------------------- attributes
    def __getattr__(self, name):
        if name.startswith("_"):      # private state is set in __init__; never the document
            raise AttributeError(name)
        try:
            return self[name]
        except KeyError:
            raise AttributeError(f"{type(self).__name__} has no attribute {name!r}; its keys: "
                                 f"{', '.join(map(str, self))}") from None

    def __setattr__(self, name, value) -> None:
        if name.startswith("_"):      # a subclass' own state, not part of the document
            object.__setattr__(self, name, value)
        else:
            self[name] = value

    def __delattr__(self, name) -> None:
        if name.startswith("_"):
            object.__delattr__(self, name)
        else:
            del self[name]

    def __dir__(self):
        return sorted(set(super().__dir__()) | {k for k in self if str(k).isidentifier()})

    # ---------------------------------------------------------- the document
    def to_dict(self) -> dict:
        """The JSON document (plain types, non-finite numbers as ``None``): what the command
        line prints with ``--json``."""
        from stand.io.jsonable import to_jsonable

        return to_jsonable({k: v for k, v in self.items() if k not in self._json_exclude})

    def to_json(self, **kwargs) -> str:
        """:meth:`to_dict` as strict JSON text (``json.dumps`` keywords, e.g. ``indent=2``)."""
        from stand.io.jsonable import dumps

        return dumps(self, **kwargs)

    def tables(self) -> list:
        """Dotted keys of the document's tables, for :meth:`to_frame`: lists of records, and
        records of equally long columns (e.g. a run-up's ``bode``)."""
        found = []

        def walk(d, prefix):
            for k, v in d.items():
                key = f"{prefix}{k}"
                if _is_table(v):
                    found.append(key)
                elif isinstance(v, dict):
                    walk(v, key + ".")

        walk(self.to_dict_all(), "")
        return found

    def to_dict_all(self) -> dict:
        """The whole document as plain types, the keys :meth:`to_dict` leaves out included."""
        from stand.io.jsonable import to_jsonable

        return to_jsonable(dict(self))

    def to_frame(self, table: Optional[str] = None):
        """A pandas DataFrame of the result.

        Parameters
        ----------
        table : str, optional
            Dotted key of a table of the document (:meth:`tables`, e.g. ``"components"``):
            one row per record.  Without it: every number of :meth:`to_dict`, one row each,
            columns ``key`` (dotted, units in the names) and ``value``.
        """
        import pandas as pd

        if table is None:
            rows = flatten_numbers(self.to_dict())
            return pd.DataFrame(rows, columns=["key", "value"])
        node: Any = self.to_dict_all()
        for part in table.split("."):
            if not isinstance(node, dict) or part not in node:
                raise KeyError(f"{type(self).__name__}: no table {table!r}; its tables: "
                               f"{', '.join(self.tables()) or 'none'}")
            node = node[part]
        if not _is_table(node):
            raise KeyError(f"{type(self).__name__}: {table!r} is not a table; its tables: "
                           f"{', '.join(self.tables()) or 'none'}")
        if isinstance(node, dict):
            return pd.DataFrame({k: v for k, v in node.items() if isinstance(v, list)})
        return pd.DataFrame.from_records(node)

    # ---------------------------------------------------------- the picture
    def plot(self, ax=None, kind: Optional[str] = None):
        """Draw the result on ``ax`` (a matplotlib Axes; default: a new backend-free figure)
        and return the Axes.

        ``kind`` names the picture where a result draws more than one (``Run``: ``"time"``,
        ``"orbit"``; docs/results.md); the others draw one picture (``kind=None``)."""
        if kind is not None:
            raise ValueError(f"{type(self).__name__}.plot: kind = {kind!r}: it draws one "
                             "picture (kind=None)")
        ax = axes_of(ax, figsize=(7, 4))
        self._draw(ax)
        return ax

    def _draw(self, ax) -> None:
        """The picture of a subclass; the base draws the document's numbers as bars."""
        rows = flatten_numbers(self.to_dict())[:30]
        ax.barh([k for k, _ in rows], [v for _, v in rows])
        ax.set_title(self._title)

    # ---------------------------------------------------------- notebooks
    def _summary(self) -> list:
        keys = self._summary_keys or tuple(self)[:6]
        out = []
        for k in keys:
            if k in self:
                v = self[k]
                text = f"{v:.6g}" if isinstance(v, float) else repr(v)
                out.append((k, text if len(text) <= 60 else text[:57] + "..."))
        return out

    def __repr__(self) -> str:
        body = ", ".join(f"{k}={v}" for k, v in self._summary())
        return f"{type(self).__name__}({body})"

    def _repr_html_(self) -> str:
        rows = "".join(f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
                       f"<td style='text-align:left'>{html.escape(v)}</td></tr>"
                       for k, v in self._summary())
        return (f"<b>{html.escape(type(self).__name__)}</b> ({html.escape(self._title)}; "
                f"{dict.__len__(self)} keys)<table>{rows}</table>")
