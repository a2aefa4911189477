"""One executor for the stand's parallel work: a picklable function mapped over items
on a local process pool, in this process, or on a dask.distributed cluster.

Used by :mod:`stand.analysis.batch` (one recording per item) and :mod:`stand.sweep` (one
chunk of points per item)::

    with Executor(workers=4) as ex:                      # local process pool
        rows = ex.map(analyze_row, files, progress=True, errors="capture")
    with Executor(scheduler="tcp://host:8786") as ex:    # a Dask cluster
        for i, rows in ex.imap_unordered(compute, chunks, max_in_flight=8):
            ...

Where the work runs (``scheduler``):

* ``None``: a local :class:`concurrent.futures.ProcessPoolExecutor` with
  ``workers`` processes (default ``os.cpu_count()``); with one worker, or one
  item, the calls run in this process (no pool to start);
* ``"serial"``: in this process (debugging, profiling);
* an address ``"tcp://host:port"`` or a ``dask.distributed.Client``: that
  cluster (a client made from an address is closed with the executor).

Items are submitted lazily, at most ``max_in_flight`` at a time (default 2 x
workers), so a long list costs no memory and a kill loses only the calls in
flight.  With ``errors="capture"`` a call that raises gives an
:class:`ItemError` in its place and the others go on; with ``errors="raise"``
(default) the first failure is raised and the calls not started are cancelled.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Iterator, Optional

__all__ = ["Executor", "ItemError", "SERIAL", "error_text", "progress_bar", "default_start_method"]

#: the ``scheduler`` value that runs every call in this process
SERIAL = "serial"
#: longest error text kept in an :class:`ItemError` (and a result table's ``error`` column)
MAX_ERROR_CHARS = 2000


def error_text(exc: BaseException, limit: int = MAX_ERROR_CHARS) -> str:
    """``"TypeName: message"`` of an exception, cut to ``limit`` characters."""
    text = f"{type(exc).__name__}: {exc}"
    return text if len(text) <= limit else text[:limit - 3] + "..."


@dataclass(frozen=True)
class ItemError:
    """A call that raised, in place of its result (``errors="capture"``).

    Attributes
    ----------
    index : int
        Position of the item in the input.
    item : object
        The item itself.
    error : str
        ``"TypeName: message"`` (:func:`error_text`).
    """

    index: int
    item: Any
    error: str


def default_start_method() -> str:
    """Start method of the local pool: ``"fork"`` when this process has a single thread
    (fast start, and scripts need no ``if __name__ == "__main__"`` guard), else
    ``"spawn"`` (forking a process that holds other threads -- a Dask client, a
    progress-bar monitor -- can deadlock)."""
    import multiprocessing as mp
    import threading

    if "fork" in mp.get_all_start_methods() and threading.active_count() == 1:
        return "fork"
    return "spawn"


class _NoBar:
    """Stand-in for a progress bar when none is shown."""

    def update(self, n: int = 1) -> None:
        pass

    def close(self) -> None:
        pass


def progress_bar(total: int, *, enabled: bool = True, unit: str = "it", desc: Optional[str] = None,
                 **kwargs):
    """A tqdm bar on stderr (``update``/``close``), or a silent stand-in when ``enabled``
    is false, ``total`` is 0 or tqdm is not installed."""
    if enabled and total:
        try:
            from tqdm import tqdm
        except ImportError:
            return _NoBar()
        return tqdm(total=total, unit=unit, desc=desc, **kwargs)
    return _NoBar()


class Executor:
    """Map a picklable function over items here, on a local pool or on a Dask cluster.

    Parameters
    ----------
    workers : int, optional
        Local pool size (default ``os.cpu_count()``).  With Dask it is only
        reported by :attr:`workers` (default: the cluster's thread count), e.g.
        to size chunks.
    scheduler : None, "serial", str or dask.distributed.Client
        Where the calls run (module docstring).
    start_method : {"fork", "spawn", "forkserver"}, optional
        Start method of the local pool; default :func:`default_start_method` at
        construction ("spawn" and "forkserver" need the usual
        ``if __name__ == "__main__":`` guard in a calling script).

    Notes
    -----
    Use it as a context manager (or call :meth:`close`): the local pool is
    shut down, the calls not started are cancelled and a client made from an
    address is closed.
    """

    def __init__(self, workers: Optional[int] = None, scheduler: Any = None, *,
                 start_method: Optional[str] = None):
        if workers is not None and workers < 1:
            raise ValueError(f"workers = {workers}: must be >= 1")
        self._pool = None
        self._client = None
        self._own_client = False
        self._start = None
        if scheduler is None:
            self.mode = "local"
            self.workers = int(workers or os.cpu_count() or 1)
            self._start = start_method or default_start_method()
        elif isinstance(scheduler, str) and scheduler == SERIAL:
            self.mode, self.workers = SERIAL, 1
        else:
            from dask.distributed import Client

            self.mode = "dask"
            if isinstance(scheduler, str):
                self._client, self._own_client = Client(scheduler), True
            else:
                self._client = scheduler
            self.workers = int(workers or max(1, sum(self._client.nthreads().values())))

    # ------------------------------------------------------------ lifetime
    def __enter__(self) -> "Executor":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Shut the local pool down (cancelling what has not started); close an own client."""
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None
        if self._own_client and self._client is not None:
            self._client.close()
            self._client = None

    def _local_pool(self):
        if self._pool is None:
            import multiprocessing as mp
            from concurrent.futures import ProcessPoolExecutor

            self._pool = ProcessPoolExecutor(max_workers=self.workers,
                                             mp_context=mp.get_context(self._start))
        return self._pool

    # ------------------------------------------------------------ mapping
    def imap_unordered(self, func: Callable, items: Iterable, *, max_in_flight: Optional[int] = None,
                       errors: str = "raise", size_hint: Optional[int] = None
                       ) -> Iterator[tuple]:
        """``(index, func(item))`` for every item, as the calls finish.

        Parameters
        ----------
        func : callable
            A picklable function of one argument (a module-level function, or a
            :func:`functools.partial` of one).
        items : iterable
            Consumed lazily.
        max_in_flight : int, optional
            Calls submitted but not finished at any time (default 2 x workers).
        errors : {"raise", "capture"}
            A call that raises: raise it (and cancel the calls not started), or
            yield an :class:`ItemError` in its place and go on.
        size_hint : int, optional
            Number of items, when known: with one item the call runs in this
            process instead of starting a pool.

        Yields
        ------
        (int, object)
            The item's index and the call's result (or its :class:`ItemError`).
        """
        if errors not in ("raise", "capture"):
            raise ValueError(f'errors = {errors!r}: must be "raise" or "capture"')
        if self.mode == SERIAL or (self.mode == "local" and (self.workers == 1 or size_hint == 1)):
            yield from self._serial(func, items, errors)
        elif self.mode == "local":
            yield from self._pooled(func, items, max_in_flight or 2 * self.workers, errors)
        else:
            yield from self._dask(func, items, max_in_flight or 2 * self.workers, errors)

    def map(self, func: Callable, items: Iterable, *, progress: bool = False, unit: str = "item",
            desc: Optional[str] = None, max_in_flight: Optional[int] = None,
            errors: str = "raise") -> list:
        """``[func(item) for item in items]``, computed by :meth:`imap_unordered`, in
        the items' order; ``progress`` shows a bar counting the items."""
        items = list(items)
        out: list = [None] * len(items)
        bar = progress_bar(len(items), enabled=progress, unit=unit, desc=desc)
        try:
            for i, res in self.imap_unordered(func, items, max_in_flight=max_in_flight,
                                              errors=errors, size_hint=len(items)):
                out[i] = res
                bar.update(1)
        finally:
            bar.close()
        return out

    @staticmethod
    def _serial(func, items, errors):
        for i, item in enumerate(items):
            try:
                res = func(item)
            except Exception as exc:
                if errors == "raise":
                    raise
                res = ItemError(i, item, error_text(exc))
            yield i, res

    @staticmethod
    def _outcome(fut, i, item, errors):
        try:
            return fut.result()
        except Exception as exc:
            if errors == "raise":
                raise
            return ItemError(i, item, error_text(exc))

    def _pooled(self, func, items, limit, errors):
        from concurrent.futures import FIRST_COMPLETED, wait

        pool = self._local_pool()
        source = enumerate(items)
        running: dict = {}
        try:
            while True:
                for i, item in source:
                    running[pool.submit(func, item)] = (i, item)
                    if len(running) >= limit:
                        break
                if not running:
                    return
                finished, _ = wait(running, return_when=FIRST_COMPLETED)
                for fut in finished:
                    i, item = running.pop(fut)
                    yield i, self._outcome(fut, i, item, errors)
        finally:
            for fut in running:
                fut.cancel()

    def _dask(self, func, items, limit, errors):
        from dask.distributed import as_completed

        client = self._client
        source = enumerate(items)
        running: dict = {}

        def submit() -> list:
            for i, item in source:
                fut = client.submit(func, item, pure=False)
                running[fut] = (i, item)
                return [fut]
            return []

        pending = as_completed([f for _ in range(limit) for f in submit()])
        try:
            for fut in pending:
                i, item = running.pop(fut)
                for nxt in submit():
                    pending.add(nxt)
                yield i, self._outcome(fut, i, item, errors)
        finally:
            if running:
                client.cancel(list(running))
