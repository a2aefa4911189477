"""vision.io.read_ahead (the decoder thread of iter_frames) gives exactly the frames and
the track of the sequential reader; vision.spot.track's ROI search recovers after the spot
jumps or disappears (synthetic frames with known truth, vision.artificial)."""
import itertools
import math
import threading
from pathlib import Path

import numpy as np
import pytest

from vision import artificial as art
from vision.io import iter_frames, read_ahead
from vision.spot import track

SAMPLE = Path(__file__).resolve().parents[1] / "data_samples" / "video" / "screen.mp4"
#: px: RMS bound of the spot centre at the default 8-bit noise (sigma 2 px, 204 DN peak,
#: 1 DN read noise: 0.008-0.016 px per axis, tests/test_vision_spot.py), with margin
RMS_PX = 0.05


def _workers():
    return [t for t in threading.enumerate() if t.name == "vision-read-ahead"]


def _whirl(n, cam, radius=40.0, jump_at=None, gone=()):
    """Spot positions (n, 1, 2) [px] on a circle, 0.15 rad per frame; from ``jump_at`` the
    circle is moved by (+90, -50) px (a jump far outside the ROI); NaN (no spot) in ``gone``."""
    th = 0.15 * np.arange(n)
    px = np.column_stack([0.5 * cam.width + radius * np.cos(th) - 45.0,
                          0.5 * cam.height + radius * np.sin(th) + 25.0])
    if jump_at is not None:
        px[jump_at:] += (90.0, -50.0)
    px[list(gone)] = np.nan
    return px[:, None, :]


@pytest.fixture(scope="module")
def video(tmp_path_factory):
    """40 lossless frames (FFV1, 160 x 120 px) of a whirling spot, and the truth."""
    cv2 = pytest.importorskip("cv2")
    cam = art.Camera(width=160, height=120, sigma_px=2.0)
    px = _whirl(40, cam, radius=25.0)
    path = str(tmp_path_factory.mktemp("vid") / "whirl.avi")
    w = cv2.VideoWriter(path, cv2.CAP_FFMPEG, cv2.VideoWriter_fourcc(*"FFV1"), 100.0,
                        (cam.width, cam.height), [cv2.VIDEOWRITER_PROP_IS_COLOR, 0])
    if not w.isOpened():
        pytest.skip("OpenCV cannot write FFV1 here")
    for f in art.spot_frames(px, cam):
        w.write(f)
    w.release()
    return path, px[:, 0]


def test_threaded_reader_gives_the_sequential_frames_and_track(video):
    path, truth = video
    seq = list(iter_frames(path, ahead=0))
    thr = list(iter_frames(path, ahead=3))          # a short queue: the thread waits too
    assert len(seq) == len(thr) == len(truth)
    for a, b in zip(seq, thr):
        assert a.index == b.index and a.time == b.time and np.array_equal(a.image, b.image)
    ta, tb = track(iter_frames(path, ahead=0)), track(iter_frames(path))
    assert ta.equals(tb)
    assert math.sqrt(np.mean((tb[["u_px", "v_px"]].to_numpy() - truth) ** 2)) <= RMS_PX
    assert not _workers()


def test_a_large_frame_is_read_ahead_by_ffmpegs_threads_with_the_same_frames(tmp_path, monkeypatch):
    """A frame of LARGE_FRAME_PIXELS or more: the read-ahead decoder opens the file with
    FFmpeg's own threads (the decoder is the slow stage) -- the same frames as read in turn."""
    cv2 = pytest.importorskip("cv2")
    import vision.io as vio

    cam = art.Camera(width=512, height=512, sigma_px=2.0)
    assert cam.width * cam.height >= vio.LARGE_FRAME_PIXELS
    path = str(tmp_path / "large.avi")
    w = cv2.VideoWriter(path, cv2.CAP_FFMPEG, cv2.VideoWriter_fourcc(*"FFV1"), 100.0,
                        (cam.width, cam.height), [cv2.VIDEOWRITER_PROP_IS_COLOR, 0])
    if not w.isOpened():
        pytest.skip("OpenCV cannot write FFV1 here")
    for f in art.spot_frames(_whirl(6, cam, radius=60.0), cam):
        w.write(f)
    w.release()
    opened = []
    real = cv2.VideoCapture

    def capture(*args):
        opened.append(args[2][1] if len(args) > 2 else "default")   # CAP_PROP_N_THREADS asked
        return real(*args)

    monkeypatch.setattr(cv2, "VideoCapture", capture)
    thr = list(iter_frames(path))
    assert opened == [1, "default"]   # one thread asked first, then FFmpeg's own for the size
    seq = list(iter_frames(path, ahead=0))
    assert len(seq) == len(thr) == 6
    for a, b in zip(seq, thr):
        assert a.index == b.index and np.array_equal(a.image, b.image)


def test_threaded_reader_on_the_video_sample_tracks_as_the_sequential_one():
    if not SAMPLE.is_file():
        pytest.skip("no video sample")
    ta = track(itertools.islice(iter_frames(SAMPLE, ahead=0), 12))
    tb = track(itertools.islice(iter_frames(SAMPLE), 12))     # closed early: 488 frames unread
    assert len(ta) == 12 and ta.equals(tb)


def test_read_ahead_raises_where_the_source_fails_and_stops_when_closed():
    def source():
        yield from range(5)
        raise OSError("disk gone at item 5")

    got = []
    with pytest.raises(OSError, match="item 5"):
        for x in read_ahead(source(), 2):
            got.append(x)
    assert got == [0, 1, 2, 3, 4]
    closed = []

    def endless():
        try:
            yield from itertools.count()
        finally:
            closed.append(True)

    it = read_ahead(endless(), 4)
    assert [next(it) for _ in range(3)] == [0, 1, 2]
    it.close()
    assert closed == [True] and not _workers()


def test_roi_tracker_recovers_after_a_jump_and_a_lost_spot():
    """The spot jumps 103 px (far outside the ROI) at frame 15 and is gone in frames
    27-28: the jump is found by the full-frame search, the gone frames are "missing", and
    every other frame is within the noise of the truth."""
    cam = art.Camera(width=320, height=240, sigma_px=2.0)
    px = _whirl(36, cam, jump_at=15, gone=(27, 28))
    df = track(art.spot_frames(px, cam), gain=cam.electrons_per_dn)
    gone = df["frame"].isin([27, 28]).to_numpy()
    assert not df["ok"][gone].any() and df["flags"][gone].str.contains("missing").all()
    assert df["ok"][~gone].all()
    err = df[["u_px", "v_px"]].to_numpy()[~gone] - px[~gone, 0]
    assert math.sqrt(np.mean(err ** 2)) <= RMS_PX
    assert np.abs(err).max() <= 4 * RMS_PX


def test_read_ahead_holds_at_most_max_bytes_of_frames():
    """Frames of 1000 bytes with a 3000-byte budget: the thread gets 3 frames ahead (plus
    the one it holds waiting for room) and no further, however deep ``depth`` is."""
    import time

    produced = []

    def frames():
        for k in range(100):
            produced.append(k)
            yield k, 0.0, np.zeros(1000, np.uint8)

    it = read_ahead(frames(), depth=256, max_bytes=3000, batch=1)
    assert next(it)[0] == 0
    deadline = time.monotonic() + 10.0
    while len(produced) < 5 and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(0.1)                        # room for a wrong producer to run further
    assert len(produced) == 5              # 1 consumed + 3 queued + 1 held
    assert [x[0] for x in it] == list(range(1, 100))
    assert not _workers()


@pytest.mark.parametrize("batch, depth", [(1, 1), (3, 2), (4, 16), (8, 256)])
def test_read_ahead_in_batches_gives_every_item_once_in_order(batch, depth):
    """Batches of 1, 2, 4, ... up to ``batch`` (and a last partial one) give the items as
    iterating them directly does, for a count that is no multiple of any batch."""
    assert list(read_ahead(iter(range(23)), depth=depth, batch=batch)) == list(range(23))
    assert list(read_ahead(iter([]), depth=depth, batch=batch)) == []
    assert not _workers()
