"""The findings' uncertain inputs, declared once (``INPUTS``: each with its central value, its
range and its source), and ``spread``, the one function that carries them into a number: it
evaluates a headline over the joint range of the inputs that number depends on and returns it
as central (low-high) with the input that moves it most.

The joint range is sampled at every corner of the box where the inputs are few (up to
CORNERS_UP_TO), else at a scrambled Sobol sample of it (``scipy.stats.qmc``, a fixed seed);
always with each input's own two ends, the others central (the single-input corners), which
name the input that moves the number most. A number whose inputs are not listed here depends
on none: the referee table says so.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import pandas as pd
from scipy.stats import qmc

from analytic import ball, presets
from analytic.flight import DRAG_SPREAD, LIFT_SPREAD

from . import answers as A
from .report import ranged

#: Up to this many inputs every corner of their box is evaluated (2^4 = 16); beyond it a
#: Sobol sample of SAMPLE_POINTS points (a power of two, as Sobol's balance needs).
CORNERS_UP_TO = 4
SAMPLE_POINTS = 16
#: The Sobol sample's seed: fixed, so that a number is the same on every run.
SEED = 58


@dataclass(frozen=True, kw_only=True)
class Input:
    """One uncertain input: ``key`` (a keyword of the functions it enters), ``label`` (as the
    text names it), ``unit``, its ``central`` value and its range ``low``-``high`` (in that
    unit), and its ``source``: a reference key, or "assumed" with the reason."""

    key: str
    label: str
    unit: str
    central: float
    low: float
    high: float
    source: str

    def __post_init__(self) -> None:
        if not self.low <= self.central <= self.high or not self.low < self.high:
            raise ValueError(f"{self.key}: low <= central <= high, low < high")
        if not self.source.strip():
            raise ValueError(f"{self.key}: every input needs a source (or 'assumed' and why)")


def _e_range() -> tuple[float, float]:
    """The ball's COR over COR_LAWS at the two swings' closing speeds (at the R161's sweet
    spot): the range of the rigid model's e."""
    speeds = [sc.v0_mps + sc.bat_speed_mps for sc in A.SCENARIOS]
    return min(ball.cor_range(v)[0] for v in speeds), max(ball.cor_range(v)[1] for v in speeds)


_LAW, _E = ball.COR_LAW, _e_range()
_PROFILE = "the R161's profile is not published; the fit (analytic.presets.r161_profile) assumes it"
#: The declared table: every uncertain input of the findings.
INPUTS = {
    i.key: i
    for i in (
        Input(
            key="e",
            label="ball-bat COR e of the rigid model",
            unit="1",
            central=A.E,
            low=_E[0],
            high=_E[1],
            source="0.5: [ncaa] cap, [nathan2000] 'about 0.5'; range: COR_LAWS at the swings' "
            "closing speeds (section 4)",
        ),
        Input(
            key="cor_ref",
            label="the ball's COR at 25.9 m/s",
            unit="1",
            central=_LAW.cor_ref,
            low=0.514,
            high=0.578,
            source="[mlbcor] specification band",
        ),
        Input(
            key="cor_exponent",
            label="the COR's fall with speed, e ~ v^-p",
            unit="1",
            central=_LAW.exponent,
            low=ball.EXPONENT_RANGE[0],
            high=ball.EXPONENT_RANGE[1],
            source="assumed (no speed-resolved data read): central through [nathan2000]'s "
            "qualitative 'about 0.5' at 50 m/s; 0 no fall, 1/4 [johnson1985]",
        ),
        Input(
            key="drag_scale",
            label="C_D over Nathan's",
            unit="1",
            central=1.0,
            low=1 - DRAG_SPREAD,
            high=1 + DRAG_SPREAD,
            source="[adair] C_D uncertain by 10%",
        ),
        Input(
            key="lift_scale",
            label="C_L over Nathan's",
            unit="1",
            central=1.0,
            low=1 - LIFT_SPREAD,
            high=1 + LIFT_SPREAD,
            source="assumed: the visible scatter of the lift data about the fit [nathancalc]",
        ),
        Input(
            key="spin_share",
            label="share of the pitch's spin the impact hands on",
            unit="1",
            central=1.0,
            low=0.0,
            high=1.0,
            source="1: rigid rolling (the model); 0: outgoing spin independent of incoming "
            "[nathan2012]; between, by less than rolling [crossnathan2006]",
        ),
        Input(
            key="spin_boost",
            label="batted backspin over rigid rolling's",
            unit="1",
            central=1.0,
            low=1.0,
            high=1.4,
            source="1: rigid rolling (the model); up to 1.4 [kensrud2017]",
        ),
        Input(
            key="wood_density_kgm3",
            label="density of the wood a hole removes",
            unit="kg/m^3",
            central=A.HOLE_WOOD_KGM3,
            low=presets.r161_profile()[1].density_kgpm3,
            high=672.0,
            source="640: a 1 x 10 in hole took 2.9 oz (82 g) from a wood bat [nathancork]; "
            "low: the R161's beam fit (section 3c); high: ash at 12% moisture, specific "
            "gravity 0.60 x 1.12 [woodhandbook]",
        ),
        Input(
            key="metal_com_fraction",
            label="metal bat's COM, share of its length from the knob",
            unit="1",
            central=A.AL.com_from_knob_m / A.AL.length_m,
            low=0.55,
            high=0.65,
            source="assumed, no source: the paper gives no balance point",
        ),
        Input(
            key="metal_rod_fraction",
            label="metal bat's J_cm, share of a uniform rod's",
            unit="1",
            central=A.AL.inertia_cm_kgm2 / (A.AL.mass_kg * A.AL.length_m**2 / 12),
            low=0.40,
            high=0.76,
            source="0.50: the paper's 70 lb in^2, unsourced; 0.76: the R161's [cross2009]; "
            "0.40 assumed",
        ),
        Input(
            key="modulus_scale",
            label="the wood's E and G over the handbook's",
            unit="1",
            central=1.0,
            low=0.8,
            high=1.2,
            source="assumed +-20%: about the scatter of E between pieces of one species "
            "(coefficient of variation 22% [woodhandbook])",
        ),
        Input(
            key="knob_radius_m",
            label="knob radius",
            unit="m",
            central=0.0215,
            low=0.019,
            high=0.024,
            source=f"assumed: {_PROFILE}",
        ),
        Input(
            key="handle_end_m",
            label="where the handle ends, from the knob",
            unit="m",
            central=0.254,
            low=0.20,
            high=0.30,
            source=f"assumed: {_PROFILE}",
        ),
        Input(
            key="barrel_radius_m",
            label="barrel radius",
            unit="m",
            central=0.03175,
            low=0.0315,
            high=0.5 * 2.61 * 0.0254,
            source=f"assumed (at most 2.61 in across [rules]): {_PROFILE}",
        ),
        Input(
            key="taper_exponent",
            label="taper's shape (1 a cone, 2 a flare)",
            unit="1",
            central=2.0,
            low=1.5,
            high=3.0,
            source=f"assumed: {_PROFILE}",
        ),
    )
}
#: Categorical inputs, each of a few named models (the first is the central one), and where
#: they are carried: the ball's loss and how a 0.7 ms contact time is read (section 3c).
MODEL_INPUTS = {
    "ball model": "Hunt-Crossley (rate-dependent loss) or hysteretic (rate-independent), with "
    "the same e(v) on a wall [sawicki2003] [nathan2000]: the loss law is not measured",
    "contact-time definition": "0.7 ms on a wall at 40 m/s [nathan2000], read as how long the "
    "force lasts or until the gap closes (analytic.ball.CONTACT_DEFINITIONS)",
}


@dataclass(frozen=True, kw_only=True)
class Spread:
    """A number over the joint range of its inputs: ``central`` (every input central), its
    ``low`` and ``high`` over the sample, the ``inputs`` it depends on, each one's value at its
    own low and high end with the others central (``ends``), and the ``driver``: the input whose
    ends move it most (its label, or a model input's name)."""

    central: float
    low: float
    high: float
    inputs: tuple[str, ...]
    ends: tuple[tuple[str, float, float], ...]
    driver: str

    def text(self, sign: str = "") -> str:
        """``central (low-high)`` in the figures the range allows (``report.ranged``)."""
        return ranged(self.central, self.low, self.high, sign)


def sample(keys: Sequence[str], table: dict[str, Input] = INPUTS) -> list[dict[str, float]]:
    """The points a number is evaluated at: central first, then each input's two ends (the
    others central), then every corner (up to CORNERS_UP_TO inputs) or a Sobol sample."""
    ins = [table[k] for k in keys]
    central = {i.key: i.central for i in ins}
    out = [central]
    out += [{**central, i.key: v} for i in ins for v in (i.low, i.high)]
    if len(ins) <= CORNERS_UP_TO:
        out += [
            dict(zip(keys, c, strict=True))
            for c in itertools.product(*[(i.low, i.high) for i in ins])
        ]
    else:
        unit = qmc.Sobol(d=len(ins), scramble=True, seed=SEED).random(SAMPLE_POINTS)
        box = qmc.scale(unit, [i.low for i in ins], [i.high for i in ins])
        out += [dict(zip(keys, (float(x) for x in row), strict=True)) for row in box]
    return out


def spread(
    fn: Callable[..., float], keys: Sequence[str], table: dict[str, Input] = INPUTS
) -> Spread:
    """``fn(**inputs)`` over the joint range of the inputs ``keys`` (``sample``)."""
    points = sample(keys, table)
    values = [float(fn(**p)) for p in points]
    n = len(keys)
    ends = tuple((k, values[1 + 2 * j], values[2 + 2 * j]) for j, k in enumerate(keys[:n]))
    driver = max(ends, key=lambda x: abs(x[2] - x[1]))[0] if keys else "-"
    return Spread(
        central=values[0],
        low=min(values),
        high=max(values),
        inputs=tuple(keys),
        ends=ends,
        driver=table[driver].label if keys else "-",
    )


def over_models(cases: dict[str, float], driver: str) -> Spread:
    """A number over the models of a categorical input (``MODEL_INPUTS``): the first case is
    central, ``driver`` the input's name."""
    values = list(cases.values())
    return Spread(
        central=values[0],
        low=min(values),
        high=max(values),
        inputs=(driver,),
        ends=((driver, min(values), max(values)),),
        driver=driver,
    )


def inputs_table() -> pd.DataFrame:
    """The declared table, as the findings print it."""
    rows = [
        {
            "input": i.label,
            "key": f"`{i.key}`",
            "central": f"{i.central:.4g}",
            "range": f"{i.low:.4g}-{i.high:.4g}",
            "unit": i.unit,
            "source": i.source,
        }
        for i in INPUTS.values()
    ]
    rows += [
        {"input": name, "key": "-", "central": "-", "range": "-", "unit": "-", "source": why}
        for name, why in MODEL_INPUTS.items()
    ]
    return pd.DataFrame(rows)
