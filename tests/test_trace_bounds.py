"""`stand track --trace` with the rings and the capacity: a circle flagged "unresolved"
(radius below 3 spot sigmas: not separable from the spot) gives no unbalance, only an upper
bound; a resolved circle keeps its reading.  Frames drawn with a known circle
(vision.artificial)."""
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from stand.analysis.trace_reading import trace_ring_columns
from vision import artificial as art
from vision.trace import UNRESOLVED_SIGMAS, track_traces

SCALE = 1e-4                                   # m of screen per px (0.1 mm/px)
RINGS = 0.5e-3 * np.arange(21)                 # ring i at 0.5 i mm: zone i -> i S/16
S_GMM = 7200.0                                 # g mm: S/16 = 450 g mm per 0.5 mm


def _frames(R_px, peak, n=3, seed=0):
    """n frames of a spot (sigma 2 px) drawing 3 turns of a circle of R_px px."""
    cam = art.Camera(width=200, height=200, sigma_px=2.0, peak=peak)
    rng = np.random.default_rng(seed)
    pos = [art.orbit_positions(np.array([100.0, 100.0]) + rng.uniform(-2, 2, 2), R_px, 4000,
                               turns=3, phase=rng.uniform(0, 2 * np.pi)) for _ in range(n)]
    return list(art.spot_frames(pos, cam, seed=seed))


def _table(R_px, peak):
    df = track_traces(_frames(R_px, peak))
    trace_ring_columns(df, SCALE, 0.0, RINGS, S_GMM)
    return df


def test_unresolved_tiny_circle_is_only_a_bound():
    # R = 1 px with a 2 px spot, saturated as the stand_cameras frames: before the fix the table
    # said unbalance_gmm = the ring reading of the fitted 3.6 px (~330 g mm) as if measured
    df = _table(1.0, 4000.0)
    assert df["ok"].all()
    assert all({"unresolved", "saturated"} <= set(f.split(",")) for f in df["flags"])
    assert df["unbalance_gmm"].isna().all() and df["radius_mm"].isna().all()
    assert (df["zone"] == -1).all()
    # the bound: 3 spot sigmas on the screen, read against the rings (0.5 mm per S/16)
    r_max = UNRESOLVED_SIGMAS * df["spot_sigma_px"] * SCALE
    np.testing.assert_allclose(df["radius_max_mm"], r_max * 1e3, rtol=1e-12)
    np.testing.assert_allclose(df["unbalance_max_gmm"], r_max / 0.5e-3 * S_GMM / 16, rtol=1e-9)
    # and it is a bound: above the true circle's reading (1 px = 0.1 mm -> 90 g mm)
    assert (df["unbalance_max_gmm"] > 0.1 / 0.5 * S_GMM / 16).all()


def test_resolved_circle_keeps_its_reading():
    # R = 40 px = 4 mm = ring 8: 8 S/16 = 3600 g mm; spread over the ring: unsaturated, resolved
    df = _table(40.0, 4000.0)
    assert df["ok"].all() and (df["flags"].fillna("") == "").all()
    assert df["unbalance_max_gmm"].isna().all() and df["radius_max_mm"].isna().all()
    assert df["zone"].isin([7, 8]).all()
    # the reading of the fitted radius, within 3 sigma of its pixel-noise std (+1e-9 rounding)
    sU = df["radius_std_mm"] / 0.5 * S_GMM / 16
    assert (df["unbalance_gmm"] - 3600.0).abs().le(3 * sU + 1e-9).all()
    np.testing.assert_allclose(df["unbalance_gmm"], df["radius_mm"] / 0.5 * S_GMM / 16, rtol=1e-12)


def test_stand_track_on_stand_cameras_says_how_many_frames_are_bounds(tmp_path, capsys):
    from stand.cli.main import main
    import stand

    root = Path(__file__).resolve().parents[1]
    rec, out = tmp_path / "c.h5", tmp_path / "t.csv"
    assert main(["run", str(root / "data_samples" / "scenes" / "stand_cameras.toml"),
                 "-o", str(rec)]) == 0
    capsys.readouterr()
    assert main(["track", str(rec), "--trace", "--calibration", str(rec), "--capacity", "7200",
                 "-o", str(out)]) == 0
    text = capsys.readouterr().out
    df = pd.read_csv(out, comment="#")
    bound = df["flags"].fillna("").str.contains("unresolved")
    # the balanced stand: the settled frames are a still (saturated) spot, R < 3 sigma
    assert bound.sum() >= 20
    assert f"; {int(bound.sum())} unresolved: no radius, only an upper bound" in text
    assert df.loc[bound, "unbalance_gmm"].isna().all()
    assert (df.loc[bound, "unbalance_max_gmm"] > 0).all()
    assert df.loc[~bound & df["ok"], "unbalance_gmm"].notna().all()
    # stand analyze of the table reads the settled frames as a person reads the screen: they
    # are bounds, so no unbalance -- neither the bounds nor the mean of the balancing
    # transient's resolved circles (3135 g mm) -- and the bound of the settled frames in a note
    a = stand.analyze(str(out))
    assert a.get("unbalance_gmm") is None
    tail = df.index[df.index > df.index[~bound & df["ok"]].max()]          # the settled frames
    (note,) = [n for n in a.to_dict()["notes"] if n.startswith("ring reading")]
    assert f"the last {len(tail)} circles are unresolved" in note
    assert f"below {df.loc[tail, 'unbalance_max_gmm'].max():.4g} g·mm" in note


def _trace_csv(path, radii_mm, stds_mm, flags=None, scale_rel=1e-3):
    """A trace table as `stand track --trace` writes it (the columns settled_circles reads)."""
    n = len(radii_mm)
    flags = flags or [""] * n
    rows = [f"{k},{0.5 * k},100,100,{r / 0.1},0.01,2.0,{f},True,0.0,0.0,{r},{s},,5,{700.0 * r},"
            for k, (r, s, f) in enumerate(zip(radii_mm, stds_mm, flags))]
    path.write_text("# ring_radii_m = 0.0,0.001,0.002,0.003,0.004,0.005,0.006,0.007,0.008\n"
                    "# capacity_gmm = 7200.0\n# optical_gain = 6.0\n"
                    f"# scale_mm_per_px = 0.1\n# scale_std_mm_per_px = {0.1 * scale_rel}\n"
                    "frame,time,u_px,v_px,radius_px,radius_std_px,spot_sigma_px,flags,ok,x_mm,"
                    "y_mm,radius_mm,radius_std_mm,radius_max_mm,zone,unbalance_gmm,"
                    "unbalance_max_gmm\n" + "\n".join(rows) + "\n")
    return path


def test_settled_circles_count_the_ring_scale_once_and_not_a_transient(tmp_path):
    """Four settled circles of 5 mm whose stated std is the ring scale's alone (1e-3 of the
    radius: 5 um): the reading's radius std is that 5 um once -- not divided by sqrt(4) as if
    it averaged out, not added twice; the shrinking frames before them are left out; a
    last circle alone gives a note and no zero ±."""
    import stand

    radii = [9.0, 7.5, 6.0, 5.0, 5.0, 5.0, 5.0]
    stds = [r * 1e-3 for r in radii]
    a = stand.analyze(str(_trace_csv(tmp_path / "t.csv", radii, stds))).to_dict()
    rr = a["ring_reading"]
    assert rr["circles"] == 4 and rr["circle_radius_mm"] == pytest.approx(5.0)
    assert rr["circle_radius_mm_std"] == pytest.approx(5e-3, rel=1e-6)
    assert "ring scale's calibration" in rr["uncertainty_statement"]
    one = stand.analyze(str(_trace_csv(tmp_path / "one.csv", [9.0, 7.0, 5.0],
                                       [float("nan")] * 3))).to_dict()
    assert one["ring_reading"]["circles"] == 1
    assert any("only the last 1 circle(s) agree" in n for n in one["notes"])
    assert one["ring_reading"]["circle_radius_mm_std"] != 0.0
