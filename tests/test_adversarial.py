"""One adversarial harness for every command: bad inputs x the commands that read them.

A catalogue of bad inputs -- scene mutations (missing / unknown keys, wrong types,
NaN / inf, negatives, absurd sizes, binary garbage, a string where a table is
expected), recording mutations (truncations, flipped bytes, deleted datasets, NaN
stretches, non-monotonic or zero-length time, wrong units), table mutations
(missing columns, text in numbers, one row, semicolons, a BOM) and image mutations
(blank, saturated, two spots, zero-size, a PNG declaring 50 000 x 50 000 pixels) --
is crossed with every command that reads that kind of input; so are scenes valid key by
key whose structure no computation resolves (conditioning extremes) and degenerate
speed programmes (issue 34).  Each cell must end in
exit 2 with one line naming the input and the problem, or in a result (exit 0/1)
with the problem stated (exit 1: exactly one stderr line saying what stopped and its
budget); never a traceback, a hang (per-cell time limit), memory
beyond the bound, or a changed input (hash before and after).  Seeds are fixed.

``python tests/test_adversarial.py`` prints the table; under pytest the table is
printed at the end of the run (tests/conftest.py).
"""
from __future__ import annotations

import hashlib
import io
import json
import random
import re
import resource
import signal
import struct
import sys
import time
import zlib
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _helpers import theory_computed_once, toml_text  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "data_samples" / "scenes"
CELL_TIME_LIMIT_S = 20.0       #: a cell that runs longer is a hang
REFUSAL_TIME_LIMIT_S = 8.0     #: a refusal (exit 2) that takes longer is a defect (issue 34)
MEMORY_BOUND_BYTES = 4 << 30   #: peak resident memory of the whole harness
SEED = 20261125


# ---------------------------------------------------------------- inputs
def _short(doc: dict) -> dict:
    doc = json.loads(json.dumps(doc))
    if "weight_model" in doc:
        doc.setdefault("run", {})["duration"] = 20.0
        doc["run"]["samples"] = 201
    else:
        doc["run"]["duration"] = 1.0
    return doc


BASES = {name: _short(tomllib.loads((SCENES / f"{name}.toml").read_text()))
         for name in ("ball_runup", "family_two_mass", "weight_damper")}


def _scene_text(doc) -> str:
    tables = {}
    for k, v in doc.items():
        if isinstance(v, dict) and any(isinstance(x, dict) for x in v.values()):
            plain = {a: b for a, b in v.items() if not isinstance(b, dict)}
            if plain:            # keys of the table itself, e.g. a mutation's unknown key
                tables[k] = plain
            for sub, body in v.items():
                if isinstance(body, dict):
                    tables[f"{k}__{sub}"] = body
        else:
            tables[k] = v
    return toml_text(**tables)


def scene_mutations(base: str, rng: random.Random):
    """(label, bytes) of invalid scene files built from the base scene."""
    doc = BASES[base]
    out = [("empty file", b""), ("binary garbage", bytes(rng.getrandbits(8) for _ in range(300))),
           ("not TOML", b"this is = = not toml [[\n"), ("latin-1 text", "name = 'é'\n".encode("latin-1"))]
    for table in list(doc):
        if table == "scene":
            continue
        d = {k: v for k, v in doc.items() if k != table}
        out.append((f"missing [{table}]", _scene_text(d).encode()))
        d = json.loads(json.dumps(doc))
        if isinstance(d[table], dict):
            d[table]["unknwon_key"] = 1.0
            out.append((f"unknown key in [{table}]", _scene_text(d).encode()))
        d = json.loads(json.dumps(doc))
        d[table] = "a string"
        text = _scene_text({k: v for k, v in d.items() if k != table}) + f'{table} = "a string"\n'
        out.append((f"string where [{table}] is a table", text.encode()))
    numeric = [(t, k) for t, body in doc.items() if isinstance(body, dict)
               for k, v in body.items() if isinstance(v, (int, float)) and not isinstance(v, bool)]
    for t, k in rng.sample(numeric, min(5, len(numeric))):
        for label, value in (("text", "'x'"), ("nan", "nan"), ("inf", "inf"), ("negative", None),
                             ("absurd", "1e300")):
            d = json.loads(json.dumps(doc))
            if label == "negative":
                value = repr(-abs(float(d[t][k])) - 1.0)
            text = _scene_text(d).replace(f"\n{k} = {json.dumps(d[t][k])}\n", f"\n{k} = {value}\n", 1)
            out.append((f"{t}.{k} {label}", text.encode()))
    d = json.loads(json.dumps(doc))
    if "balancer" in d:
        d["balancer"]["count"] = 10 ** 9
        out.append(("10^9 weights", _scene_text(d).encode()))
    d = json.loads(json.dumps(doc))
    d["run"]["duration"] = 1e12
    out.append(("10^12 s", _scene_text(d).encode()))
    return out


def _edited(name: str, edits: dict, duration: float = 1.0) -> bytes:
    """A sample scene with ``key = value`` lines replaced (the first of each key) and a short run."""
    text = (SCENES / f"{name}.toml").read_text()
    for key, value in {**edits, "duration": repr(duration)}.items():
        text, n = re.subn(rf"(?m)^{re.escape(key)} = .*$", f"{key} = {value}", text, count=1)
        assert n == 1, (name, key)
    return text.encode()


def conditioning_mutations():
    """(label, bytes) of scenes valid key by key whose structure no computation resolves
    (issue 34): refused at load by every command (stand.scene.conditioning)."""
    def two(**edits):      # (its screens film from 2.5 s on: the run keeps its 5 s)
        return _edited("paper003_two_screens", edits, duration=5.0)

    return [
        ("rigid rotor mass 1e30 kg, A 1e-30 kg m^2", two(mass="1e30", A="1e-30")),
        ("rigid rotor mass 1e20 kg", two(mass="1e20")),
        ("rigid rotor A 1e-30 kg m^2", two(A="1e-30")),
        ("rigid rotor supports 1e30 N/m", two(c1="1e30", c2="1e30")),
        ("planar rotor stiffness 1e30 N/m", _edited("ball_runup", {"stiffness": "1e30"})),
        ("two-mass rotor shaft 1e30 N/m", _edited("family_two_mass", {"rotor_stiffness": "1e30"})),
    ]


def programme_mutations():
    """(label, bytes) of degenerate speed programmes (issue 34): a programme of one node is
    a constant speed in every command; equal times, negative speeds and steps of infinite
    acceleration are refused by every command."""
    out = []
    for base in ("body_damper", "family_two_mass", "ball_runup"):
        for label, prog in (("one node at rest [[0, 0]]", "[[0.0, 0.0]]"),
                            ("one node [[0, 5]]", "[[0.0, 5.0]]"),
                            ("one node late [[3, 5]]", "[[3.0, 5.0]]"),
                            ("at rest throughout", "[[0.0, 0.0], [5.0, 0.0]]"),
                            ("starts after the run", "[[50.0, 5.0], [60.0, 6.0]]"),
                            ("equal times", "[[0.0, 0.0], [0.0, 5.0]]"),
                            ("negative speed", "[[0.0, -5.0]]"),
                            ("a step in 1e-300 s", "[[0.0, 0.0], [1e-300, 5.0]]")):
            out.append((f"{base}: {label}", _edited(base, {"programme": prog})))
    return out


def _sweep_spec(tmp: Path, scene: Path, i: int) -> Path:
    spec = tmp / f"sweep_{i}.toml"
    spec.write_text(f'[sweep]\ncompute = ["theory"]\n[base]\nscene = "{scene.name}"\n'
                    '[[axis]]\nkey = "speed"\nvalues = [5.0, 20.0]\n')
    return spec


def recording_mutations(good: Path, rng: random.Random):
    """(label, writer(path)) of damaged recordings made from a good one."""
    import h5py

    data = good.read_bytes()

    def copy_then(edit):
        def make(p: Path):
            p.write_bytes(data)
            with h5py.File(p, "r+") as f:
                edit(f)
        return make

    def flipped(k):
        def make(p: Path):
            b = bytearray(data)
            for i in random.Random(k).sample(range(len(b) // 4, len(b)), 64):
                b[i] ^= 0xFF
            p.write_bytes(bytes(b))
        return make

    def replace(key, fn):
        def edit(f):
            a = f[key][()]
            del f[key]
            f[key] = fn(a)
        return edit

    out = [(f"truncated at {q:.0%}", (lambda q: lambda p: p.write_bytes(data[:int(len(data) * q)]))(q))
           for q in (0.05, 0.3, 0.6, 0.95)]
    out += [(f"flipped bytes #{k}", flipped(k)) for k in range(3)]
    for key in ("time", "planes", "rotor", "weights", "shaft"):
        out.append((f"deleted {key}", copy_then(lambda f, key=key: f.__delitem__(key))))
    out += [
        ("NaN stretch in x", copy_then(replace("planes/balancer/x",
                                               lambda a: np.where(np.arange(a.size) % 50 < 10, np.nan, a)))),
        ("non-monotonic time", copy_then(replace("time", lambda a: a[::-1].copy()))),
        ("zero-length time", copy_then(replace("time", lambda a: a[:0]))),
        ("wrong units", copy_then(lambda f: f["planes/balancer/x"].attrs.__setitem__("units", "furlong"))),
        ("text scene attribute", copy_then(lambda f: f.attrs.__setitem__("scene", "[[[ not toml"))),
    ]
    return out


def table_mutations():
    t = np.linspace(0, 2, 401)
    good = "t_s,x_m,y_m\n" + "".join(f"{a},{1e-4 * np.cos(60 * a)},{1e-4 * np.sin(60 * a)}\n" for a in t)
    rows = good.splitlines()
    return [
        ("missing column", "\n".join(r.rsplit(",", 1)[0] for r in rows).encode()),
        ("text in a number", good.replace("\n1.0,", "\nabc,", 1).encode()),
        ("one row", ("\n".join(rows[:2]) + "\n").encode()),
        ("semicolons", good.replace(",", ";").encode()),
        ("BOM", ("\ufeff" + good).encode("utf-8")),
        ("empty", b""),
        # shape extremes (issue 34): refused from the shape, before any parsing work
        ("header of 10^6 columns over 3-column rows",
         (rows[0] + "," + ",".join(f"c{i}" for i in range(10 ** 6)) + "\n"
          + "\n".join(rows[1:]) + "\n").encode()),
        ("header of 10^5 columns", (rows[0] + "," + ",".join(f"c{i}" for i in range(10 ** 5))
                                    + "\n" + "\n".join(rows[1:]) + "\n").encode()),
        ("a row of 10^6 fields", ("\n".join(rows[:3]) + "," + ",".join(["1"] * 10 ** 6) + "\n"
                                  + "\n".join(rows[3:]) + "\n").encode()),
        ("a field over the csv field limit", ("\n".join(rows[:3]) + ',"' + "9" * 200_000 + '"\n'
                                              + "\n".join(rows[3:]) + "\n").encode()),
    ]


def _png(width: int, height: int, pixels: bytes = b"") -> bytes:
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    head = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", head) + chunk(b"IDAT", zlib.compress(pixels)) + \
        chunk(b"IEND", b"")


def image_mutations():
    import cv2

    def enc(img):
        return cv2.imencode(".png", img)[1].tobytes()

    yy, xx = np.mgrid[0:120, 0:160]
    spot = lambda x, y: 200 * np.exp(-((xx - x) ** 2 + (yy - y) ** 2) / 8.0)  # noqa: E731
    return [
        ("blank", enc(np.zeros((120, 160), np.uint8))),
        ("saturated", enc(np.full((120, 160), 255, np.uint8))),
        ("two spots", enc((10 + spot(40, 60) + spot(120, 60)).clip(0, 255).astype(np.uint8))),
        ("zero-size file", b""),
        ("PNG declaring 50000 x 50000", _png(50_000, 50_000)),
    ]


# ---------------------------------------------------------------- cells
class _Hang(BaseException):   # not an Exception: the CLI's last-resort handler must not swallow it
    pass


def _alarm(signum, frame):
    raise _Hang()


def _digest(paths) -> dict:
    return {str(p): hashlib.sha256(p.read_bytes()).hexdigest() for p in paths if p.is_file()}


#: a progress bar's line on stderr (tqdm: "name:  50%|#####     | 1/2 [...]")
_PROGRESS = re.compile(r"\d+%\|")


def run_cell(argv, inputs) -> dict:
    """Run ``stand <argv>`` in this process; classify the outcome."""
    from stand.cli.main import main

    before = _digest(inputs)
    out, err = io.StringIO(), io.StringIO()
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, CELL_TIME_LIMIT_S)
    t0 = time.perf_counter()
    try:
        with redirect_stdout(out), redirect_stderr(err):
            code = main([str(a) for a in argv])
    except _Hang:
        code = "hang"
    except SystemExit as exc:        # argparse
        code = exc.code
    except BaseException as exc:     # noqa: BLE001 -- a crash of the harness' subject
        code = f"raised {type(exc).__name__}: {exc}"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    wall = time.perf_counter() - t0
    e, o = err.getvalue(), out.getvalue()
    changed = _digest(inputs) != before
    if code == "hang" or isinstance(code, str):
        verdict = "crash" if code != "hang" else "hang"
    elif "Traceback" in e + o or code == 3:
        verdict = "crash"
    elif changed:
        verdict = "changed input"
    elif code == 2:
        lines = [ln for ln in e.splitlines() if ln.strip()]
        named = any(Path(str(p)).name in e for p in inputs)
        verdict = "clear error" if len(lines) == 1 and named else f"unclear error: {e.strip()[:200]!r}"
        if verdict == "clear error" and wall > REFUSAL_TIME_LIMIT_S:
            verdict = f"slow refusal ({wall:.1f} s > {REFUSAL_TIME_LIMIT_S} s)"
    elif code == 1:      # stopped early (a run's step budget, a computation's work budget)
        lines = [ln for ln in e.splitlines() if ln.strip() and not _PROGRESS.search(ln)]
        verdict = "partial result" if len(lines) == 1 else f"unclear stop: {e.strip()[:200]!r}"
    elif code == 0:
        verdict = "partial result"
    else:
        verdict = f"exit {code}"
    return {"argv": [str(a) for a in argv], "verdict": verdict, "wall": wall}


def cells(tmp: Path):
    """Yield (command, input label, argv, inputs) for every cell of the catalogue."""
    from stand.cli.main import main

    rng = random.Random(SEED)
    for base in BASES:
        for i, (label, blob) in enumerate(scene_mutations(base, rng)):
            p = tmp / f"scene_{base}_{i}.toml"
            p.write_bytes(blob)
            for cmd, extra in (("run", ["-o", tmp / "out.h5"]), ("theory", ["--no-floquet"]),
                               ("accuracy", ["--fast"]),
                               ("experiment", ["constant", "-o", tmp / "out_e.h5", "--duration", "1"])):
                yield cmd, f"{base}: {label}", [cmd, p, *extra], [p]
    scene_cmds = (("run", ["-o", tmp / "out_c.h5"]), ("theory", []), ("accuracy", ["--fast"]),
                  ("experiment", ["constant", "-o", tmp / "out_ce.h5", "--duration", "1"]))
    for kind, catalogue in (("conditioning", conditioning_mutations()),
                            ("programme", programme_mutations())):
        for i, (label, blob) in enumerate(catalogue):
            p = tmp / f"{kind}_{i}.toml"
            p.write_bytes(blob)
            extra_cmds = (("accuracy", ["--methods", "RK4"]),) if kind == "programme" else ()
            for cmd, extra in scene_cmds + extra_cmds:
                yield (f"{cmd}{' RK4' if 'RK4' in extra else ''}", f"{kind}: {label}",
                       [cmd, p, *extra], [p])
            spec = _sweep_spec(tmp, p, i + (100 if kind == "programme" else 0))
            yield ("sweep", f"{kind}: {label}",
                   ["sweep", spec, "-o", tmp / f"{spec.stem}.parquet"], [spec, p])
    good = tmp / "good.h5"
    scene = tmp / "good_scene.toml"
    scene.write_text(_scene_text(BASES["ball_runup"]))
    with redirect_stdout(io.StringIO()):
        main(["run", str(scene), "-o", str(good)])
    for i, (label, make) in enumerate(recording_mutations(good, rng)):
        p = tmp / f"rec_{i}.h5"
        make(p)
        for cmd, extra in (("analyze", []), ("report", ["-o", tmp / "r.html"]),
                           ("snapshot", ["-o", tmp / "s.png"]), ("track", ["-o", tmp / "t.csv"]),
                           ("strobe", ["-o", tmp / "sb.csv"])):
            yield cmd, f"recording: {label}", [cmd, p, *extra], [p]
    for i, (label, blob) in enumerate(table_mutations()):
        p = tmp / f"table_{i}.csv"
        p.write_bytes(blob)
        for cmd, extra in (("analyze", []), ("report", ["-o", tmp / "rt.html"])):
            yield cmd, f"table: {label}", [cmd, p, *extra], [p]
    for i, (label, blob) in enumerate(image_mutations()):
        d = tmp / f"img_{i}"
        d.mkdir()
        p = d / "frame_000.png"
        p.write_bytes(blob)
        for cmd, extra in (("track", [d, "-o", tmp / "ti.csv"]), ("strobe", [d, "-o", tmp / "si.csv"]),
                           ("track", [good, "-o", tmp / "tc.csv", "--calibration", p,
                                      "--ring-radii", "0.01,0.02,0.03"])):
            yield (f"{cmd}{' --calibration' if '--calibration' in extra else ''}",
                   f"image: {label}", [cmd, *extra], [p, good])


#: the fast run's degenerate programmes for ``theory`` (a speed map, ~2 s a cell) and ``sweep``
#: (a batch of runs): the first few (one node at rest, one node, one node late: the constant
#: speeds the theory and the sweep answer; the refused ones are refused at load, before either);
#: run, experiment and accuracy, which follow the programme, meet every one
FAST_PROGRAMMES = 3


def cell_kind(command: str, label: str) -> tuple:
    """A cell's kind: its command and its mutation without the base scene, table or key it
    hits ("ball_runup: rotor.mass nan" -> "nan")."""
    head, _, rest = label.partition(": ")
    what = re.sub(r"\[[^\]]*\]", "[]", rest if head in BASES else label)
    return command, re.sub(r"^\S+\.\S+ ", "", what)


def _fast(command: str, label: str, seen: set) -> bool:
    """Whether the fast run tries this cell: the first of its kind (programmes: see
    ``FAST_PROGRAMMES``)."""
    if cell_kind(command, label) in seen:
        return False
    if command in ("theory", "sweep") and label.startswith("programme: "):
        return sum(c == command and w.startswith("programme: ") for c, w in seen) < FAST_PROGRAMMES
    return True


def select(catalogue, one_per_kind: bool) -> list:
    """The cells of ``catalogue`` (a list of :func:`cells`) that a run tries: all, or
    (``one_per_kind``) the first of each :func:`cell_kind` (:func:`_fast`)."""
    if not one_per_kind:
        return list(catalogue)
    seen, chosen = set(), []
    for cell in catalogue:
        if _fast(cell[0], cell[1], seen):
            chosen.append(cell)
            seen.add(cell_kind(cell[0], cell[1]))
    return chosen


def run_cells(chosen) -> list:
    """Run the cells ``chosen`` (command, input label, argv, inputs); one row each."""
    import warnings

    from stand.api.warmup import warmup

    # compile ahead: a cell's time limit is about input handling, not a cold compiler
    warmup(every_kind=True, say=lambda line: None, precompile=False)
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for cmd, label, argv, inputs in chosen:
            r = run_cell(argv, inputs)
            r.update(command=cmd, input=label)
            rows.append(r)
    return rows


def run_harness(tmp: Path, one_per_kind: bool = False) -> tuple:
    """All cells (``one_per_kind``: the first of each :func:`cell_kind`); returns (rows, table
    text)."""
    rows = run_cells(select(list(cells(tmp)), one_per_kind))
    return rows, _table(rows)


def _table(rows, total: bool = True) -> str:
    """The harness' table: per command the cells tried, the clear errors, the partial results
    and the bad outcomes (crash, hang, unclear, changed input), and (``total``) their sum."""
    table = {}
    for r in rows:
        t = table.setdefault(r["command"], {"tried": 0, "clear error": 0, "partial result": 0,
                                            "bad": 0})
        t["tried"] += 1
        if r["verdict"] in ("clear error", "partial result"):
            t[r["verdict"]] += 1
        else:
            t["bad"] += 1
    lines = [f"{'command':<22}{'tried':>7}{'clear error':>13}{'partial result':>16}"
             f"{'crash/hang/unclear/changed':>28}"]
    tot = {k: sum(t[k] for t in table.values()) for k in ("tried", "clear error", "partial result", "bad")}
    for cmd, t in [*table.items(), *([("all", tot)] if total else [])]:
        lines.append(f"{cmd:<22}{t['tried']:>7}{t['clear error']:>13}{t['partial result']:>16}"
                     f"{t['bad']:>28}")
    return "\n".join(lines)


def _report_ahead(folder: Path) -> None:
    """The speed map of the damaged recordings' scene, before the cells: under
    ``theory_computed_once`` it (seconds) is then computed outside any cell's time limit, as
    the kernels are compiled ahead (a cell's limit is about input handling).  Asked as the
    report's dynamics section asks it (``scene_theory(<the recording's scene>,
    closed_forms=False)``, stand.reports.balancing) of a good recording of that scene: the
    same key, without drawing a whole report (~1 s of figures) that no cell checks."""
    import warnings

    from stand.cli.main import main
    from stand.recording.hdf5 import read_recording
    from stand.theories.planar import speedmap

    folder.mkdir()
    scene = folder / "scene.toml"
    scene.write_text(_scene_text(BASES["ball_runup"]))
    with redirect_stdout(io.StringIO()), redirect_stderr(io.StringIO()):
        assert main(["run", str(scene), "-o", str(folder / "good.h5")]) == 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        speedmap.scene_theory(read_recording(folder / "good.h5").scene, closed_forms=False)


#: every command of the catalogue, one test each (pytest-xdist spreads them over its workers)
COMMANDS = ("run", "theory", "accuracy", "accuracy RK4", "experiment", "sweep", "analyze", "report",
            "snapshot", "track", "track --calibration", "strobe")


@pytest.fixture(scope="module")
def catalogue(tmp_path_factory):
    """Every cell of the catalogue, its input files written once per test process."""
    return list(cells(tmp_path_factory.mktemp("adversarial")))


def test_the_catalogue_crosses_every_command(catalogue):
    """The catalogue's size (the fast run: one cell per command and mutation kind, 308 cells;
    ``-m full``: ~800) and its commands: each is one test below."""
    assert len(select(catalogue, True)) >= 300 and len(catalogue) >= 700
    assert {cell[0] for cell in catalogue} == set(COMMANDS)


@pytest.mark.parametrize("one_per_kind", [True, pytest.param(False, marks=pytest.mark.full)],
                         ids=["one cell per kind", "every cell"])
@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_against_the_bad_input_catalogue(command, one_per_kind, catalogue, tmp_path,
                                                       record_property):
    """``command`` against its cells of the catalogue.  Fast: one cell per mutation kind
    (``_fast``); ``-m full``: every cell."""
    t0 = time.perf_counter()
    chosen = [cell for cell in select(catalogue, one_per_kind) if cell[0] == command]
    # the damaged recordings are all of one scene: its speed map, which every report of
    # them draws in its dynamics section, is computed once (_helpers.theory_computed_once)
    with theory_computed_once(shared=True):   # (once per session: tests/_shared.py)
        if command == "report":
            _report_ahead(tmp_path / "ahead")
        rows = run_cells(chosen)
    wall = time.perf_counter() - t0
    record_property("adversarial_table", f"{_table(rows, total=False)}   ({wall:.0f} s)")
    bad = [r for r in rows if r["verdict"] not in ("clear error", "partial result")]
    assert chosen, f"no cell of {command!r} in the catalogue"
    assert not bad, "\n".join(f"{r['command']} / {r['input']}: {r['verdict']}  ({' '.join(r['argv'])})"
                              for r in bad[:40])
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    assert peak < MEMORY_BOUND_BYTES, f"peak memory {peak / 2**30:.2f} GiB"


if __name__ == "__main__":  # pragma: no cover
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        t0 = time.perf_counter()
        rows, table = run_harness(Path(d))
        print(table)
        print(f"{len(rows)} cells in {time.perf_counter() - t0:.0f} s")
        for r in rows:
            if r["verdict"] not in ("clear error", "partial result"):
                print(f"  {r['command']} / {r['input']}: {r['verdict']}")
