"""The report's section on how a row is judged: the statuses and the tolerance table."""

from __future__ import annotations

from ..core import terms
from ..core.judge import Status
from .base import Results, lead


def section(res: Results) -> str:
    """The statuses, then every tolerance term with its value and reason (``core.terms``)."""
    rows = "\n".join(f"| `{name}` | {value:g} | {why} |" for name, value, why in terms.table())
    return "\n\n".join(
        [
            lead(
                "A row is `ok` only when the engine's impact is sound and matches, within its "
                "tolerance, the answer that applies:",
                [
                    "rigid-body theory for a rigid contact",
                    "the engine's own contact law for a soft one",
                    "the one-step frictional law with friction",
                    "the linear chain for a segmented bat",
                ],
            ),
            "The tolerance is built from the engine's error model (its float precision, its "
            "contact's declared biases: `adapters/errors.py`) and the terms below; one function "
            "turns it into the status (`answers.held_to`).",
            f"Statuses: {', '.join(f'`{s.value}`' for s in Status)}.",
            "| term | value | why |\n|---|---|---|\n" + rows,
        ]
    )
