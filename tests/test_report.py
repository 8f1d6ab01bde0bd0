"""results/report.md: generated from the files in results/, never by hand.

A stale report (results regenerated, report not) fails here; so does a number typed into the
narrative instead of read from a file (changing the file must change the report), and a chart
link to nothing.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pandas as pd
import pytest

from experiments import baselines, report
from experiments.core import terms
from experiments.core.judge import Status
from experiments.core.runs import RESULTS


@pytest.fixture(scope="module")
def committed() -> str:
    return (RESULTS / "report.md").read_text()


@pytest.fixture()
def copy(tmp_path: Path) -> Path:
    """A scratch copy of results/ to edit."""
    return Path(shutil.copytree(RESULTS, tmp_path / "results"))


def _edit_csv(path: Path, engine: str, column: str, value) -> None:
    df = pd.read_csv(path)
    df.loc[df.engine == engine, column] = value
    df.to_csv(path, index=False, lineterminator="\n")


def _diff(a: str, b: str) -> list[tuple[str, str]]:
    """The lines that differ between two reports of the same length."""
    la, lb = a.splitlines(), b.splitlines()
    assert len(la) == len(lb)
    return [(x, y) for x, y in zip(la, lb) if x != y]


def test_committed_report_is_what_the_results_give(committed):
    # Regenerate with: python -m experiments.baselines --only report
    assert report.render(RESULTS) == committed, (
        "results/report.md is stale: run `python -m experiments.baselines --only report`"
    )


def test_a_number_in_a_table_comes_from_its_csv(copy, committed):
    _edit_csv(copy / "bench_engines.csv", "pymunk", "simulate_per_collision_us", 777.7)
    changed = _diff(committed, report.render(copy))
    assert changed == [(old, new) for old, new in changed if old.startswith("| pymunk |")]
    assert len(changed) == 1
    assert changed[0][1].split(" | ")[2] == "778"


def test_a_ranking_in_a_sentence_is_computed(copy, committed):
    _edit_csv(copy / "bench_engines.csv", "rapier", "bare_per_step_us", 0.05)
    new = report.render(copy)
    assert "Per bare step the rigid-contact engines rank pymunk" in committed
    assert "Per bare step the rigid-contact engines rank Rapier (0.050 us), pymunk" in new


def _caught(text: str, engine: str) -> str:
    """The engine's line of the out-of-the-box catches (`defaults_caught.csv`)."""
    return next(
        ln for ln in text.splitlines() if ln.lstrip().startswith(f"- {engine} ") and " ok at " in ln
    )


def test_a_verdict_follows_the_numbers(copy, committed):
    # PyBullet catches exactly the share the tunnelling bound allows; one fewer and the
    # report must stop saying so.
    line = _caught(committed, "PyBullet")
    assert "PyBullet 24.8%" in line and "exactly the bound" in line
    caught = pd.read_csv(copy / "defaults_caught.csv")
    row = caught.engine == "pybullet"
    caught.loc[row, "ok"] -= 1
    caught.loc[row, "fraction_ok"] = caught.loc[row, "ok"] / caught.loc[row, "impacts"]
    caught.to_csv(copy / "defaults_caught.csv", index=False, lineterminator="\n")
    new = _caught(report.render(copy), "PyBullet")
    assert "PyBullet 24.7%" in new and "exactly the bound" not in new


def test_a_sweep_summary_number_reaches_the_narrative(copy, committed):
    # MJX's error is the float32 engines' largest: the range the narrative gives ends there
    meta = copy / "sweep_all_reference_r161_swing.json"
    text = meta.read_text()
    old = '"v1_abs_err_max_mps": 0.09495650794980293'
    assert old in text
    meta.write_text(text.replace(old, '"v1_abs_err_max_mps": 0.12'))
    new = report.render(copy)
    assert "1.0e-5-9.5e-2 m/s" in committed and "1.0e-5-9.5e-2 m/s" not in new
    assert "1.0e-5-1.2e-1 m/s" in new


def test_every_link_resolves(committed):
    for target in re.findall(r"\]\(([^)#]+\.(?:png|md))(?:#[^)]*)?\)", committed):
        assert (RESULTS / target).is_file(), target
    images = re.findall(r"!\[[^]]*\]\(([^)]+)\)", committed)
    assert "pareto.png" in images and len(images) >= 10
    headings = {report.anchor(h) for h in re.findall(r"^## (.+)$", committed, re.M)}
    for anchor in re.findall(r"\]\(#([^)]+)\)", committed):
        assert anchor in headings, anchor


def test_a_missing_study_is_named_not_fatal(copy):
    (copy / "pareto_cheapest.csv").unlink()
    text = report.render(copy)
    assert "*Not available: `pareto_cheapest.csv` is not in the results" in text
    assert "## Where methods fail\n\n![status over time step" in text


def test_an_infinite_value_is_a_damaged_file_named_not_a_crash(copy):
    # the commands write NaN for what was not measured, never Infinity: one that is there was
    # put there by hand, and the sections reading it say so
    name = "sweep_all_reference_r161_swing.json"
    path = copy / name
    path.write_text(
        re.sub(r'("v1_abs_err_max_mps": )[^,]+', r"\1Infinity", path.read_text(), count=1)
    )
    text = report.render(copy)
    assert f"damaged (Damaged: {name} (a value Infinity, which no command writes))" in text


def test_baselines_writes_the_report_last():
    assert baselines.PARTS[-1] == "report"
    assert baselines.parts_arg("report,sweeps") == ("sweeps", "report")
    assert baselines.STUDIES["report"].COMMAND.parser().parse_args([]).results == RESULTS


def test_the_command_writes_report_md(tmp_path, committed, capsys):
    assert report.main(["--out", str(tmp_path), "--name", "r"]) == 0
    assert (tmp_path / "r" / "report.md").read_text() == committed


def test_committed_engine_pages_are_what_the_results_give():
    # Regenerate with: python -m experiments.baselines --only report
    files = report.pages.pages(RESULTS)
    assert len(files) == 1 + len(
        set(pd.read_csv(RESULTS / "sweep_all_reference_r161_swing.csv").engine)
    )
    for name, data in files.items():
        assert (RESULTS / name).read_bytes() == data, f"results/{name} is stale"
    for target in re.findall(r"\]\(([^)]+\.md)\)", files["engines.md"].decode()):
        assert target in files or (RESULTS / target).is_file(), target


def test_a_page_reads_its_numbers_from_the_files(copy):
    # the ok count of the reference sweep, counted here; the best batch's cost and the
    # cheapest setting, edited in their CSVs, reach the page
    ref = pd.read_csv(copy / "sweep_all_reference_r161_swing.csv")
    name = sorted(set(ref.engine))[0]
    rows = ref[ref.engine == name]
    text = report.pages.page(copy, name)
    assert f"{(rows.status == Status.OK).sum()}/{len(rows)} ok" in text
    bench = pd.read_csv(copy / "bench_batches.csv")
    bench.loc[bench.engine == name, "us_per_impact"] += 1000.0
    bench.loc[(bench.engine == name) & (bench.batch == 10), "us_per_impact"] = 1.5
    bench.to_csv(copy / "bench_batches.csv", index=False, lineterminator="\n")
    cheap = pd.read_csv(copy / "pareto_cheapest.csv")
    at = (cheap.engine == name) & (cheap.target == report.pages.PAGE_TARGET)
    cheap.loc[at, ["winner", "setting"]] = [name, "a setting typed here"]
    cheap.to_csv(copy / "pareto_cheapest.csv", index=False, lineterminator="\n")
    text = report.pages.page(copy, name)
    assert "1.5 us in a batch of 10 " in text and "a setting typed here" in text


def test_the_batches_and_twins_numbers_come_from_their_files(copy):
    before = report.render(copy)
    batches = pd.read_csv(copy / "bench_batches.csv")
    best = batches[batches.engine == "newton"].impacts_per_s.idxmax()
    batches.loc[best, "impacts_per_s"] = 4.2e6
    batches.to_csv(copy / "bench_batches.csv", index=False, lineterminator="\n")
    twins = pd.read_csv(copy / "twins.csv")
    twins.loc[0, "max_abs_diff_mps"] = 0.0777
    twins.to_csv(copy / "twins.csv", index=False, lineterminator="\n")
    after = report.render(copy)
    assert "Newton 4.2e6/s" not in before and "Newton 4.2e6/s" in after
    assert "0.078 m/s" in after.split("**Twins.**")[1].split("\n\n")[0]


def test_no_line_of_the_report_is_over_500_characters(committed):
    # Readability (the issue: one fact per line): a long bullet is a lead and its sub-bullets.
    long = [ln[:60] for ln in committed.splitlines() if len(ln) > 500]
    assert not long, long


def test_a_record_text_is_listed_a_clause_a_line():
    # never cut inside brackets or code; a claim's reason after its colon is a fact of its own
    text = "a (x; y) b: c; d `e; f`. The g (h: i)."
    assert report.base.clauses(text) == ["a (x; y) b: c", "d `e; f`", "The g (h: i)"]
    assert report.base.claim(text) == ["a (x; y) b", "c", "d `e; f`", "The g (h: i)"]
    assert report.base.lead("head:", ["one", "", "two\n- three"]) == (
        "head:\n- one\n- two\n  - three"
    )


def test_the_report_does_not_repeat_the_summary_table(committed):
    rows = [ln for ln in (RESULTS / "summary.md").read_text().splitlines() if ln.startswith("| ")]
    assert len(rows) > 10 and not any(row in committed for row in rows)


def test_the_judging_section_lists_every_term_with_its_value(committed):
    # the tolerance table of the report is experiments.core.terms, term by term
    section = committed.split("## How an impact is judged")[1].split("\n## ")[0]
    for name, value, _ in terms.table():
        assert f"| `{name}` | {value:g} |" in section, name
