"""The sweet spot located from each engine's own data, set beside the model's (section 1)."""

from __future__ import annotations

import math

import adapters

from . import answers as A
from .report import md_table


def sweet_engines_text(engines: tuple[str, ...]) -> str:
    """The sweet spot from each engine's data against the model's: float64 and float32 rigid
    contacts, and compliant ones, apart."""
    located, ref = A.engine_sweet_spots(engines), adapters.ContactReference.RIGID_IMPULSE
    kind = {
        n: "soft"
        if adapters.contact_reference(n) is not ref
        else adapters.record(n).errors.precision
        for n in engines
    }
    worst = {
        k: max(
            (abs(x) for n in engines if kind[n] == k for x in located[f"{n} - analytic (mm)"]),
            default=math.nan,
        )
        for k in ("float64", "float32", "soft")
    }
    group = {k: ", ".join(n for n in engines if kind[n] == k) for k in worst}
    soft = group["soft"] and (
        f"; {group['soft']}, whose contact converges to a compliant law, "
        f"up to\n{worst['soft']:.3g} mm from it (the rigid model is not "
        "its answer)"
    )
    single = group["float32"] and (
        f" ({group['float32']}, float32: up to {worst['float32']:.2g} mm, for v1 is flat at its "
        "maximum and an error dv in v1 moves the located maximum by up to sqrt(2 dv / |v1''|))"
    )
    return f"""\
Located from engine data alone (a bounded Brent search on each engine's v1(s), reference
profile), every float64 engine whose contact converges to the rigid impulse puts the sweet
spot within **{worst["float64"] * 1e3:.2g} um** of the
model{single}{soft} (engine minus model, mm):

{md_table(located, "{:.4g}")}

What this agreement confirms: the rigid-contact engines solve the same Newton-restitution impact
at the same e, so they confirm the model's arithmetic (the impulse, the swing, the search for the
maximum), not its physics. Whether a ball and bat obey one e and a rigid bat is for measurements
to say (sections 3c and 4). An engine with another contact law (a soft, compliant one) lands
elsewhere because it is a different model, not because it is wrong.
"""
