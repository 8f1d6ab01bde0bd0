"""Answer the paper's questions with the harness: sweet spot, corked bats, metal bats, the ball
as it really is, and an audit of the paper.

    python -m experiments.findings [--engine all]

Writes findings.md and findings_*.png into the run directory (results/ by
``python -m experiments.baselines``). The numbers come from ``answers``, ``metal`` and ``carry``
(the rigid-bat model, flight, engines through the runner) and ``ball`` (the ball's assumed
COR law and its range); ``questions`` (sections 1-2), ``metal_text`` (3), ``carry_text`` (3b),
``flex_text`` (3c), ``ball`` (4) and ``report`` (the head, sections 5-6, the references) write
them up. ``referee`` collects every quoted number as a claim with its command, dependence and
source: the short answers quote claims only, and tests/test_findings_claims.py traces them.
``inputs`` declares the uncertain inputs with their ranges and sources, and ``ranges`` carries
them into every headline number (central, low-high, the input that moves it most).
Numbers from the literature carry their reference.
"""

from __future__ import annotations

import argparse

import adapters

from ..core import cli, estimate, runs
from ..core.cli import Command
from ..core.io import figure_png, provenance
from . import answers as A
from . import referee
from .ball import ball_section
from .carry_text import carry_section
from .flex_text import flex_section
from .gradient_text import fit_section
from .metal_text import metal_section
from .questions import cork_section, sweet_spot_section
from .report import (
    REFS,
    audit_section,
    engine_section,
    head_section,
    pyplot,
    references_section,
)

__all__ = ["COMMAND", "REFS", "main", "produce"]


#: The sections that fire no engine, as measured on 2 cores (s): the carry's frictional impacts
#: and flights, the flexible bat's beam, the ball's fit, the rest.
MODEL_S = {"cork, metal": 3.0, "carry": 45.0, "flex": 15.0, "ball": 3.0}
#: The J fit's descent through one differentiable engine, its compile included (s).
FIT_S = 20.0


def _shares_s(engines: tuple[str, ...]) -> dict[str, float]:
    """Each part's expected wall time (s): the engines' impacts (``engine_checks``) and their
    sweet-spot searches, then the model sections."""
    impacts = estimate.run_s(A.check_jobs(engines)[0])
    searches = estimate.search_s(A.sweet_spot_jobs(engines))
    fits = FIT_S * sum(1 for n in engines if adapters.record(n).can.autodiff)
    return {"engines": sum(impacts.values()) + sum(searches.values()) + fits, **MODEL_S}


def estimate_s(args: argparse.Namespace) -> float:
    """The run's expected wall time (s)."""
    return sum(_shares_s(tuple(args.engine)).values())


def produce(args: argparse.Namespace) -> tuple[dict[str, bytes], str]:
    """The report and its charts, with progress in percent of the expected work."""
    engines = tuple(args.engine)
    shares = _shares_s(engines)
    total = sum(shares.values())
    done = dict.fromkeys(shares, 0)
    with runs.Progress(100, "findings", unit="% of the work") as bar:

        def finished(part: str) -> None:
            done[part] = 1
            bar(round(100 * sum(shares[p] for p in done if done[p]) / total) - bar.done)

        with cli.runner(args) as runner:
            checks = A.engine_checks(runner, engines)
        sweet_text, sweet_figs, sweet = sweet_spot_section(engines)
        finished("engines")
        cork_text, cork_figs, cork = cork_section()
        metal_text, metal_figs, metal = metal_section()
        finished("cork, metal")
        carry_text, carry_figs, _ = carry_section()
        finished("carry")
        flex_text, _, flex = flex_section()
        finished("flex")
        ball_text, ball_figs, ball = ball_section()
        finished("ball")
    claims = referee.collect(sweet, cork, metal, ball, flex)
    head = head_section(provenance()["commit"], engines, referee.short_answers_text(claims))
    body = head + "\n".join(
        [
            sweet_text,
            cork_text,
            metal_text,
            carry_text,
            flex_text,
            ball_text,
            audit_section(sweet, cork),
            engine_section(checks, engines),
            fit_section(engines),
            referee.referee_section(claims),
            references_section(),
        ]
    )
    figs = {**sweet_figs, **cork_figs, **metal_figs, **carry_figs, **ball_figs}
    files = {name: figure_png(fig) for name, fig in figs.items()}
    plt = pyplot()
    for fig in figs.values():
        plt.close(fig)
    files["findings.md"] = body.encode()
    return files, f"findings.md and {len(figs)} charts"


COMMAND = Command(name="findings", doc=__doc__, produce=produce, estimate=estimate_s)
main = COMMAND.main
