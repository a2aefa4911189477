"""The acceptance sizes of issue 44, too slow for the test suite (``tests/test_adversarial_files.py``
runs the same limits on small files).  A script, not a test::

    python benchmarks/bench_untrusted_files.py [--dir DIR] [--skip-big-sheet]

1. The xlsx bomb of the issue: a ~4 MB workbook whose one sheet unzips to ~1.4 GB of XML
   (30,000,000 rows).  ``stand analyze BOMB.xlsx`` runs in a child process; its wall time
   and peak resident memory (``os.wait4``) must be <= 10 s and < 500 MB, with exit 2 and one
   line.
2. A real sheet at Excel's limit: 1,048,576 rows (a header and 1,048,575 samples of time,
   x, y, written with ``r`` attributes as Excel writes them).  ``stand analyze SHEET.xlsx
   --columns ...`` must read it (exit 0 or 1, no refusal); its time and memory are printed.

Building the bomb takes ~30 s (1.4 GB through zlib), the sheet ~20 s.
"""
from __future__ import annotations

import argparse
import io
import os
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NS = b'<worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main">'


def _workbook(path: Path, write_sheet) -> Path:
    """A workbook from openpyxl's skeleton with ``sheet1.xml`` streamed by ``write_sheet(w)``."""
    import openpyxl

    buf = io.BytesIO()
    openpyxl.Workbook().save(buf)
    src = zipfile.ZipFile(buf)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED, compresslevel=6) as z:
        for info in src.infolist():
            if info.filename != "xl/worksheets/sheet1.xml":
                z.writestr(info.filename, src.read(info.filename))
                continue
            with z.open(info.filename, "w", force_zip64=True) as w:
                w.write(NS)
                write_sheet(w)
                w.write(b"</sheetData></worksheet>")
    return path


def bomb(path: Path, rows: int = 30_000_000) -> Path:
    def sheet(w):
        w.write(b"<sheetData>")
        chunk = b"<row><c><v>1.5</v></c><c><v>2.25</v></c></row>" * 100_000
        for _ in range(rows // 100_000):
            w.write(chunk)
    return _workbook(path, sheet)


def full_sheet(path: Path, rows: int = 1_048_576) -> Path:
    import numpy as np

    def sheet(w):
        w.write(f'<dimension ref="A1:C{rows}"/><sheetData>'.encode())
        w.write(b'<row r="1"><c r="A1" t="inlineStr"><is><t>time_s</t></is></c><c r="B1" '
                b't="inlineStr"><is><t>x_um</t></is></c><c r="C1" t="inlineStr"><is><t>y_um'
                b'</t></is></c></row>')
        for start in range(2, rows + 1, 65_536):
            r = np.arange(start, min(start + 65_536, rows + 1))
            t = (r - 2) * 1e-3
            x, y = 50 * np.cos(2 * np.pi * 20 * t), 50 * np.sin(2 * np.pi * 20 * t)
            w.write("".join(f'<row r="{i}"><c r="A{i}"><v>{a!r}</v></c><c r="B{i}"><v>{b!r}</v>'
                            f'</c><c r="C{i}"><v>{c!r}</v></c></row>'
                            for i, a, b, c in zip(r.tolist(), t.tolist(), x.tolist(), y.tolist())
                            ).encode())
    return _workbook(path, sheet)


def measure(argv) -> tuple:
    """(exit code, wall [s], peak resident memory [B], stderr, CPU [s]) of ``stand <argv>`` in a
    child (the CPU time tells the work apart from a loaded machine's waiting)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    t0 = time.perf_counter()
    p = subprocess.Popen([sys.executable, "-m", "stand", *map(str, argv)], env=env,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    err = p.stderr.read().decode(errors="replace")
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    return (p.returncode, time.perf_counter() - t0, usage.ru_maxrss * 1024, err,
            usage.ru_utime + usage.ru_stime)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dir", help="where to build the files (default: a temporary folder)")
    ap.add_argument("--skip-big-sheet", action="store_true")
    args = ap.parse_args(argv)
    ok = True
    with tempfile.TemporaryDirectory(dir=args.dir) as d:
        d = Path(d)
        t0 = time.perf_counter()
        b = bomb(d / "bomb.xlsx")
        info = zipfile.ZipFile(b).getinfo("xl/worksheets/sheet1.xml")
        print(f"bomb: {b.stat().st_size / 1e6:.1f} MB, sheet unzips to {info.file_size / 1e9:.2f} GB "
              f"(built in {time.perf_counter() - t0:.0f} s)")
        code, wall, peak, err, cpu = measure(["analyze", b])
        lines = [ln for ln in err.splitlines() if ln.strip()]
        good = code == 2 and len(lines) == 1 and wall <= 10 and peak < 500e6
        ok &= good
        print(f"  stand analyze: exit {code} in {wall:.1f} s (CPU {cpu:.1f} s), peak "
              f"{peak / 1e6:.0f} MB, {len(lines)} line(s): {'PASS' if good else 'FAIL'} (<= 10 s, < 500 MB, exit 2, 1 line)")
        print(f"  {lines[0] if lines else ''}")
        if not args.skip_big_sheet:
            t0 = time.perf_counter()
            s = full_sheet(d / "sheet.xlsx")
            print(f"sheet: 1,048,576 rows, {s.stat().st_size / 1e6:.1f} MB "
                  f"(built in {time.perf_counter() - t0:.0f} s)")
            code, wall, peak, err, cpu = measure(["analyze", s, "--columns",
                                             "time=time_s[s],x=x_um[um],y=y_um[um]"])
            good = code in (0, 1)
            ok &= good
            print(f"  stand analyze: exit {code} in {wall:.1f} s (CPU {cpu:.1f} s), peak "
                  f"{peak / 1e6:.0f} MB: "
                  f"{'PASS' if good else 'FAIL'} (read, not refused)")
            if not good:
                print(f"  {err.strip()[-300:]}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
