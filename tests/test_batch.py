"""stand analyze on a folder / glob: parallel, one summary table, bad files reported in their row."""
import shutil

import pandas as pd
import pytest

from stand.analysis.batch import analyze_row, expand_sources, run_batch
from stand.cli.main import main

REC = "data_samples/recordings/stand_cameras.h5"


@pytest.fixture
def folder(tmp_path):
    d = tmp_path / "recs"
    d.mkdir()
    for k in range(3):
        shutil.copy(REC, d / f"run{k}.h5")
    (d / "broken.h5").write_bytes(b"not an hdf5 file")
    (d / "notes.txt").write_text("ignored")
    return d


def test_folder_summary_in_parallel(folder, tmp_path, capsys):
    out = tmp_path / "summary.csv"
    assert main(["analyze", str(folder), "-o", str(out), "--workers", "2"]) == 0
    assert "4 recordings analysed (1 failed)" in capsys.readouterr().out
    df = pd.read_csv(out)
    assert list(df["file"].map(lambda f: f.split("/")[-1])) == ["broken.h5", "run0.h5", "run1.h5", "run2.h5"]
    ok = df[df["status"] == "ok"]
    assert len(ok) == 3 and ok["unbalance_gmm"].nunique() == 1       # same recording, same answer
    assert "broken.h5" in df.loc[df["status"] == "error", "file"].iloc[0]
    single = analyze_row(REC)
    assert ok["unbalance_gmm"].iloc[0] == pytest.approx(single["unbalance_gmm"])


def test_glob_and_parquet(folder, tmp_path):
    out = tmp_path / "s.parquet"
    assert main(["analyze", str(folder / "run*.h5"), "-o", str(out), "--workers", "1"]) == 0
    assert len(pd.read_parquet(out)) == 3


def test_errors(tmp_path):
    assert main(["analyze", str(tmp_path / "*.h5"), "-o", str(tmp_path / "x.csv")]) == 2
    with pytest.raises(FileNotFoundError):
        expand_sources(str(tmp_path))


def test_dask_local_cluster(folder):
    from dask.distributed import LocalCluster

    # the distributed path (scheduler address, tasks and results through the scheduler) with an
    # in-process worker: the batch's rows pickled to and from worker processes are
    # test_folder_summary_in_parallel's (the process pool), the executor's Dask path with a worker
    # process is tests/test_sweep.py::test_simulate_sweep_200_points_on_dask_localcluster's; a
    # worker process of its own here cost ~2 s of start-up
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as lc:
        df = run_batch(expand_sources(str(folder / "run*.h5")), analyze_row, scheduler=lc.scheduler_address)
    assert (df["status"] == "ok").all() and len(df) == 3
