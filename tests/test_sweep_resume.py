"""``stand sweep`` says when it resumes from an earlier run's parts, and ``--fresh``
starts over (issue 21, item 4)."""
import argparse

import numpy as np
import pytest

import stand.sweep.run as sweep_run
from stand.cli.sweep import add_sweep_arguments, sweep_main
from stand.sweep import parts_dir, read_results

from _helpers import toml_text

# 3 speeds x 2 unbalances of a two-ball dimensionless rotor, theory only: about 0.1 s
SPEC = toml_text(
    base__dimensionless=dict(n=2, Rt=0.01, h=0.3, H=0.3, e0=0.5, initial_angles=[150.0, 210.0]),
    base__drive=dict(type="speed", programme_dimensionless=[[0.0, 3.0]]),
    base__run=dict(duration=30.0, sample_rate=5.0),
    sweep=dict(compute=["theory"], chunk_size=2),
    axis=[dict(key="R_omega", values=[2.0, 3.0, 4.0]), dict(key="e0", values=[0.3, 0.5])])
N = 6


@pytest.fixture
def computed(monkeypatch):
    """The point ids that reach the per-point work, in this process (``--scheduler serial``)."""
    seen = []
    real = sweep_run.compute_chunk

    def counting(payload, indices, ids, points):
        seen.extend(ids)
        return real(payload, indices, ids, points)

    monkeypatch.setattr(sweep_run, "compute_chunk", counting)
    return seen


def _sweep(tmp_path, capsys, *extra):
    """Run ``stand sweep`` on SPEC; returns (exit code, stderr)."""
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC)
    p = argparse.ArgumentParser()
    add_sweep_arguments(p)
    capsys.readouterr()
    code = sweep_main(p.parse_args([str(spec), "-o", str(tmp_path / "r.parquet"), "--scheduler",
                                    "serial", "--no-progress", *extra]))
    return code, capsys.readouterr().err


def test_resume_says_so_and_skips_done_points(tmp_path, capsys, computed):
    out, pdir = tmp_path / "r.parquet", parts_dir(tmp_path / "r.parquet")
    code, err = _sweep(tmp_path, capsys)
    assert code == 0 and err == ""                        # a first run has nothing to say
    assert len(computed) == N
    first = read_results(out).set_index("point_id")["wall_time_s"]
    parts = sorted(pdir.glob("part-*.parquet"))
    assert len(parts) == 3                                # chunk_size = 2
    parts[0].unlink()                                     # as if killed after two chunks

    computed.clear()
    code, err = _sweep(tmp_path, capsys)
    assert code == 0
    assert err == (f"stand sweep: resuming: 4 of 6 points already done in {pdir}/ "
                   "\u2014 use --fresh to recompute\n")
    assert len(computed) == 2                             # only the deleted chunk's points
    again = read_results(out).set_index("point_id")["wall_time_s"]
    kept = [i for i in first.index if i not in computed]
    assert len(kept) == 4
    np.testing.assert_array_equal(again[kept].to_numpy(), first[kept].to_numpy())


def test_missing_output_is_reported_then_resumed(tmp_path, capsys, computed):
    out, pdir = tmp_path / "r.parquet", parts_dir(tmp_path / "r.parquet")
    _sweep(tmp_path, capsys)
    table = read_results(out)
    out.unlink()
    computed.clear()
    code, err = _sweep(tmp_path, capsys)
    assert code == 0
    assert err == (f"stand sweep: {out} is missing; resuming from 6 of 6 points in {pdir}/ "
                   "\u2014 use --fresh to recompute\n")
    assert computed == []                                 # nothing recomputed, but said so
    assert out.exists()
    np.testing.assert_array_equal(read_results(out)["wall_time_s"], table["wall_time_s"])


def test_fresh_recomputes_every_point_and_leaves_no_stale_parts(tmp_path, capsys, computed):
    out, pdir = tmp_path / "r.parquet", parts_dir(tmp_path / "r.parquet")
    _sweep(tmp_path, capsys)
    old_parts = set(pdir.glob("part-*.parquet"))
    stray = pdir / ".part-000000000-dead.parquet.x1y2.tmp"   # a kill's leftover temporary
    stray.write_bytes(b"half")
    mine = pdir / "notes.txt"                                 # not the stand's: stays
    mine.write_text("keep me")
    computed.clear()

    code, err = _sweep(tmp_path, capsys, "--fresh")
    assert code == 0 and err == ""                            # nothing resumed, nothing said
    assert sorted(computed) == sorted(read_results(out)["point_id"])
    assert len(set(computed)) == N
    now = set(pdir.glob("part-*.parquet"))
    assert len(now) == 3 and not now & old_parts              # only this run's parts
    assert not stray.exists() and mine.read_text() == "keep me"


def test_library_fresh_and_log(tmp_path, computed):
    """run_sweep(fresh=...) and its ``log`` line; table.attrs counts the reused points."""
    spec, out = tmp_path / "s.toml", tmp_path / "lib.parquet"
    spec.write_text(SPEC)
    lines = []
    t1 = sweep_run.run_sweep(spec, out, scheduler="serial", progress=False, log=lines.append)
    t2 = sweep_run.run_sweep(spec, out, scheduler="serial", progress=False, log=lines.append)
    assert lines == [f"resuming: 6 of 6 points already done in {parts_dir(out)}/ "
                     "\u2014 use --fresh to recompute"]
    assert (t1.attrs["resumed_points"], t2.attrs["resumed_points"]) == (0, 6)
    assert len(computed) == N
    t3 = sweep_run.run_sweep(spec, out, scheduler="serial", progress=False, fresh=True,
                             log=lines.append)
    assert len(lines) == 1 and t3.attrs["resumed_points"] == 0 and len(computed) == 2 * N
    # parts of another sweep (other base scene) are named, not silently ignored
    spec.write_text(SPEC.replace("h = 0.3", "h = 0.4"))
    sweep_run.run_sweep(spec, out, scheduler="serial", progress=False, log=lines.append)
    assert lines[1] == (f"{parts_dir(out)}/ holds 6 results of another sweep (other base scene, "
                        "options or axes): ignored, computing all 6 points \u2014 use --fresh "
                        "to delete them")
