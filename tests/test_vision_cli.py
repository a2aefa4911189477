"""stand track / stand strobe on the sample recording, scored against its truth."""
from pathlib import Path

import h5py
import numpy as np
import pandas as pd

from stand.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
REC = ROOT / "data_samples" / "recordings" / "stand_cameras.h5"


def _track_with_rings(tmp_path, *datasets):
    """`stand track` of the sample recording with the ring calibration: the CSV path,
    its table and the named datasets of the recording."""
    out = tmp_path / "track.csv"
    assert main(["track", str(REC), "-o", str(out), "--calibration",
                 str(ROOT / "data_samples" / "images" / "calibration_rings.png")]) == 0
    df = pd.read_csv(out, comment="#")
    with h5py.File(REC) as f:
        arrays = [f[name][:] for name in datasets]
    return (out, df, *arrays)


def test_track_with_ring_calibration_matches_the_truth(tmp_path):
    _, df, truth_px, truth_m, inside = _track_with_rings(
        tmp_path, "truth/screen/centre_px", "truth/screen/centre_m", "truth/screen/in_frame")
    pitch = 1e-4  # the sample camera's pixel_pitch
    assert np.array_equal(df["ok"].to_numpy(bool), inside)
    good = inside & ~df["flags"].fillna("").str.contains("saturated").to_numpy()
    err_px = np.hypot(df["u_px"] - truth_px[:, 0], df["v_px"] - truth_px[:, 1])[good]
    assert np.sqrt(np.mean(err_px**2)) < 0.1
    # px -> mm through the rings: the calibrated scale is the camera's within 0.2 %
    assert abs(df["scale_mm_per_px"].iloc[0] / (pitch * 1e3) - 1) < 2e-3
    err_mm = np.hypot(df["x_mm"] - truth_m[:, 0] * 1e3, df["y_mm"] - truth_m[:, 1] * 1e3)[good]
    assert np.max(err_mm) < 0.2 * pitch * 1e3


def test_strobe_angles_of_the_balanced_run(tmp_path):
    out = tmp_path / "angles.csv"
    assert main(["strobe", str(REC), "-o", str(out), "--weights", "2"]) == 0
    df = pd.read_csv(out, comment="#")
    with h5py.File(REC) as f:
        truth = np.degrees(f["truth/stroboscope/relative_angle"][:, 0, :])
    last = df.iloc[-1]
    # slot error (4.1) = 0.003 / (2 pi 0.12) -> 1.43 deg
    np.testing.assert_allclose(sorted([last["weight1_deg"], last["weight2_deg"]]), sorted(truth[-1]),
                               atol=1.43)


def test_track_errors(tmp_path, capsys):
    bad = tmp_path / "bad.h5"
    bad.write_bytes(b"not hdf5")
    assert main(["track", str(bad), "-o", str(tmp_path / "t.csv")]) == 2
    assert "bad.h5" in capsys.readouterr().err


def test_track_writes_the_columns_stand_analyze_reads(tmp_path):
    out, df, phi = _track_with_rings(tmp_path, "instruments/screen/frame_rotor_angle")
    # shaft displacement = screen displacement / optical gain (6 on the sample stand)
    np.testing.assert_allclose(df["x_m"], df["x_mm"] * 1e-3 / 6.0)
    np.testing.assert_allclose(df["t_s"], df["time"] + 0.1)           # mid-exposure (0.2 s)
    np.testing.assert_allclose(df["rotor_angle_rad"], phi)
    assert main(["analyze", str(out), "--json"]) == 0
