"""Streaming frame sources: HDF5 image datasets, video files, image folders.

:func:`iter_frames` yields :class:`FrameRecord` (index, time [s] or NaN, image)
one frame at a time (constant memory: one frame is read per step).

Error policy
------------
* unreadable / corrupt file, missing dataset, video that cv2 cannot open,
  image that cv2 cannot decode, empty folder -> :class:`VisionError` (raised).
* a frame whose size differs from the first frame's, mid-stream ->
  :class:`VisionError` (raised, naming the frame index and both sizes).
* blank frames (all pixels equal, e.g. all zero) are **yielded** (not an
  error); :func:`vision.spot.locate` flags them ``"blank"`` + ``"missing"``
  (NaN centre, ``ok`` False), so a tracking table keeps one row per frame.
"""
from __future__ import annotations

import glob
import math
import os
import queue
import sys
import threading
from pathlib import Path
from typing import Callable, Iterable, Iterator, NamedTuple, Sequence

import numpy as np

__all__ = ["VisionError", "FrameRecord", "iter_frames", "read_ahead", "frame_table",
           "DEFAULT_DATASET", "VIDEO_SUFFIXES", "IMAGE_SUFFIXES", "HDF5_SUFFIXES", "READ_AHEAD",
           "READ_AHEAD_BYTES", "READ_AHEAD_BATCH"]

DEFAULT_DATASET = "instruments/screen/frames"
HDF5_SUFFIXES = {".h5", ".hdf5", ".hdf"}
VIDEO_SUFFIXES = {".avi", ".mp4", ".mkv", ".mov", ".mpg", ".mpeg", ".wmv", ".webm", ".m4v"}
IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".pgm", ".ppm"}
#: frames a decoder thread reads ahead of the consumer at most (video files and images:
#: OpenCV releases the GIL while it decodes, so decoding overlaps the tracking of earlier
#: frames).  Deep on purpose: decoding and tracking cost about the same per frame on average
#: but not frame by frame (a saturated arc costs the tracker more than a dot), and a shallow
#: queue makes each stage wait for the other's slow stretches -- the sample video's decode +
#: track / decode 0.85 with 16 frames, 0.93 with 64, 0.95-0.97 with 256 (benchmarks/README.md)
READ_AHEAD = 256
#: [bytes] ... and at most this much image memory ahead (a 1280 x 1024 camera: 51 frames)
READ_AHEAD_BYTES = 64 * 2 ** 20
#: frames handed over at a time (one queue operation and one wake-up per batch)
READ_AHEAD_BATCH = 8
#: [s] the interpreter's thread switch interval while a reader thread runs (Python's default
#: 5 ms): the decoder thread wants the GIL back a few times per frame (after the decode, the
#: timestamp, the gray conversion), and a consumer busy in Python keeps it waiting up to the
#: interval each time -- on the critical path, the decoder being the slower stage.  Sample
#: video, decode + track / decode alternated in one process (benchmarks/README.md): 0.81-0.97
#: at 0.2 ms, 0.90-0.95 at 50 us, 0.93-0.98 at 10 us (the tracker's cost of the extra
#: switches below the noise)
SWITCH_INTERVAL = 1e-5
#: [pixels] a video frame at least this large is decoded with FFmpeg's own threads even when
#: read ahead: the decoder is then the slow stage by far (a 1280 x 1024 FFV1 frame 35 ms with
#: one thread, 23 ms with FFmpeg's; the tracker ~1 ms inside its ROI), and the read-ahead
#: pipeline runs at 42-43 frames/s instead of 24 (2026-11-30, benchmarks/README.md); below
#: it one thread, the other core tracking (the 256 x 256 sample: 1050 frames/s against 915)
LARGE_FRAME_PIXELS = 512 * 512


class VisionError(ValueError):
    """A frame source cannot be read, or it yields an inconsistent frame."""


class FrameRecord(NamedTuple):
    index: int
    time: float          #: s; NaN when the source has no timestamps
    image: np.ndarray    #: (H, W) gray


def _split_source(source, dataset):
    if isinstance(source, tuple):
        return str(source[0]), str(source[1])
    s = str(source)
    if not os.path.exists(s) and ":" in s:
        path, _, ds = s.rpartition(":")
        if Path(path).suffix.lower() in HDF5_SUFFIXES:
            return path, ds
    return s, dataset


def _check_size(shape, index, first):
    if first is not None and shape != first:
        raise VisionError(f"frame {index}: size {shape[1]}x{shape[0]} (W x H) differs from the "
                          f"first frame's {first[1]}x{first[0]}")


def _iter_hdf5(path, dataset):
    import h5py

    try:
        f = h5py.File(path, "r")
    except Exception as exc:   # OSError for corrupt / non-HDF5 files
        raise VisionError(f"{path}: cannot open as HDF5 ({exc})") from exc
    with f:
        if dataset not in f or not isinstance(f[dataset], h5py.Dataset):
            raise VisionError(f"{path}: no image dataset {dataset!r}")
        ds = f[dataset]
        if ds.ndim not in (2, 3):
            raise VisionError(f"{path}:{dataset}: expected (F, H, W) frames, shape {ds.shape}")
        parent = dataset.rpartition("/")[0]
        tname = f"{parent}/frame_time" if parent else "frame_time"
        times = None
        if tname in f and isinstance(f[tname], h5py.Dataset) and f[tname].shape[:1] == ds.shape[:1]:
            times = f[tname]
        n = 1 if ds.ndim == 2 else ds.shape[0]
        for i in range(n):
            try:
                img = ds[()] if ds.ndim == 2 else ds[i]
                t = float(times[i]) if times is not None else math.nan
            except Exception as exc:
                raise VisionError(f"{path}:{dataset}: frame {i} unreadable ({exc})") from exc
            yield i, t, np.asarray(img)


def _iter_video(path, threads: int = 0, large_threads: int | None = None):
    """(index, time [s], gray image) of every frame; ``threads``: FFmpeg's decoding threads
    (0: its default); ``large_threads``: instead of ``threads`` for frames of at least
    :data:`LARGE_FRAME_PIXELS`."""
    import cv2

    if not os.path.isfile(path):
        raise VisionError(f"{path}: no such video file")
    cap = None
    if threads > 0:
        cap = cv2.VideoCapture(path, cv2.CAP_FFMPEG, [cv2.CAP_PROP_N_THREADS, threads])
        size = cap.get(cv2.CAP_PROP_FRAME_WIDTH) * cap.get(cv2.CAP_PROP_FRAME_HEIGHT)
        if large_threads is not None and large_threads != threads and size >= LARGE_FRAME_PIXELS:
            cap.release()
            cap = (cv2.VideoCapture(path, cv2.CAP_FFMPEG, [cv2.CAP_PROP_N_THREADS, large_threads])
                   if large_threads > 0 else None)
    if cap is None or not cap.isOpened():
        cap = cv2.VideoCapture(path)
    try:
        if not cap.isOpened():
            raise VisionError(f"{path}: cv2.VideoCapture cannot open it (corrupt or unsupported)")
        i = 0
        while True:
            ok, img = cap.read()
            if not ok:
                break
            t = cap.get(cv2.CAP_PROP_POS_MSEC)
            if img.ndim == 3:
                img = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
            yield i, (t / 1000.0 if t >= 0 else math.nan), img
            i += 1
        if i == 0:
            raise VisionError(f"{path}: no frame could be decoded (corrupt or unsupported video)")
    finally:
        cap.release()


def read_image(path, flags=None) -> np.ndarray:
    """Read one image file (``cv2.imread``, unchanged depth by default).

    Raises
    ------
    VisionError
        The file is not an image, is corrupt, or declares more pixels than the
        decoder accepts (OpenCV's ``CV_IO_MAX_IMAGE_PIXELS``); the message names it.
    """
    import cv2

    try:
        img = cv2.imread(str(path), cv2.IMREAD_UNCHANGED if flags is None else flags)
    except cv2.error as exc:
        reason = str(exc).strip().splitlines()[-1] if str(exc).strip() else type(exc).__name__
        if "MAX_IMAGE_PIXELS" in str(exc) or "validateInputImageSize" in str(exc):
            reason = "the image declares more pixels than the decoder accepts (too large)"
        raise VisionError(f"{path}: cannot read the image: {reason}") from None
    if img is None:
        raise VisionError(f"{path}: cv2.imread cannot read it (corrupt or not an image)")
    return img


def _iter_images(paths):
    import cv2

    if not paths:
        raise VisionError("no image files found")
    for i, p in enumerate(paths):
        img = read_image(p)
        if img.ndim == 3:
            code = cv2.COLOR_BGRA2GRAY if img.shape[2] == 4 else cv2.COLOR_BGR2GRAY
            img = cv2.cvtColor(img, code)
        yield i, math.nan, img


def read_ahead(items: Iterable, depth: int = READ_AHEAD,
               max_bytes: int | None = None, batch: int = READ_AHEAD_BATCH) -> Iterator:
    """The items of ``items``, produced by a background thread up to ``depth`` ahead of the
    consumer (a bounded queue: memory for about ``depth`` items).  With ``max_bytes``, the
    depth is also at most ``max_bytes`` over the first item's size (the bytes of its arrays,
    :func:`_item_bytes`).  The thread hands the items over ``batch`` at a time (one queue
    operation and one wake-up of the consumer per batch instead of per item; the first
    batches 1, 2, 4, ... items, so that the consumer starts at once); the depth is counted
    in whole batches, at least one.

    Same items in the same order as iterating ``items`` directly; an exception raised by
    ``items`` is raised here, at the position where it occurred.  Closing this generator
    early (``break``, garbage collection) stops the thread and closes ``items`` (e.g. releases
    a video file).
    """
    batch = max(int(batch), 1)
    q: queue.Queue = queue.Queue(maxsize=max(int(depth) // batch, 1))
    stop = threading.Event()
    end = object()

    def put(x) -> bool:
        while not stop.is_set():
            try:
                q.put(x, timeout=0.05)
                return True
            except queue.Full:
                pass
        return False

    def produce():
        it = iter(items)
        chunk: list = []
        n_next = 1           # the next batch's size: 1, 2, 4, ... up to ``batch``
        try:
            for k, x in enumerate(it):
                if k == 0 and max_bytes is not None:
                    size = _item_bytes(x)
                    if size > 0:
                        with q.mutex:     # Queue.put reads maxsize under this lock
                            q.maxsize = max(1, min(q.maxsize, int(max_bytes // size) // batch))
                chunk.append(x)
                if len(chunk) >= n_next:          # (small at first: no wait to start)
                    if not put((chunk, None)):
                        return
                    chunk, n_next = [], min(2 * n_next, batch)
            chunk.append(end)
            put((chunk, None))
        except BaseException as exc:   # noqa: BLE001 - handed to the consumer, raised there
            put((chunk, exc))
        finally:
            close = getattr(it, "close", None)
            if close is not None:
                close()

    worker = threading.Thread(target=produce, name="vision-read-ahead", daemon=True)
    interval = sys.getswitchinterval()
    sys.setswitchinterval(min(interval, SWITCH_INTERVAL))
    worker.start()
    try:
        while True:
            xs, exc = q.get()
            for x in xs:
                if x is end:
                    return
                yield x
            if exc is not None:
                raise exc
    finally:
        stop.set()
        worker.join()
        if sys.getswitchinterval() == min(interval, SWITCH_INTERVAL):   # not changed meanwhile
            sys.setswitchinterval(interval)


def _item_bytes(x) -> int:
    """Bytes held by the arrays of ``x`` (an array, or a tuple holding arrays)."""
    if isinstance(x, np.ndarray):
        return int(x.nbytes)
    if isinstance(x, tuple):
        return sum(int(y.nbytes) for y in x if isinstance(y, np.ndarray))
    return 0


def iter_frames(source, dataset: str = DEFAULT_DATASET, *,
                progress: bool = False, ahead: int = READ_AHEAD) -> Iterator[FrameRecord]:
    """Stream gray frames from ``source``, one at a time.

    Parameters
    ----------
    source : str, Path, (path, dataset) tuple, ndarray or iterable of arrays
        * HDF5 file (``.h5``, ``.hdf5``, ``.hdf``), optionally ``"file.h5:group/ds"``
          or a (path, dataset) pair; the dataset is (F, H, W) (or one (H, W)
          image); timestamps from the sibling ``frame_time`` dataset when present.
        * video file (``cv2.VideoCapture``; colour converted to gray);
          timestamps from ``CAP_PROP_POS_MSEC``.
        * a folder (its images, sorted by name) or a glob pattern
          (``cv2.imread``, unchanged depth, colour converted to gray).
        * an array (F, H, W) or an iterable of (H, W) arrays.
    dataset : str
        HDF5 dataset path (default ``instruments/screen/frames``).
    progress : bool
        Show a tqdm progress bar when tqdm is installed.
    ahead : int
        Video files and images are decoded by a thread up to ``ahead`` frames (and
        :data:`READ_AHEAD_BYTES`) ahead of the consumer (:func:`read_ahead`; a video by one
        FFmpeg thread: the other cores are the tracker's; frames of
        :data:`LARGE_FRAME_PIXELS` and more by FFmpeg's own threads, the decoder being the
        slow stage by far); 0: decoded in the caller's thread, on demand (FFmpeg's own
        threads).

    Yields
    ------
    FrameRecord(index, time, image)

    Raises
    ------
    VisionError
        Unreadable/corrupt source, a frame of another size than the first
        (mid-stream).  Blank frames are yielded (see the module docstring).
    """
    first = None
    items = _open(source, dataset, ahead > 0)
    if ahead > 0 and getattr(items, "__name__", "") in ("_iter_video", "_iter_images"):
        items = read_ahead(items, ahead, READ_AHEAD_BYTES)   # (OpenCV releases the GIL)
    for i, t, img in _with_progress(items, progress):
        img = np.asarray(img)
        if img.ndim != 2:
            raise VisionError(f"frame {i}: expected a 2-D gray image, shape {img.shape}")
        _check_size(img.shape, i, first)
        first = img.shape if first is None else first
        yield FrameRecord(i, float(t), img)


def _with_progress(items, progress):
    """``items`` wrapped in a tqdm progress bar when asked for and installed."""
    if progress:
        try:
            from tqdm import tqdm
            return tqdm(items, unit="frame")
        except ImportError:
            pass
    return items


def frame_table(frames: Iterable, measure: Callable, columns: Sequence[str], *,
                progress: bool = False):
    """Measure every frame; one row per frame in a pandas DataFrame.

    Parameters
    ----------
    frames : iterable
        2-D arrays, or :class:`FrameRecord` (as yielded by :func:`iter_frames`;
        then a ``time`` column [s] is added, NaN when the source has no
        timestamps, and ``frame`` is the record's index).
    measure : callable
        ``measure(image) -> result``, called on the frames in order (it may
        keep state, e.g. a region of interest).
    columns : sequence of str
        Attributes of the result tabulated after ``frame`` (and ``time``); a
        set (the flags) becomes its sorted comma-separated string ("" when
        empty), an ``ok`` column is made bool.
    progress : bool
        Show a tqdm progress bar when tqdm is installed.

    Returns
    -------
    pandas.DataFrame
        Columns: frame, [time,] *columns.
    """
    import pandas as pd

    rows = {c: [] for c in ("frame", "time", *columns)}
    have_time = False
    for k, item in enumerate(_with_progress(frames, progress)):
        t = math.nan
        if hasattr(item, "image"):
            have_time = True
            k, t, img = item.index, item.time, item.image
        else:
            img = item
        result = measure(img)
        rows["frame"].append(k)
        rows["time"].append(t)
        for c in columns:
            v = getattr(result, c)
            rows[c].append(",".join(sorted(v)) if isinstance(v, (set, frozenset)) else v)
    if not have_time:
        del rows["time"]
    df = pd.DataFrame(rows)
    if "ok" in df:
        df["ok"] = df["ok"].astype(bool)
    return df


def _open(source, dataset, one_decoder_thread=False):
    if isinstance(source, np.ndarray):
        arr = source if source.ndim == 3 else source[None]
        return ((i, math.nan, arr[i]) for i in range(arr.shape[0]))
    is_pair = (isinstance(source, tuple) and len(source) == 2
               and all(isinstance(x, (str, os.PathLike)) for x in source))
    if not (isinstance(source, (str, os.PathLike)) or is_pair):
        return ((i, math.nan, img) for i, img in enumerate(source))
    path, ds = _split_source(source, dataset)
    p = Path(path)
    if p.is_dir():
        files = sorted(q for q in p.iterdir() if q.suffix.lower() in IMAGE_SUFFIXES)
        if not files:
            raise VisionError(f"{path}: folder holds no images ({sorted(IMAGE_SUFFIXES)})")
        return _iter_images(files)
    if any(ch in path for ch in "*?["):
        files = sorted(glob.glob(path))
        if not files:
            raise VisionError(f"{path}: pattern matches no file")
        return _iter_images(files)
    suffix = p.suffix.lower()
    if suffix in HDF5_SUFFIXES:
        if not p.is_file():
            raise VisionError(f"{path}: no such file")
        return _iter_hdf5(path, ds)
    if suffix in IMAGE_SUFFIXES:
        if not p.is_file():
            raise VisionError(f"{path}: no such file")
        return _iter_images([p])
    if not p.is_file():
        raise VisionError(f"{path}: no such file")
    # read ahead: the reading thread is the decoder's parallelism, the other cores track
    # (a large frame: FFmpeg's threads too, LARGE_FRAME_PIXELS)
    return _iter_video(path, 1 if one_decoder_thread else 0, large_threads=0)
