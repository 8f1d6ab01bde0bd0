"""The paper's questions (findings.md, quoted from the file) and where every file came from."""

from __future__ import annotations

import re

import pandas as pd

from .base import Results, lead, md_table


def _anchor(heading: str) -> str:
    return re.sub(r"[^a-z0-9 _-]", "", heading.lower()).replace(" ", "-")


def section(res: Results) -> str:
    text = res.text("findings.md")
    lines = text.splitlines()
    start = next((i for i, ln in enumerate(lines) if ln.startswith("**Short answers**")), None)
    if start is None:  # a findings.md without its short answers: link it, quote nothing
        start = stop = len(lines)
    else:
        stop = next(
            (i for i, ln in enumerate(lines) if i > start and ln.startswith("## ")), len(lines)
        )
    short = "\n".join(lines[start:stop]).strip()
    heads = [ln[3:].strip() for ln in lines if ln.startswith("## ")]
    charts = [
        res.chart(n, n.removesuffix(".png").replace("_", " ")) for n in res.glob("findings_*.png")
    ]
    return "\n\n".join(
        part
        for part in [
            lead(
                "Full report with tables, charts, the audit of the paper and references: "
                "[findings.md](findings.md) (`python -m experiments.findings`). Its sections:",
                [f"[{h}](findings.md#{_anchor(h)})" for h in heads],
            ),
            "Its short answers (quoted from the file; its opening paragraph states the swings and "
            "the model they assume):"
            if short
            else "",
            "\n".join("> " + ln if ln else ">" for ln in short.splitlines()),
            *charts,
        ]
        if part
    )


def sources(res: Results) -> str:
    rows = []
    for name in res.glob("*.json"):
        prov = res.json(name).get("provenance")
        if not isinstance(prov, dict):
            continue
        stem = name.removesuffix(".json")
        rows.append(
            {
                "files": f"`{stem}.*`" if res.glob(f"{stem}.*") != [name] else f"`{name}`",
                "written by": f"`{prov.get('command', '?')}`",
                "commit": f"{str(prov.get('commit', '?'))[:10]}"
                + (" (dirty)" if prov.get("dirty") else ""),
                "date (UTC)": prov.get("date_utc", "?"),
            }
        )
    return (
        "Each result file's provenance, as its JSON records it (commit, and whether the "
        "code differed from it; the CSVs and charts of a study come from the same run as "
        "its JSON):\n\n" + md_table(pd.DataFrame(rows))
    )
