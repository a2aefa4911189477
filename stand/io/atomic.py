"""Atomic file writes: a temporary file in the target's directory, then ``os.replace``.

Every file the stand writes (recordings, reports, tables, checkpoints, images)
goes through :func:`atomic_path`: the content is written to a temporary file
beside the target, flushed to disk, given the permissions a new file would
have (the old target's, else 0666 minus the umask), then renamed onto the
target.  If anything fails the temporary file is removed and an existing
target is left untouched; no reader ever sees a partial file under the final
name.
"""
from __future__ import annotations

import os
import stat
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Union

__all__ = ["atomic_path", "write_text", "write_bytes", "new_file_mode", "check_output_path"]

PathLike = Union[str, os.PathLike]


def new_file_mode(target: Path) -> int:
    """Permissions for the new file: the old target's, else 0o666 minus the umask."""
    try:
        return stat.S_IMODE(Path(target).stat().st_mode)
    except OSError:
        pass
    try:  # Linux: read the umask without changing it
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return 0o666 & ~int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


def check_output_path(path: PathLike, what: str = "output") -> Path:
    """Check that ``path`` can receive a file, before any work is done.

    Raises
    ------
    FileNotFoundError
        The directory does not exist (named in the message).
    IsADirectoryError, ValueError
        ``path`` is a directory, or exists and is not a regular file (a device
        such as /dev/null, a fifo, a symbolic link): the atomic rename would
        replace it, so it is refused.
    """
    path = Path(path)
    directory = path.parent
    if not directory.is_dir():
        raise FileNotFoundError(2, f"cannot write {what} {path}: directory does not exist",
                                str(directory))
    if path.is_dir():
        raise IsADirectoryError(21, f"cannot write {what}: {path} is a directory", str(path))
    if os.path.lexists(path) and (path.is_symlink() or not path.is_file()):
        raise ValueError(f"cannot write {what} {path}: it exists and is not a regular file "
                         "(device, fifo or symbolic link); the atomic rename would replace it")
    return path


def _fsync(path: str) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


@contextmanager
def atomic_path(path: PathLike, suffix: str = ".tmp") -> Iterator[str]:
    """Yield a temporary path beside ``path``; on a clean exit it replaces ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        The final file.  Its directory must exist.
    suffix : str
        Ending of the temporary name (e.g. ``".h5.tmp"``, ``".png"`` when a
        library picks the format from the name).

    Examples
    --------
    >>> with atomic_path("table.csv") as tmp:      # doctest: +SKIP
    ...     df.to_csv(tmp, index=False)
    """
    path = check_output_path(path)
    mode = new_file_mode(path)
    fd, tmp = tempfile.mkstemp(dir=str(path.resolve().parent), prefix=f".{path.name}.",
                               suffix=suffix)
    os.close(fd)
    try:
        yield tmp
        _fsync(tmp)
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise


def write_text(path: PathLike, text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically; returns the path."""
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding=encoding) as fh:
            fh.write(text)
    return Path(path)


def write_bytes(path: PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; returns the path."""
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(data)
    return Path(path)
