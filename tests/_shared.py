"""One expensive computation per test session, shared by pytest-xdist's workers.

``tests/conftest.py`` names a folder for the session (``$STAND_TEST_SHARED``, made by the
controller before its workers start; pytest-xdist's own recipe for a session fixture run
once); :func:`once` computes a value the first time a key is asked for, in whichever worker
asks first, and every later ask -- in any worker -- loads that value (pickled, under a lock:
a second worker asking meanwhile waits instead of computing it again).  Without the folder
(a plain ``pytest`` run of one file) it computes every time.
"""
from __future__ import annotations

import hashlib
import os
import pickle
from pathlib import Path
from typing import Callable

from stand.io.atomic import atomic_path
from stand.io.lock import file_lock

ENV = "STAND_TEST_SHARED"


def once(key: str, compute: Callable):
    """``compute()``, computed once per test session for ``key`` (module docstring); each
    caller gets its own copy (unpickled)."""
    folder = os.environ.get(ENV)
    if not folder or not Path(folder).is_dir():
        return compute()
    path = Path(folder) / (hashlib.sha1(key.encode()).hexdigest() + ".pkl")
    with file_lock(path.with_suffix(".lock")):
        if path.is_file():
            return pickle.loads(path.read_bytes())
        value = compute()
        with atomic_path(path, suffix=".pkl") as tmp:
            Path(tmp).write_bytes(pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL))
    return pickle.loads(path.read_bytes())
