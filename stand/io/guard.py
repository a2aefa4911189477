"""Never lose what a user brought: outputs that would overwrite an input are refused.

Atomic writes (:mod:`stand.io.atomic`) protect an output from a crash; this
module protects the *inputs*.  Before a command does any work, every output
path it was given is resolved and compared with every input path:

* the same file (``os.path.samefile``: symbolic links, ``./`` and relative
  spellings, hard links) -> refused;
* an existing file of another kind than the command writes (``-o scene.toml``
  for an HDF5 recording, an HDF5 recording for an HTML report) -> refused
  unless ``--force``.

The refusal is one :class:`OutputRefused` (a ``ValueError``) line naming both paths.

:func:`memory_budget` is the one memory limit of every reader of a user's file (tables,
recordings, TOML): what it may take is checked against the shapes the file declares,
before any data is read.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Iterable, Optional

__all__ = ["OutputRefused", "check_outputs", "file_kind", "KINDS", "memory_budget"]

#: what each kind of output looks like: file endings, and a signature at the start
KINDS = {
    "hdf5": ((".h5", ".hdf5", ".hdf", ".nc"), b"\x89HDF\r\n\x1a\n"),
    "html": ((".html", ".htm"), None),
    "json": ((".json",), None),
    "csv": ((".csv", ".txt", ".tsv"), None),
    "parquet": ((".parquet", ".pq"), b"PAR1"),
    "png": ((".png",), b"\x89PNG\r\n\x1a\n"),
    "pdf": ((".pdf",), b"%PDF"),
    "npz": ((".npz",), b"PK\x03\x04"),
}
SIGNATURES = {sig: kind for kind, (_, sig) in KINDS.items() if sig}
#: endings of inputs a user writes by hand: never overwritten by another kind of file
SOURCES = (".toml", ".py", ".yaml", ".yml", ".ini", ".cfg", ".md", ".rst", ".mp4", ".avi",
           ".mov", ".mkv", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp")


class OutputRefused(ValueError):
    """An output path would destroy an input or a file of another kind."""


def file_kind(path: Path) -> Optional[str]:
    """The kind of an existing file: by its signature, else by its ending (None if unknown)."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(8)
    except OSError:
        head = b""
    for sig, kind in SIGNATURES.items():
        if head.startswith(sig):
            return kind
    suffix = path.suffix.lower()
    for kind, (endings, sig) in KINDS.items():
        if suffix in endings and sig is None:
            return kind
    return suffix.lstrip(".") or None


def _same(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.abspath(a) == os.path.abspath(b)


def check_outputs(inputs: Iterable, outputs: Iterable, force: bool = False) -> None:
    """Refuse outputs that are inputs, or existing files of another kind (module docstring).

    Parameters
    ----------
    inputs : iterable of path-like or None
        Files the command reads (None entries are skipped; globs and folders too).
    outputs : iterable of (path-like or None, kind)
        Files the command writes with the kind it writes (a key of :data:`KINDS`).
    force : bool
        Allow replacing an existing file of another kind (never an input).

    Raises
    ------
    OutputRefused
        One line naming the output, the input or the existing file, and why.
    """
    ins = [Path(p) for p in inputs if p is not None and Path(p).is_file()]
    for out, kind in outputs:
        if out is None:
            continue
        out = Path(out)
        for src in ins:
            if out.exists() and _same(out, src):
                raise OutputRefused(f"output {str(out)!r} is the input {str(src)!r}: refusing to "
                                    f"overwrite what the command reads; choose another output")
        if not out.is_file():
            continue
        have = file_kind(out)
        if have == kind:
            continue
        if out.suffix.lower() in SOURCES:
            raise OutputRefused(f"output {str(out)!r} exists and is a {out.suffix} file, not "
                                f"{kind}: refusing to replace a source file; choose another output")
        if not force:
            raise OutputRefused(f"output {str(out)!r} exists and holds {have or 'unknown'} data, "
                                f"not {kind}: give --force to replace it, or choose another output")


def memory_budget() -> float:
    """Bytes one input file may take while it is read [B]: a quarter of the physical memory
    (8 GiB where the system does not say)."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 4
    except (ValueError, OSError, AttributeError):
        return 2.0 ** 33 / 4
