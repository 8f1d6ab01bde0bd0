"""The tables, the changes between releases, the page and the charts of ``experiments.history``."""

from __future__ import annotations

import io
import math
import re
from dataclasses import dataclass

import pandas as pd

import adapters

from ..core.io import json_bytes, provenance
from ..core.judge import Status
from ..parts.history_probe import GRIDS

#: Statuses of impacts the engine stepped (not refused before a step): their wall time is a cost.
STEPPED = tuple(
    str(s) for s in Status if s not in (Status.UNSUPPORTED, Status.ERROR, Status.TIMEOUT)
)
#: A check that did not run: the release lacks a feature the reference profile needs (its
#: impacts said so), or the check was not run for that reason.
LACKING = rf"in this release|\b{Status.UNSUPPORTED}\b|^not run"


#: history.csv's columns: a release's, then a grid's (blank for a release not judged).
SUMMARY = [
    "engine",
    "release",
    "state",
    "version",
    "numpy",
    "extras",
    "python",
    "checks_passed",
    "checks_failed",
    "checks_not_run",
    "grid",
    "impacts",
    "ok",
    "statuses",
    "max_err_mps",
    "cost_us_per_impact",
    "reason",
]


@dataclass(frozen=True, kw_only=True)
class Change:
    """What moved between two releases of an engine: ``regression`` when the later one lost
    a verdict or a check, or its error grew past the tolerance."""

    engine: str
    release: str
    text: str
    regression: bool = False


def _frame(records: list[dict], columns: list[str]) -> pd.DataFrame:
    return pd.DataFrame(records, columns=columns)


class Report:
    """The probes' results of every (engine, release) fired, in the order fired."""

    def __init__(self, results: list[dict]) -> None:
        self.results = results
        self.order: dict[str, list[str]] = {}
        for r in results:
            self.order.setdefault(r["engine"], []).append(r["release"])
        head = ["engine", "release"]
        self.rows = _frame(
            [
                {"engine": r["engine"], "release": r["release"], **row}
                for r in results
                for row in r.get("rows", [])
            ],
            head + ["grid", "s_m", "status", "err_mps", "tol_mps", "wall_s"],
        )
        self.checks = _frame(
            [
                {
                    "engine": r["engine"],
                    "release": r["release"],
                    "check": c["check"],
                    "outcome": _outcome(c),
                    "detail": c["detail"],
                }
                for r in results
                for c in r.get("checks", [])
            ],
            head + ["check", "outcome", "detail"],
        )

    def _result(self, engine: str, release: str) -> dict:
        return next(r for r in self.results if (r["engine"], r["release"]) == (engine, release))

    def summary(self) -> pd.DataFrame:
        """A row per release and grid (one row, with the reason, for a release not judged)."""
        out = []
        for r in self.results:
            head = {
                "engine": r["engine"],
                "release": r["release"],
                "state": r["state"],
                "version": r.get("version", ""),
                "numpy": r.get("numpy", ""),
                "extras": r.get("extras", ""),
                "python": r.get("python", ""),
            }
            checks = self.checks[
                (self.checks.engine == r["engine"]) & (self.checks.release == r["release"])
            ]
            head |= {
                "checks_passed": int((checks.outcome == "passed").sum()),
                "checks_failed": int((checks.outcome == "failed").sum()),
                "checks_not_run": int((checks.outcome == "not run").sum()),
            }
            rows = self.rows[
                (self.rows.engine == r["engine"]) & (self.rows.release == r["release"])
            ]
            if rows.empty:
                out.append({**head, "grid": "", "reason": r.get("reason", "")})
                continue
            for grid, g in rows.groupby("grid", sort=False):
                measured = g[g.status == Status.OK]  # as summary.md: errors over ok impacts
                out.append(
                    {
                        **head,
                        "grid": grid,
                        "impacts": len(g),
                        "ok": int((g.status == Status.OK).sum()),
                        "statuses": ", ".join(
                            f"{k} {v}" for k, v in g.status.value_counts().items()
                        ),
                        "max_err_mps": measured.err_mps.max() if len(measured) else math.nan,
                        "cost_us_per_impact": g[g.status.isin(STEPPED)].wall_s.median() * 1e6,
                        "reason": _reason(r, g),
                    }
                )
        return pd.DataFrame(out, columns=SUMMARY)  # every column, if no release was judged

    def changes(self, engine: str, before: str, after: str) -> list[Change]:
        """Everything that moved from ``before`` to ``after`` (a row each)."""

        def say(text: str, regression: bool = False) -> Change:
            return Change(engine=engine, release=after, text=text, regression=regression)

        a, b = self._result(engine, before), self._result(engine, after)
        out = []
        if a["state"] != b["state"]:
            why = f": {b['reason']}" if b.get("reason") else ""
            out.append(
                say(f"{a['state']} -> {b['state']}{why}"[:200], regression=a["state"] == "judged")
            )
        out += [say(t, lost) for t, lost in self._row_changes(engine, before, after)]
        ca = self.checks[(self.checks.engine == engine) & (self.checks.release == before)]
        cb = self.checks[(self.checks.engine == engine) & (self.checks.release == after)]
        moved = cb.assign(was=cb.check.map(dict(zip(ca.check, ca.outcome))))
        moved = moved[moved.was.notna() & (moved.was != moved.outcome)]
        for (was, now), g in moved.groupby(["was", "outcome"], sort=False):
            said = (
                g.check.iloc[0] + f" ({g.detail.iloc[0][:120]})"
                if len(g) == 1
                else f"{len(g)}: " + ", ".join(g.check)
            )
            out.append(say(f"checks {was} -> {now}: {said}", regression=was == "passed"))
        da, db = a.get("defaults", {}), b.get("defaults", {})
        out += [say(f"default {k}: {da[k]} -> {db[k]}") for k in db if k in da and da[k] != db[k]]
        return out

    def _row_changes(self, engine: str, before: str, after: str) -> list[tuple[str, bool]]:
        """The impacts that moved, a line per grid and kind of move: a status that changed
        (a regression if it was ok), an ok impact whose error moved past its tolerance (a
        regression if it grew)."""
        ra = self.rows[(self.rows.engine == engine) & (self.rows.release == before)]
        rb = self.rows[(self.rows.engine == engine) & (self.rows.release == after)]
        if rb.empty and self._result(engine, after)["state"] != "judged":
            return []  # nothing fired: the change of state says why
        both = ra.merge(rb, on=["grid", "s_m"], how="left", suffixes=("_a", "_b"))
        both["status_b"] = both.status_b.fillna("not fired")
        both["moved"] = abs(both.err_mps_b - both.err_mps_a) > both[["tol_mps_a", "tol_mps_b"]].max(
            axis=1
        )
        out = []
        for (grid, a, b), g in both.groupby(
            ["grid", "status_a", "status_b"], sort=False, dropna=False
        ):
            if a != b:
                out.append((f"{grid}: {_impacts(g)} {a} -> {b}{_worst(g)}", a == Status.OK))
                continue
            moved = g[g.moved & (g.status_a == Status.OK)]
            for grew, m in moved.groupby(moved.err_mps_b > moved.err_mps_a):
                out.append(
                    (
                        f"{grid}: {_impacts(m)} ok, error {'grew' if grew else 'shrank'} "
                        f"past its tolerance{_worst(m)}",
                        bool(grew),
                    )
                )
        return out

    def regressions(self, engine: str, reference: str, candidate: str) -> list[str]:
        return [c.text for c in self.changes(engine, reference, candidate) if c.regression]

    def verdict(self, engine: str, reference: str, candidate: str) -> tuple[int, str, str]:
        """The candidate checked against the reference: the exit code, the verdict's text, and
        why the check could not be made ('' if it was). It is made only where both were
        judged (a candidate the adapter cannot drive is judged: a regression, if the
        reference was driven); one that judged nothing never passes."""
        head = f"\n{engine} {candidate} against {reference}: "
        for release, role in ((reference, "the reference"), (candidate, "the candidate")):
            result = self._result(engine, release)
            why = unjudged(result)
            if why and not (role == "the candidate" and result["state"] == Status.UNSUPPORTED):
                said = f"not checked: {role} {release} could not be judged ({why})"
                return 1, head + said, f"{engine} {candidate} against {reference}: {said}"
        lost = self.regressions(engine, reference, candidate)
        if not lost:
            return 0, head + "no regression", ""
        return 1, head + f"{len(lost)} regressions\n" + "\n".join(f"  {c}" for c in lost), ""

    def nothing_judged(self) -> str:
        """Why no release at all could be judged ('' if one was): the first one's reason."""
        whys = [(r, unjudged(r)) for r in self.results]
        if not whys or any(why is None for _, why in whys):
            return ""
        first, why = whys[0]
        return f"no release could be judged ({first['engine']} {first['release']}: {why})"

    def all_changes(self) -> list[Change]:
        return [
            c
            for engine, listed in self.order.items()
            for a, b in zip(listed, listed[1:])
            for c in self.changes(engine, a, b)
        ]

    def files(self) -> dict[str, bytes]:
        summary, changes = self.summary(), self.all_changes()
        files = {
            "history.csv": _csv(summary),
            "history_rows.csv": _csv(self.rows),
            "history_checks.csv": _csv(self.checks),
            "history.json": json_bytes(
                {
                    "grids": GRIDS,
                    "changes": [c.__dict__ for c in changes],
                    "defaults": {
                        f"{r['engine']} {r['release']}": r.get("defaults", {}) for r in self.results
                    },
                    "errors": {
                        f"{r['engine']} {r['release']}": r["errors"]
                        for r in self.results
                        if r.get("errors")
                    },
                    "provenance": provenance(),
                }
            ),
            "history.md": page(summary, changes).encode(),
        }
        for engine in self.order:
            files[f"history_{engine}.png"] = chart(summary[summary.engine == engine], changes)
        return files

    def text(self) -> str:
        s = self.summary()
        cols = [
            c
            for c in (
                "engine",
                "release",
                "state",
                "grid",
                "ok",
                "impacts",
                "max_err_mps",
                "cost_us_per_impact",
                "checks_passed",
                "checks_failed",
            )
            if c in s
        ]
        return s[cols].to_string(index=False, float_format=lambda v: f"{v:.3g}")


def unjudged(result: dict) -> str | None:
    """Why a release was not judged, in a line (None if it was): no environment, a probe
    that failed, a release the adapter does not drive, or a probe that judged no impact and
    no check (each grid and the suite raised: its last error's last line)."""
    if result["state"] != "judged":
        return f"{result['state']}: {result.get('reason', '')}"[:300]
    if result.get("rows") or result.get("checks"):
        return None
    last = [
        ln
        for e in (result.get("errors") or {}).values()
        for ln in str(e).splitlines()
        if ln.strip()
    ][-1:]
    return "its probe judged no impact and no check" + (f" ({last[0][:200]})" if last else "")


def _outcome(check: dict) -> str:
    """passed, failed, or not run: the release lacks what the reference profile needs."""
    if check["passed"]:
        return "passed"
    return "not run" if re.search(LACKING, check["detail"]) else "failed"


def _impacts(g: pd.DataFrame) -> str:
    s = g.s_m
    where = f"s = {s.iloc[0]:+.3f} m" if len(g) == 1 else f"s {s.min():+.3f} to {s.max():+.3f} m"
    return f"{len(g)} impact{'s' if len(g) > 1 else ''} ({where})"


def _worst(g: pd.DataFrame) -> str:
    """The largest error after, beside its tolerance and the error before (m/s)."""
    i = g.err_mps_b.fillna(-1.0).idxmax()
    if math.isnan(g.err_mps_b[i]) and math.isnan(g.err_mps_a[i]):
        return ""
    before = "" if math.isnan(g.err_mps_a[i]) else f"{g.err_mps_a[i]:.2e} -> "
    return f"; worst error {before}{g.err_mps_b[i]:.2e} m/s, tolerance {g.tol_mps_b[i]:.2e}"


def _reason(result: dict, rows: pd.DataFrame) -> str:
    errors = result.get("errors", {})
    return errors.get(rows.grid.iloc[0], "")[-200:] if errors else ""


def _csv(df: pd.DataFrame) -> bytes:
    return df.to_csv(index=False, float_format="%.6g", lineterminator="\n").encode()


def page(summary: pd.DataFrame, changes: list[Change]) -> str:
    """history.md: per engine, a table of its releases and what moved at each."""
    lines = [
        "# Each engine's agreement with theory, release by release",
        "",
        "Made by `python -m experiments.history` (its docstring says what is fired). A row "
        "per release: for each grid the impacts `ok` (within the judge's tolerance of the "
        "answer that applies) and the largest error among them; the conformance "
        "checks passed / failed / not run (the release lacks a feature the reference "
        "profile needs); the cost of an impact on the swing grid. **Marked** releases "
        "moved (listed below the table); a verdict or check lost is a regression.",
        "",
    ]
    grids = list(GRIDS)
    for engine, df in summary.groupby("engine", sort=False):
        marked = {c.release for c in changes if c.engine == engine}
        lines += [
            f"## {engine}",
            "",
            f"![{engine} across releases](history_{engine}.png)",
            "",
            "| release | "
            + " | ".join(f"{g}: ok, max error (m/s)" for g in grids)
            + " | checks passed / failed / not run | us per impact (swing) |",
            "|" + "---|" * (len(grids) + 3),
        ]
        for release, r in df.groupby("release", sort=False):
            first = r.iloc[0]
            name = f"**{release}**" if release in marked else release
            if first.state != "judged" and r.grid.eq("").all():
                lines.append(
                    f"| {name} | {first.state}: {first.reason[:150]} |" + " |" * (len(grids) + 1)
                )
                continue
            cells = []
            for g in grids:
                row = r[r.grid == g]
                cells.append("" if row.empty else _cell(row.iloc[0]))
            swing = r[r.grid == "swing"].cost_us_per_impact.dropna()
            cost = f"{swing.iloc[0]:.0f}" if len(swing) else ""
            lines.append(
                f"| {name} | " + " | ".join(cells) + f" | {first.checks_passed} / "
                f"{first.checks_failed} / {first.checks_not_run} | {cost} |"
            )
        lines.append("")
        for c in (c for c in changes if c.engine == engine):
            lines.append(f"- {c.release}{' (regression)' if c.regression else ''}: {c.text}")
        install = adapters.record(engine).install
        lines += [
            f"- {r}, its release notes: {note}"
            for r, note in install.release_notes.items()
            if r in marked
        ]
        given = df[df.extras.fillna("") != ""].drop_duplicates("release")
        lines += [
            f"- {r.release} was judged with {r.extras} added (the release needs it but "
            "does not require it)"
            for r in given.itertuples()
        ]
        lines += ["", f"The adapter drives {engine} from release {install.oldest or '?'} on.", ""]
    return "\n".join(lines)


def _cell(row) -> str:
    """A grid's impacts ok, and its largest error, or its statuses where none was ok."""
    head = f"{row.ok:.0f}/{row.impacts:.0f}"
    err = _num(row.max_err_mps)
    return f"{head}, {err}" if err else f"{head} ({row.statuses})"


def _num(v: float) -> str:
    return "" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.1e}"


def chart(summary: pd.DataFrame, changes: list[Change]) -> bytes:
    """One engine: ok impacts, the largest error and the cost per impact against release."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    releases = list(dict.fromkeys(summary.release))
    x = {r: i for i, r in enumerate(releases)}
    fig, axes = plt.subplots(
        3, 1, figsize=(max(6.0, 0.7 * len(releases) + 3), 7.5), sharex=True, layout="constrained"
    )
    for i, (grid, marker) in enumerate(zip(GRIDS, "osD^")):
        g = summary[summary.grid == grid]
        xs = [x[r] for r in g.release]
        # a tenth of an impact apart, so that grids with equal counts stay visible
        axes[0].plot(xs, g.ok + 0.1 * (i - 1.5), marker=marker, label=grid)
        axes[1].plot(xs, g.max_err_mps.clip(lower=1e-16), marker=marker, label=grid)
        if grid.startswith("swing"):
            axes[2].plot(xs, g.cost_us_per_impact, marker=marker, color=f"C{i}", label=grid)
    engine = summary.engine.iloc[0]
    for r in summary[summary.grid == ""].itertuples():  # no impact fired: say why there
        for ax in axes:
            ax.text(
                x[r.release],
                0.5,
                r.state.replace("_", " "),
                rotation=90,
                ha="center",
                va="center",
                fontsize=8,
                color="0.4",
                transform=ax.get_xaxis_transform(),
            )
    regressed: dict[str, bool] = {}
    for c in changes:
        if c.engine == engine and c.release in x:
            regressed[c.release] = regressed.get(c.release, False) or c.regression
    for release, regression in regressed.items():
        for ax in axes:
            ax.axvspan(
                x[release] - 0.4,
                x[release] + 0.4,
                alpha=0.12,
                lw=0,
                color="tab:red" if regression else "tab:blue",
            )
    axes[0].set_ylabel(f"impacts ok (of {summary.impacts.max():.0f} a grid)")
    axes[1].set_ylabel("largest |error| of ok\nimpacts (m/s, log)")
    axes[1].set_yscale("log")
    axes[2].set_ylabel("cost per impact\nstepped (us)")
    axes[2].legend(fontsize=8)
    axes[2].set_xticks(range(len(releases)), releases, rotation=45, ha="right")
    axes[2].set_xlim(-0.6, len(releases) - 0.4)  # every release in view, fired or not
    axes[2].set_xlabel("release (shaded: something moved; red: a regression)")
    axes[0].legend(fontsize=8, ncol=2, loc="center right")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.suptitle(f"{engine} across its releases (R161, the paper's pitch)")
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    plt.close(fig)
    return buf.getvalue()


__all__ = ["Change", "Report", "chart", "page", "unjudged"]
