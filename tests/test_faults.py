"""Faults: a full disk, a read-only output folder, kill -9 of a batch report.

Every output is written atomically (stand.io.atomic): a failure leaves no partial
file under the final name and the previous output intact; the command ends with
exit 2 and one line naming the output.  (kill -9 and resume of ``stand run
--checkpoint`` and ``stand sweep``: tests/test_checkpoint.py, tests/test_sweep.py.)
"""
from __future__ import annotations

import hashlib
import io
import os
from contextlib import contextmanager
import resource
import shutil
import signal
import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pandas as pd
import pytest

from _helpers import wait_for

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"


def _stand_here(*argv) -> int:
    """``stand <argv>`` in this process (the command's own code, without a Python start);
    only the kill -9 below needs a process of its own."""
    from stand.cli.main import main

    with redirect_stdout(io.StringIO()), redirect_stderr(io.StringIO()):
        return main([str(a) for a in argv])


def _stand_err(*argv) -> tuple:
    """``stand <argv>`` in this process: (exit code, stderr)."""
    from stand.cli.main import main

    err = io.StringIO()
    with redirect_stdout(io.StringIO()), redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, err.getvalue()


@contextmanager
def _file_size_limit(limit_bytes: int):
    """A full disk, as this process sees it: writes past ``limit_bytes`` of a file fail with
    EFBIG ("File too large"; SIGXFSZ ignored).  Only the soft limit is lowered, and put back
    when the block ends."""
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    old = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
        signal.signal(signal.SIGXFSZ, old)


def _digest(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


def _short_scene(tmp_path, duration: float = 4.0) -> Path:
    p = tmp_path / "scene.toml"
    p.write_text((SCENES / "no_balancer.toml").read_text().replace("duration = 40.0",
                                                                   f"duration = {duration}"))
    return p


def _leftovers(folder: Path) -> list:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(".") and "tmp" in p.name)


@pytest.mark.parametrize("command", ["run", "report"])
def test_full_disk_keeps_the_previous_output(tmp_path, command):
    # the report of a 1-s run (as the kill test's: its HTML still far over the 20-kB limit)
    scene = _short_scene(tmp_path, duration=1.0 if command == "report" else 4.0)
    rec = tmp_path / "run.h5"
    assert _stand_here("run", scene, "-o", rec) == 0
    if command == "run":
        out = tmp_path / "old.h5"
        shutil.copy(rec, out)
        argv = ("run", scene, "-o", out)
    else:
        # the previous output: any file under the name (atomic replacement does not read it;
        # a report of its own here cost a second report's figures, ~3 s)
        out = tmp_path / "report.html"
        out.write_text("<!DOCTYPE html>\n<html><body>the previous report</body></html>\n")
        argv = ("report", rec, "-o", out)
    before = _digest(out)
    with _file_size_limit(20_000):
        code, err = _stand_err(*argv)
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "File too large" in lines[0] and str(out) in lines[0], err
    assert _digest(out) == before
    assert _leftovers(tmp_path) == []


def _make_read_only(folder: Path):
    """chattr +i as root (root ignores permissions), chmod 555 otherwise; None if impossible."""
    if os.geteuid() == 0:
        if shutil.which("chattr") is None or subprocess.run(["chattr", "+i", str(folder)],
                                                            capture_output=True).returncode:
            return None
        return lambda: subprocess.run(["chattr", "-i", str(folder)], check=False)
    folder.chmod(0o555)
    return lambda: folder.chmod(0o755)


def test_read_only_output_folder_is_a_clear_error(tmp_path):
    scene = _short_scene(tmp_path)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    out = out_dir / "run.h5"
    assert _stand_here("run", scene, "-o", out) == 0
    before = _digest(out)
    undo = _make_read_only(out_dir)
    if undo is None:
        pytest.skip("cannot make a folder read-only here (root without chattr)")
    try:
        code, err = _stand_err("run", scene, "-o", out)
    finally:
        undo()
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and str(out) in lines[0], err
    assert "not permitted" in lines[0] or "Permission denied" in lines[0], err
    assert _digest(out) == before and _leftovers(out_dir) == []


def test_batch_report_killed_then_rerun_equals_an_uninterrupted_run(tmp_path):
    scene = _short_scene(tmp_path, duration=1.0)   # 1 s, not 4 s: a cheaper report
    recs = tmp_path / "recs"
    recs.mkdir()
    # two recordings: the killed run stops after the first report (polled every 50 ms; the
    # second report, ~1-2 s of CPU, mostly its figures, comes before the summary): one left to
    # resume (a third recording cost ~2.4 s of CPU over the clean run and the rerun)
    for k in range(2):
        assert _stand_here("run", scene, "-o", recs / f"r{k}.h5") == 0
    clean_dir, killed_dir = tmp_path / "clean", tmp_path / "killed"
    clean_dir.mkdir()
    killed_dir.mkdir()
    # the uninterrupted reference; the killed report and its rerun are processes of their own
    assert _stand_here("report", recs, "-o", clean_dir, "--summary", clean_dir / "s.csv",
                       "--workers", "1") == 0
    proc = subprocess.Popen([sys.executable, "-m", "stand", "report", str(recs), "-o", str(killed_dir),
                             "--summary", str(killed_dir / "s.csv"), "--workers", "1"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    wait_for(lambda: any(killed_dir.glob("*.html")), proc, timeout_s=120)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    # nothing partial under a final name: every HTML there is complete, no summary yet
    for html in killed_dir.glob("*.html"):
        assert html.read_text().rstrip().endswith("</html>")
    assert not (killed_dir / "s.csv").exists()
    # the rerun: the command's own code, in this process
    assert _stand_here("report", recs, "-o", killed_dir, "--summary", killed_dir / "s.csv",
                       "--workers", "1") == 0
    a = pd.read_csv(clean_dir / "s.csv").drop(columns=["report"])
    b = pd.read_csv(killed_dir / "s.csv").drop(columns=["report"])
    pd.testing.assert_frame_equal(a, b)
    assert sorted(p.name for p in killed_dir.glob("*.html")) == \
        sorted(p.name for p in clean_dir.glob("*.html"))
