"""One impact's verdict: ``judge(case, outcome, error_model)``, the same judgement a table's
row gets (``tables.table``, which judges a whole firing at once in arrays), for one impact and
any error model (the engine's record's by default: a study or a test can ask what another
precision or contact law would allow)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import adapters
from analytic import ImpactCase

from .episode import SimOutcome
from .fire import Fired
from .judge import ERROR_MODELS, Status
from .tables import table


@dataclass(frozen=True, kw_only=True)
class Verdict:
    """``status``; the answer that applies (``reference``: 'rigid theory', 'its own contact
    law' or 'none'), the engine's v1 off it and the tolerance (m/s; NaN where unjudged)."""

    status: Status
    reference: str
    v1_err_mps: float
    v1_tol_mps: float


def judge(case: ImpactCase, outcome: SimOutcome,
          error_model: adapters.ErrorModel | None = None) -> Verdict:
    """The verdict on one fired impact, its tolerances from ``error_model``."""
    token = ERROR_MODELS.set({} if error_model is None else {outcome.engine: error_model})
    try:
        row = table([Fired(case, outcome, math.nan, math.nan)], "").iloc[0]
    finally:
        ERROR_MODELS.reset(token)
    if math.isfinite(row.v1_tol_mps):
        return Verdict(status=Status(row.status), reference="rigid theory",
                       v1_err_mps=float(row.v1_abs_err_mps), v1_tol_mps=float(row.v1_tol_mps))
    if math.isfinite(row.v1_law_tol_mps):
        return Verdict(status=Status(row.status), reference="its own contact law",
                       v1_err_mps=float(row.v1_law_err_mps),
                       v1_tol_mps=float(row.v1_law_tol_mps))
    return Verdict(status=Status(row.status), reference="none", v1_err_mps=math.nan,
                   v1_tol_mps=math.nan)
