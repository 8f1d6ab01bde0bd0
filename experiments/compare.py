"""What changed between two sweep tables.

    python -m experiments.compare OLD.csv NEW.csv      (also: python -m experiments.sweep --compare)

Rows are matched on (engine, profile, bat, s, motion); timing columns are ignored. A column
added, dropped or renamed, a row missing, added or duplicated, a value blank or NaN on one side
only, or a text that differs (a status, how an episode ended) is a change.
Exit codes: 0 if nothing but timing changed, 1 otherwise, 2 if a file is not a sweep table.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pandas as pd

from .core import boundary, cli, inputs
from .core.judge import Status
from .core.tables import TIMING_COLUMNS
from .errors import BadInput

KEYS = list(inputs.SWEEP_KEYS)
NUMERIC_KEYS = KEYS[3:]


def check_table(path: Path) -> None:
    """ValueError unless ``path`` is a sweep table (``inputs.SWEEP``: the one-line reason)."""
    try:
        inputs.table(path, inputs.SWEEP)
    except BadInput as err:
        raise ValueError(str(err)) from None


def compare_tables(old_path: Path, new_path: Path, out=None) -> int:
    """Print what changed between two sweep tables (``compare_frames``); BadInput if one is not
    a sweep table. Exit code 0 only if nothing but timing changed."""
    return compare_frames(
        inputs.table(old_path, inputs.SWEEP), inputs.table(new_path, inputs.SWEEP), out
    )


def compare_frames(old: pd.DataFrame, new: pd.DataFrame, out=None) -> int:
    """Print (to ``out``, default the stdout of the moment) the columns added, dropped or
    renamed, the added/removed/duplicated rows, status changes and the largest value changes per
    engine; a value that is blank or NaN on one side only is a change. Exit code 0 only if
    nothing but timing changed."""
    out = sys.stdout if out is None else out
    old = old.drop(columns=list(TIMING_COLUMNS), errors="ignore")
    new = new.drop(columns=list(TIMING_COLUMNS), errors="ignore")
    changed = False
    for label, table in (("old", old), ("new", new)):
        dup = int(table.duplicated(KEYS).sum())
        if dup:
            changed = True
            print(f"{label}: {dup} duplicated rows", file=out)
    pairs = _pairs(old, new)
    for side, label in (("left_only", "removed"), ("right_only", "added")):
        rows = pairs[pairs.side == side]
        if len(rows):
            changed = True
            print(f"{label}: {len(rows)} rows", file=out)
    common = pairs[pairs.side == "both"]
    a = old.iloc[common.row_old.astype(int)].reset_index(drop=True)
    b = new.iloc[common.row_new.astype(int)].reset_index(drop=True)
    changed |= _column_changes(old, new, a, b, out)
    moved = _text(a.status) != _text(b.status)
    for i in moved[moved].index:
        changed = True
        print(f"{a.engine[i]} s={a.s_m[i]:.4f}: status {a.status[i]} -> {b.status[i]}", file=out)
    for engine, idx in a.groupby("engine", sort=False).groups.items():
        changed |= _engine_changes(engine, a.loc[idx], b.loc[idx], out)
    if not changed:
        print("no change apart from timing", file=out)
    return 1 if changed else 0


def _pairs(old: pd.DataFrame, new: pd.DataFrame) -> pd.DataFrame:
    """Each row's key, its row number in each table (blank where it has none) and ``side``
    (both, left_only, right_only): the keys alone are merged, so that no column of the tables
    can meet a name the merge makes."""
    left = old[KEYS].assign(row=range(len(old)))
    right = new[KEYS].assign(row=range(len(new)))
    return left.merge(right, on=KEYS, how="outer", suffixes=("_old", "_new"), indicator="side")


def _text(col: pd.Series) -> pd.Series:
    """A column as text to compare, blank and NaN alike as ''."""
    return col.astype(object).where(col.notna(), "")


def _column_changes(
    old: pd.DataFrame, new: pd.DataFrame, a: pd.DataFrame, b: pd.DataFrame, out
) -> bool:
    """Print the columns dropped, added, or renamed (dropped and added with the same values on
    every row both tables hold); whether there was any."""
    dropped = [c for c in old.columns if c not in new.columns]
    added = [c for c in new.columns if c not in old.columns]
    for gone in list(dropped):
        same = next(
            (
                c
                for c in added
                if len(a) and _text(a[gone]).astype(str).equals(_text(b[c]).astype(str))
            ),
            None,
        )
        if same is not None:
            print(f"column renamed: {gone} -> {same} (the same values)", file=out)
            dropped.remove(gone)
            added.remove(same)
    for label, cols in (("dropped", dropped), ("added", added)):
        if cols:
            print(f"columns {label} ({len(cols)}): {', '.join(cols)}", file=out)
    return set(old.columns) != set(new.columns)


def _engine_changes(engine: str, a: pd.DataFrame, b: pd.DataFrame, out) -> bool:
    """Print how each column both tables hold changed for one engine's common rows, and each
    side's largest error of an ok impact; whether anything changed."""
    shared = [c for c in a.columns if c in b.columns and c not in (*KEYS, "status")]
    numeric = [c for c in shared if pd.api.types.is_numeric_dtype(a[c])]
    changed = False
    for col in shared:
        if col in numeric:
            changed |= _column_change(engine, a, b, col, out)
            continue
        moved = _text(a[col]) != _text(b[col])  # how an episode ended: blank is a value too
        if moved.any():
            changed = True
            i = moved.idxmax()
            print(
                f"{engine} {col}: {int(moved.sum())} rows changed, first at "
                f"s={a.s_m[i]:.4f} ({a[col][i]!r} -> {b[col][i]!r})",
                file=out,
            )
    for which, side in (("old", a), ("new", b)):
        ok = side[side.status == Status.OK]
        if len(ok):
            print(f"{engine} max |v1 err| {which}: {ok.v1_abs_err_mps.max():.3e} m/s", file=out)
    return changed


def _column_change(engine: str, a: pd.DataFrame, b: pd.DataFrame, col: str, out) -> bool:
    """Print how one column changed for one engine (a NaN on one side only counts); whether it
    did."""
    x = pd.to_numeric(a[col], errors="coerce")
    y = pd.to_numeric(b[col], errors="coerce")
    one_nan = x.isna() != y.isna()
    diff = (y - x).abs().fillna(0.0)
    moved = (diff > 0) | one_nan
    if not moved.any():
        return False
    i = diff.mask(one_nan, math.inf).idxmax()  # a NaN on one side first
    print(
        f"{engine} {col}: {int(moved.sum())} rows changed, largest "
        f"{diff[i] if not one_nan[i] else math.nan:.3e} at s={a.s_m[i]:.4f} "
        f"({x[i]:.6g} -> {y[i]:.6g})",
        file=out,
    )
    return True


@boundary.entry
def main(argv: list[str] | None = None) -> int:
    p = cli.Parser(
        prog="python -m experiments.compare",
        description=cli.summary(__doc__),
        epilog="exit codes: 0 nothing but timing changed; 1 something else changed; 2 a "
        "file that is not a sweep table",
    )
    p.add_argument("old", type=Path, help="the earlier sweep table (a run's sweep.csv)")
    p.add_argument("new", type=Path, help="the later sweep table")
    args = p.parse_args(argv)
    try:  # both read and checked before any comparison
        tables = [inputs.table(path, inputs.SWEEP) for path in (args.old, args.new)]
    except BadInput as err:
        p.error(str(err))
    return compare_frames(*tables)


if __name__ == "__main__":
    sys.exit(main())
