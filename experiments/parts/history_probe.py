"""What ``experiments.history`` measures of one engine release, run inside that release's own
environment (``experiments.core.releases``):

    python -m experiments.parts.history_probe --engine NAME --out FILE.json

- the grids (GRIDS: R161, POINTS points, the paper's pitch): every impact's status, v1 error
  against the answer that applies (a compliant contact's own law, else rigid theory), its
  tolerance and its wall time; each at the reference profile, and the swing also at the engine's
  own defaults (which need no feature a release may lack);
- the conformance suite (``check_engine``: the friction wall among its checks) at the
  reference profile: each check's pass and what it saw;
- the engine's defaults read back, and the versions the environment holds.
Writes FILE.json whatever happens to the engine (an engine that cannot be imported or raises is
said in it); exits 0 once written.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import traceback
from importlib import metadata

import numpy as np

import adapters
from analytic import presets
from analytic.dynamics import HingedSwing

from ..core import check, firings, tables
from ..core.hosting import hosted
from ..core.runner import Runner
from . import sweep_options

#: name -> sweep options: the still, swing and hinged reference grids, and the swing at defaults.
GRIDS = {
    "still": ["--u0", "0", "--omega0", "0"],
    "swing": [],
    "hinged": ["--swing"],
    "swing, default": ["--profile", "default"],
}
POINTS = 11
#: The row columns kept per impact (``history_rows.csv``).
COLUMNS = ("s_m", "status", "err_mps", "tol_mps", "wall_s")


def firing(grid: str) -> tuple[firings.Firing, str]:
    """The grid's impacts, with the sweep's defaults for what its options leave out, and the
    profile it is fired at."""
    a = sweep_options.build_parser().parse_args(["--points", str(POINTS), *GRIDS[grid]])
    bat = presets.R161
    swing = (
        HingedSwing.for_omega(bat, a.omega0, hands_from_knob_m=a.hands, angle_rad=a.swing_angle)
        if a.swing
        else None
    )
    u0 = a.omega0 * swing.arm_m(bat) if swing else a.u0
    return firings.Firing(
        bat=bat,
        s_m=firings.grid(bat, POINTS),
        v0_mps=a.v0,
        u0_mps=u0,
        omega0_radps=a.omega0,
        e=a.e,
        hands_from_knob_m=a.hands,
        swing=swing,
    ), a.profile


def grid_rows(name: str, grid: str) -> list[dict]:
    """Each impact of one grid: status, the judged error and its tolerance (m/s), wall time."""
    f, profile = firing(grid)
    with Runner() as runner:
        table = tables.table(
            runner.fire(f.jobs(name, adapters.settings_for(name, profile))), profile
        )
    law = table.v1_law_tol_mps.notna()
    err = np.where(law, table.v1_law_err_mps, table.v1_abs_err_mps)
    tol = np.where(law, table.v1_law_tol_mps, table.v1_tol_mps)
    return [
        {
            "grid": grid,
            "s_m": float(s),
            "status": str(st),
            "err_mps": float(e),
            "tol_mps": float(t),
            "wall_s": float(w),
        }
        for s, st, e, t, w in zip(table.s_m, table.status, err, tol, table.wall_s)
    ]


def checks(name: str) -> list[dict]:
    """The conformance suite at the reference profile; every check not run, with the reason,
    where the release cannot build the reference profile's scene."""
    scene = adapters.Scene(bat=presets.R161, ball=presets.BASEBALL, e=presets.E_WOOD)
    try:
        hosted(name, adapters.settings_for(name)).batch(scene, 1)
    except adapters.MissingFeature as err:
        return [
            {"check": c, "passed": False, "detail": f"not run: {err}"}
            for c in check.applicable(name)
        ]
    report = check.check_engine(name)
    return [{"check": r.name, "passed": r.passed, "detail": r.detail[:300]} for r in report.results]


def defaults(name: str) -> dict:
    """The engine's defaults as this release reads them back (str: JSON keeps them as said)."""
    read = adapters.engine_class(name).read_back_defaults()
    return {k: str(v) for k, v in read.items()}


def _guarded(out: dict, key: str, fn, *args) -> None:
    try:
        out[key] = fn(*args)
    except Exception:  # the release broke the adapter here: said in the file, not a crash
        out.setdefault("errors", {})[key] = traceback.format_exc(limit=3)[-600:]


def probe(name: str) -> dict:
    rec = adapters.record(name)
    out = {
        "engine": name,
        "python": platform.python_version(),
        "version": metadata.version(rec.install.package),
        "numpy": metadata.version("numpy"),
    }
    try:
        adapters.engine_class(name)
    except Exception as err:  # an import that fails: the release is not one the adapter drives
        out["not_driven"] = f"{type(err).__name__}: {err}"[:300]
        return out
    out["rows"] = []
    for grid in GRIDS:
        try:
            out["rows"] += grid_rows(name, grid)
        except Exception:
            out.setdefault("errors", {})[grid] = traceback.format_exc(limit=3)[-600:]
    _guarded(out, "checks", checks, name)
    _guarded(out, "defaults", defaults, name)
    return out


#: The keys of what ``probe`` writes, by what they hold (JSON's own kinds).
SHAPE = {"rows": list, "checks": list, "defaults": dict, "errors": dict, "not_driven": str}
#: The keys of each of its rows, and of each check.
ROW_KEYS, CHECK_KEYS = ("grid", *COLUMNS), ("check", "passed", "detail")
#: What each of a row's values may be (JSON null: an impact that measured nothing).
ROW_KINDS = {
    "grid": (str,),
    "s_m": (float, int),
    "status": (str,),
    "err_mps": (float, int, type(None)),
    "tol_mps": (float, int, type(None)),
    "wall_s": (float, int, type(None)),
}


def fault(result: object) -> str | None:
    """Why ``result`` is not what ``probe`` writes (None if it is): not a JSON object, neither
    rows nor ``not_driven``, a key of another kind, a row or check without its keys. The
    history reads a release's result through this, so that a garbled one is a row that says
    so, never a crash."""
    if not isinstance(result, dict):
        return f"a JSON {_json_kind(result)}, not an object"
    if "rows" not in result and "not_driven" not in result:
        return "an object with neither 'rows' nor 'not_driven'"
    for key, kind in SHAPE.items():
        if key in result and not isinstance(result[key], kind):
            return f"its {key!r} is a JSON {_json_kind(result[key])}, not {_json_kind(kind())}"
    for key, keys in (("rows", ROW_KEYS), ("checks", CHECK_KEYS)):
        for i, item in enumerate(result.get(key, [])):
            if not isinstance(item, dict) or not set(keys) <= set(item):
                return f"its {key} item {i + 1} is not an object with {', '.join(keys)}"
    for i, row in enumerate(result.get("rows", [])):
        for column, kinds in ROW_KINDS.items():
            if type(row[column]) not in kinds:  # (bool is no number here)
                return (
                    f"its rows item {i + 1} has {column} a JSON "
                    f"{_json_kind(row[column])}, not {_json_kind(kinds[0]())}"
                )
    return None


def _json_kind(value: object) -> str:
    return {
        dict: "object",
        list: "list",
        str: "string",
        bool: "true/false",
        int: "number",
        float: "number",
        type(None): "null",
    }.get(type(value), type(value).__name__)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.parts.history_probe")
    p.add_argument("--engine", required=True, choices=adapters.names())
    p.add_argument("--out", required=True)
    args = p.parse_args(argv)
    result = probe(args.engine)
    with open(args.out, "w") as f:
        json.dump(result, f)
    return 0


if __name__ == "__main__":
    sys.exit(main())
