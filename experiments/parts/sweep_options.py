"""The sweep command's options (``python -m experiments.sweep --help``), and its refusals put
in the options' names."""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path

import adapters
from analytic import presets
from analytic.ball import LAWS
from analytic.model import (
    MAX_MU,
    MAX_OMEGA_RADPS,
    MAX_SPEED_MPS,
    MAX_SPIN_RADPS,
    WOOD_DENSITY_KGM3,
)

from ..core import cli

#: The restitution of a sweep unless --e says otherwise (wood on a baseball).
DEFAULT_E = presets.E_WOOD


#: Largest grid: beyond it a sweep is an accident.
MAX_POINTS = 10_000


def _add_cork(p: argparse.ArgumentParser) -> None:
    """--corked and the hole it drills."""
    p.add_argument("--corked", action="store_true", help="drill and fill the barrel end")
    for flag, metavar, text in (
        ("--hole-radius", "M", "hole radius (m, default 0.0127)"),
        ("--hole-depth", "M", "hole depth (m, default 0.254)"),
        ("--fill-density", "KGM3", "cork 200 (default), rubber 1100, hollow 0"),
        (
            "--wood-density",
            "KGM3",
            f"wood density (kg/m^3, default {WOOD_DENSITY_KGM3:.0f}: the R161's)",
        ),
    ):
        p.add_argument(
            flag, type=cli.number(0.0), default=None, metavar=metavar, help=f"with --corked: {text}"
        )


def _add_contact(p: argparse.ArgumentParser) -> None:
    """Friction, the third dimension and the flight (``analytic.friction``, ``core.carry``)."""
    num = cli.number
    p.add_argument(
        "--friction",
        type=num(0.0, MAX_MU),
        default=0.0,
        metavar="MU",
        help="Coulomb friction between ball and bat (default 0: frictionless)",
    )
    p.add_argument(
        "--undercut",
        type=num(unit="m"),
        default=0.0,
        metavar="M",
        help="ball centre above (+) or below the bat's axis, out of the swing plane",
    )
    p.add_argument(
        "--spin",
        type=num(-MAX_SPIN_RADPS, MAX_SPIN_RADPS, unit="rad/s"),
        default=0.0,
        metavar="RADPS",
        help="the pitch's backspin about the bat's axis (- : topspin)",
    )
    p.add_argument(
        "--flight",
        action="store_true",
        help="add launch_*_deg, carry_*_m and hang_*_s per row (analytic, engine)",
    )


def _add_speeds(p: argparse.ArgumentParser, pitch: float, swing) -> None:
    """--v0, --u0 and --omega0, within the ranges an analytic ImpactCase accepts."""
    num, fast, spin = cli.number, MAX_SPEED_MPS, MAX_OMEGA_RADPS
    p.add_argument(
        "--v0",
        type=num(0.0, fast, unit="m/s"),
        default=pitch,
        metavar="MPS",
        help=f"pitch speed (m/s, 0..{fast:g})",
    )
    p.add_argument(
        "--u0",
        type=num(-fast, fast, unit="m/s"),
        default=swing.u0_mps,
        metavar="MPS",
        help=f"bat COM speed (m/s, -{fast:g}..{fast:g})",
    )
    p.add_argument(
        "--omega0",
        type=num(-spin, spin, unit="rad/s"),
        default=swing.omega0_radps,
        metavar="RADPS",
        help=f"bat angular speed about its COM (rad/s, -{spin:g}..{spin:g})",
    )


def build_parser() -> argparse.ArgumentParser:
    swing, pitch = presets.PAPER_SWING, presets.PAPER_PITCH_MPS
    num = cli.number
    p = cli.Parser(
        prog="python -m experiments.sweep",
        description="Fire a ball along a bat in physics engines and compare with impact theory.",
        epilog=f"bats: {', '.join(presets.BATS)}. A run goes to runs/<name>/ (sweep.csv, "
        "sweep.json, sweep.png, run.json). "
        + cli.EXIT_CODES
        + "; with --compare: 0 nothing but timing changed, 1 something else did",
    )
    cli.add_engine(p)
    p.add_argument(
        "--profile",
        choices=adapters.PROFILES,
        default="reference",
        help="engine settings: tuned for fidelity, or the engine's own defaults",
    )
    p.add_argument(
        "--dt",
        type=num(0.0, 1.0, lo_open=True, unit="s"),
        default=None,
        metavar="S",
        help="override the profile's time step (s)",
    )
    p.add_argument(
        "--bat",
        choices=list(presets.BATS),
        default="r161",
        help="the bat (default r161, the paper's wood bat)",
    )
    _add_cork(p)
    p.add_argument(
        "--points",
        type=cli.integer(2, MAX_POINTS),
        default=41,
        help=f"impact points over the hittable length (2..{MAX_POINTS})",
    )
    p.add_argument(
        "--s-range",
        type=num(),
        nargs=2,
        default=None,
        metavar=("MIN", "MAX"),
        help="part of the bat to sweep, m from the COM (default: all of it)",
    )
    _add_speeds(p, pitch, swing)
    p.add_argument("--e", type=num(0.0, 1.0), default=DEFAULT_E, help="coefficient of restitution")
    p.add_argument(
        "--theta",
        type=num(-1.5707, 1.5707, unit="rad"),
        default=0.0,
        metavar="RAD",
        help="ball's angle to the contact normal",
    )
    _add_contact(p)
    _add_swing(p)
    p.add_argument(
        "--budget-h",
        type=cli.number(0.0, lo_open=True, unit="h"),
        default=1.0,
        metavar="HOURS",
        help="refuse a run estimated to take longer (default 1 h)",
    )
    cli.add_runner(p)
    cli.add_output(p)
    _add_reference(p)
    p.add_argument(
        "--no-locate",
        action="store_true",
        help="skip locating the sweet spot and COP from engine data",
    )
    p.add_argument(
        "--compare",
        nargs=2,
        type=Path,
        metavar=("OLD", "NEW"),
        help="print what changed between two sweep tables, then exit",
    )
    return p


def _add_swing(p: argparse.ArgumentParser) -> None:
    """The swing in the engine before each impact: whether, about where, through what angle."""
    num = cli.number
    p.add_argument(
        "--swing",
        action="store_true",
        help="swing the bat about the hands in the engine before each impact, with "
        "the constant torque that reaches --omega0 over --swing-angle; u0 is "
        "then omega0 times the hands-to-COM distance (--u0 is ignored)",
    )
    p.add_argument(
        "--hands",
        type=num(0.0, unit="m"),
        default=0.1,
        metavar="M",
        help="hands (pivot) from the knob, for --swing and the COP",
    )
    p.add_argument(
        "--swing-angle",
        type=num(0.0, 2 * math.pi, lo_open=True, unit="rad"),
        default=math.pi / 2,
        metavar="RAD",
        help="with --swing: the angle the bat turns through before the impact (rad, "
        "0 < angle <= 2 pi, default pi/2)",
    )


def _add_reference(p: argparse.ArgumentParser) -> None:
    """What the rows are predicted under besides the rigid answer."""
    p.add_argument(
        "--reference",
        choices=("rigid", "compliant"),
        default="rigid",
        help="compliant: also predict every impact under a contact law (--law) and "
        "put it beside the rigid answer (columns v1_compliant_mps, "
        "compliant_contact_s, compliant_bat_turn_rad, ...; a curve on the chart)",
    )
    p.add_argument(
        "--law",
        choices=tuple(LAWS),
        default=None,
        help="with --reference compliant: the contact law (default ball: a Hertz "
        "baseball whose COR follows the measured data, 0.7 ms at 40 m/s; "
        "hertz: the older one-dissipation law, its COR falling too steeply)",
    )


#: The analytic records' field names and the options that set them.
OPTION_OF = {
    "s_min": "--s-range MIN",
    "s_max": "--s-range MAX",
    "s_m": "s",
    "undercut_m": "--undercut",
    "v0_mps": "--v0",
    "u0_mps": "--u0",
    "omega0_radps": "--omega0",
    "theta_rad": "--theta",
    "mu": "--friction",
    "hole_radius_m": "--hole-radius",
    "hole_depth_m": "--hole-depth",
    "fill_density_kgm3": "--fill-density",
    "wood_density_kgm3": "--wood-density",
    "hands_from_knob_m": "--hands",
    "spin_radps": "--spin",
}


def in_options(message: str) -> str:
    """An analytic record's complaint in the options' names (a closing speed: the options that
    set it)."""
    out = re.sub(r"\b(" + "|".join(OPTION_OF) + r")\b", lambda m: OPTION_OF[m[1]], message)
    if "closing speed" in out and "--v0" not in out:
        out += " (the closing speed comes from --v0, --u0, --omega0, --theta and --s-range)"
    return out
