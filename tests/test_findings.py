"""The findings report: generated whole, with its charts, and with the verdicts its numbers give.

The verdict checks restate physics, not the report's text: under the paper's u0 ~ 1/M swing a
lighter (corked) bat's COM is faster at the same omega0, so v1 at the sweet spot rises; under
omega0 ~ I_knob^-0.27 the lost mass costs more effective mass than the faster swing returns.
"""

from __future__ import annotations

import re

from analytic import SwingModel, presets
from experiments import findings


def test_report_is_complete(tmp_path):
    assert findings.main(["--out", str(tmp_path), "--name", "f"]) == 0
    tmp_path = tmp_path / "f"
    text = (tmp_path / "findings.md").read_text()
    for heading in ("## 1. Where is the sweet spot?", "## 2. Does corking help",
                    "## 3. Why are metal bats banned?", "## 4. Audit of the paper",
                    "## References"):
        assert heading in text
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    assert len(images) >= 3
    for name in images:
        assert (tmp_path / name).stat().st_size > 0
    for key in findings.REFS:  # every reference is cited somewhere in the text
        assert f"[{key}]" in text.split("## References")[0]


def test_cork_verdict_depends_on_the_swing_model():
    cork = presets.R161.corked()  # 1 x 10 in cork
    wood = {m: findings.model_v1(presets.R161, m)[3] for m in SwingModel}
    corked = {m: findings.model_v1(cork, m)[3] for m in SwingModel}
    assert corked[SwingModel.CONSTANT_FORCE] > wood[SwingModel.CONSTANT_FORCE]
    assert corked[SwingModel.MEASURED] < wood[SwingModel.MEASURED]
