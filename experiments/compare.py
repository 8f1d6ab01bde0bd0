"""What changed between two sweep tables.

    python -m experiments.compare OLD.csv NEW.csv      (also: python -m experiments.sweep --compare)

Rows are matched on (engine, profile, bat, s, motion); timing columns are ignored. A row
missing, added or duplicated, a value blank or NaN on one side only, or a text that differs
(a status, how an episode ended) is a change.
Exit codes: 0 if nothing but timing changed, 1 otherwise, 2 if a file is not a sweep table.
"""

from __future__ import annotations

import csv
import math
import sys
from pathlib import Path

import pandas as pd

from .core.judge import Status
from .core.tables import TIMING_COLUMNS

KEYS = ["engine", "profile", "bat", "s_m", "v0_mps", "u0_mps", "omega0_radps", "e", "theta_rad"]
NUMERIC_KEYS = KEYS[3:]


def check_table(path: Path) -> None:
    """Raise ValueError unless ``path`` is a readable sweep table: a CSV with the key columns,
    numbers where numbers belong, every row of the header's width."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{str(path)!r} is not a file; "
                         "allowed: a sweep table (sweep.csv of a run)")
    try:
        _check_widths(path)
        table = read(path)
    except (UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError, OSError,
            csv.Error, ValueError) as err:
        raise ValueError(f"{str(path)!r} is not a CSV table ({err}); allowed: a sweep table "
                         "(sweep.csv of a run)".replace("\n", " ")) from None
    missing = [k for k in (*KEYS, "status", "v1_abs_err_mps") if k not in table.columns]
    if missing:
        raise ValueError(f"{str(path)!r} is not a sweep table (no column {missing[0]!r}); "
                         "allowed: a sweep table (sweep.csv of a run)")
    text = [k for k in (*NUMERIC_KEYS, "v1_abs_err_mps")
            if not pd.api.types.is_numeric_dtype(table[k])]
    if text:
        raise ValueError(f"{str(path)!r}: column {text[0]!r} holds text; allowed: a sweep table "
                         "(sweep.csv of a run)")


def _check_widths(path: Path) -> None:
    """ValueError at the first row whose width is not the header's (a truncated or damaged
    file: pandas would pad it with NaN, or take a wider row's first cell for an index)."""
    with open(path, newline="", encoding="utf-8", errors="strict") as f:
        rows = csv.reader(f)
        width = len(next(rows, []))
        for n, row in enumerate(rows, start=2):
            if row and len(row) != width:  # (pandas skips blank lines too)
                raise ValueError(f"line {n} has {len(row)} fields, the header {width}")


def read(path: Path) -> pd.DataFrame:
    """A sweep table; ParserError if a row is wider than the header."""
    return pd.read_csv(path, on_bad_lines="error", encoding="utf-8", encoding_errors="strict")


def compare_tables(old_path: Path, new_path: Path, out=sys.stdout) -> int:
    """Print added/removed/duplicated rows, status changes and the largest value changes per
    engine; a value that is blank or NaN on one side only is a change. Exit code 0 only if
    nothing but timing changed."""
    old = read(old_path).drop(columns=list(TIMING_COLUMNS), errors="ignore")
    new = read(new_path).drop(columns=list(TIMING_COLUMNS), errors="ignore")
    changed = False
    for label, table in (("old", old), ("new", new)):
        dup = int(table.duplicated(KEYS).sum())
        if dup:
            changed = True
            print(f"{label}: {dup} duplicated rows", file=out)
    both = old.merge(new, on=KEYS, how="outer", suffixes=("_old", "_new"), indicator=True)
    for side, label in (("left_only", "removed"), ("right_only", "added")):
        rows = both[both["_merge"] == side]
        if len(rows):
            changed = True
            print(f"{label}: {len(rows)} rows", file=out)
    common = both[both["_merge"] == "both"]
    status = common[common.status_old.fillna("") != common.status_new.fillna("")]
    for _, r in status.iterrows():
        changed = True
        print(f"{r.engine} s={r.s_m:.4f}: status {r.status_old} -> {r.status_new}", file=out)
    numeric = [c for c in old.columns if c not in KEYS and c != "status" and c in new.columns
               and pd.api.types.is_numeric_dtype(old[c])]
    text = [c for c in old.columns if c not in (*KEYS, "status", *numeric) and c in new.columns]
    for engine, df in common.groupby("engine", sort=False):
        for col in numeric:
            changed |= _column_change(engine, df, col, out)
        for col in text:  # how an episode ended, the rigid answer's end: blank is a value too
            moved = df[f"{col}_old"].fillna("") != df[f"{col}_new"].fillna("")
            if moved.any():
                changed = True
                r = df[moved].iloc[0]
                print(f"{engine} {col}: {int(moved.sum())} rows changed, first at "
                      f"s={r.s_m:.4f} ({r[f'{col}_old']!r} -> {r[f'{col}_new']!r})", file=out)
        for which in ("old", "new"):
            ok = df[df[f"status_{which}"] == Status.OK]
            if len(ok):
                worst = ok[f"v1_abs_err_mps_{which}"].max()
                print(f"{engine} max |v1 err| {which}: {worst:.3e} m/s", file=out)
    if not changed:
        print("no change apart from timing", file=out)
    return 1 if changed else 0


def _column_change(engine: str, df: pd.DataFrame, col: str, out) -> bool:
    """Print how one column changed for one engine (a NaN on one side only counts); whether it
    did."""
    a = pd.to_numeric(df[f"{col}_old"], errors="coerce")
    b = pd.to_numeric(df[f"{col}_new"], errors="coerce")
    one_nan = a.isna() != b.isna()
    diff = (b - a).abs().fillna(0.0)
    moved = (diff > 0) | one_nan
    if not moved.any():
        return False
    i = diff.mask(one_nan, math.inf).idxmax()  # a NaN on one side first
    print(f"{engine} {col}: {int(moved.sum())} rows changed, largest "
          f"{diff[i] if not one_nan[i] else math.nan:.3e} at s={df.loc[i, 's_m']:.4f} "
          f"({a[i]:.6g} -> {b[i]:.6g})", file=out)
    return True


def main(argv: list[str] | None = None) -> int:
    from .core.cli import Parser

    p = Parser(prog="python -m experiments.compare", description=__doc__.splitlines()[0],
               epilog="exit codes: 0 nothing but timing changed; 1 something else changed; 2 a "
                      "file that is not a sweep table")
    p.add_argument("old", type=Path, help="the earlier sweep table (a run's sweep.csv)")
    p.add_argument("new", type=Path, help="the later sweep table")
    args = p.parse_args(argv)
    for path in (args.old, args.new):
        try:
            check_table(path)
        except ValueError as err:
            p.error(str(err))
    return compare_tables(args.old, args.new)


if __name__ == "__main__":
    sys.exit(main())
