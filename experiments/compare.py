"""What changed between two sweep tables.

    python -m experiments.compare OLD.csv NEW.csv      (also: python -m experiments.sweep --compare)

Rows are matched on (engine, profile, bat, s, motion); timing columns are ignored. Exit code 0
if nothing but timing changed, 1 otherwise.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pandas as pd

from .core.tables import TIMING_COLUMNS

KEYS = ["engine", "profile", "bat", "s_m", "v0_mps", "u0_mps", "omega0_radps", "e", "theta_rad"]


def check_table(path: Path) -> None:
    """Raise ValueError unless ``path`` is a readable sweep table (a CSV with the key columns)."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{str(path)!r} is not a file; "
                         "allowed: a sweep table (sweep.csv of a run)")
    try:
        columns = pd.read_csv(path, nrows=0).columns
    except (UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError, OSError) as err:
        raise ValueError(f"{str(path)!r} is not a CSV table ({type(err).__name__}); allowed: a "
                         "sweep table (sweep.csv of a run)") from None
    missing = [k for k in (*KEYS, "status", "v1_abs_err_mps") if k not in columns]
    if missing:
        raise ValueError(f"{str(path)!r} is not a sweep table (no column {missing[0]!r}); "
                         "allowed: a sweep table (sweep.csv of a run)")


def compare_tables(old_path: Path, new_path: Path, out=sys.stdout) -> int:
    """Print added/removed rows, status changes and the largest value changes per engine."""
    old = pd.read_csv(old_path).drop(columns=list(TIMING_COLUMNS), errors="ignore")
    new = pd.read_csv(new_path).drop(columns=list(TIMING_COLUMNS), errors="ignore")
    both = old.merge(new, on=KEYS, how="outer", suffixes=("_old", "_new"), indicator=True)
    changed = False
    for side, label in (("left_only", "removed"), ("right_only", "added")):
        rows = both[both["_merge"] == side]
        if len(rows):
            changed = True
            print(f"{label}: {len(rows)} rows", file=out)
    common = both[both["_merge"] == "both"]
    status = common[common.status_old != common.status_new]
    for _, r in status.iterrows():
        changed = True
        print(f"{r.engine} s={r.s_m:.4f}: status {r.status_old} -> {r.status_new}", file=out)
    numeric = [c for c in old.columns if c not in KEYS and c != "status"
               and pd.api.types.is_numeric_dtype(old[c])]
    for engine, df in common.groupby("engine", sort=False):
        for col in numeric:
            diff = (df[f"{col}_new"] - df[f"{col}_old"]).abs()
            if diff.max() > 0:
                changed = True
                i = diff.idxmax()
                print(f"{engine} {col}: {int((diff > 0).sum())} rows changed, largest "
                      f"{diff.max():.3e} at s={df.loc[i, 's_m']:.4f} "
                      f"({df.loc[i, f'{col}_old']:.6g} -> {df.loc[i, f'{col}_new']:.6g})",
                      file=out)
        for which in ("old", "new"):
            ok = df[df[f"status_{which}"] == "ok"]
            if len(ok):
                worst = ok[f"v1_abs_err_mps_{which}"].max()
                print(f"{engine} max |v1 err| {which}: {worst:.3e} m/s", file=out)
    if not changed:
        print("no change apart from timing", file=out)
    return 1 if changed else 0


def main(argv: list[str] | None = None) -> int:
    from .core.cli import Parser

    p = Parser(prog="python -m experiments.compare", description=__doc__.splitlines()[0])
    p.add_argument("old", type=Path)
    p.add_argument("new", type=Path)
    args = p.parse_args(argv)
    for path in (args.old, args.new):
        try:
            check_table(path)
        except ValueError as err:
            p.error(str(err))
    return compare_tables(args.old, args.new)


if __name__ == "__main__":
    sys.exit(main())
