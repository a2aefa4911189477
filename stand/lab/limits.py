"""The shape limits of a lab table and its error, shared by every reader (issue 34: a
reader's work is bounded by its input; a lab export has tens of channels, not thousands)."""
from __future__ import annotations

__all__ = ["TableError", "check_shape", "MAX_COLUMNS", "CELL_BYTES"]

from stand.io.guard import memory_budget as _memory_budget

MAX_COLUMNS = 4096
#: parsing a cell costs ~3 float64 copies; the table may use a quarter of the memory
CELL_BYTES = 24


class TableError(ValueError):
    """A table that cannot be analysed; one line naming the file, column and rows."""


def check_shape(label: str, n_columns: int, n_rows: int) -> None:
    """Refuse a table wider than :data:`MAX_COLUMNS` or larger than the memory budget."""
    if n_columns > MAX_COLUMNS:
        raise TableError(f"{label}: {n_columns} columns, over the limit of {MAX_COLUMNS}; "
                         f"export only the channels to analyse")
    need = float(n_columns) * n_rows * CELL_BYTES
    if need > _memory_budget():
        raise TableError(f"{label}: {n_rows} rows x {n_columns} columns would need "
                         f"{need / 2 ** 30:.1f} GiB to read, over the limit of "
                         f"{_memory_budget() / 2 ** 30:.1f} GiB (a quarter of the memory); "
                         f"split the table or export fewer channels")
