"""The base every layer uses: files in and out and the shapes of answers.

* :mod:`.atomic`, :mod:`.lock`, :mod:`.guard` -- atomic writes, locks, resource guards;
* :mod:`.jsonable`, :mod:`.tomlfile` -- JSON out, TOML in;
* :mod:`.validate` -- the one checker of input numbers (messages name key, value, unit);
* :mod:`.units` -- the unit tables and the one parser of ``"<number> <unit>"`` strings;
* :mod:`.executor` -- the one process/thread pool;
* :mod:`.figures` -- figures without a plotting backend, saved atomically;
* :mod:`.result` -- the base of the result objects (``to_dict``, ``to_frame``, ``plot(ax=)``).
* :mod:`.numbers`, :mod:`.labels` -- the one formatter of a value with its ± and unit, and the one
  table of human names with units (CLI text, reports, figure labels).

``__version__`` is the package's version (``stand.__version__``), here so that every layer can
name it without importing the API.
"""
__version__ = "0.1.0"
