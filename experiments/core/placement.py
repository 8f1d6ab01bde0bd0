"""Placing the bodies: where an impact starts, so that the engine meets the contact as planned.

The analytic free motion is run backwards from the contact instant: at t = 0 the bat's COM is
at the origin with its axis along +x and the ball touches it at s (the world frame of
``adapters.interface``). The start lies T = (approach_steps - contact_phase) dt - overlap / v_c
before it, so that after ``approach_steps`` steps the bodies overlap by ``overlap_m`` plus
``contact_phase`` steps of closing. With a swing, the bat is first swung from rest about the
hands in the engine (``swing_case``), released, and meets the ball ``approach_steps`` later.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import chain
from operator import attrgetter
from types import SimpleNamespace

import numpy as np

from adapters import Hands, Settings, State
from analytic import Ball, Bat, ImpactCase, checks
from analytic.dynamics import Drive, HingedSwing

from . import geometry as g
from .terms import HITTABLE_SLACK_M

#: Where the ball waits while the bat swings: far from anything it could touch (m).
PARKED_BALL_Y_M = 100.0


def check_hittable(case: ImpactCase) -> None:
    """Raise ValueError unless s lies on the capsule's cylinder, where the contact normal is
    perpendicular to the axis as the impact model assumes (the caps would tilt it)."""
    bat = case.bat
    checks.in_range("s_m", case.s_m, bat.s_min_m - HITTABLE_SLACK_M, bat.s_max_m + HITTABLE_SLACK_M)


def min_dt_s(case: ImpactCase, settings: Settings) -> float:
    """The smallest step at which the start lies before the contact (T > 0): below it the
    ``overlap_m`` the contact is first seen at takes more than ``approach_steps`` steps of
    closing (along the normal: an undercut's is tilted), and the bodies would start inside each
    other (s)."""
    closing = case.closing_speed_mps * (math.cos(case.tilt_rad) if case.undercut_m else 1.0)
    return settings.overlap_m / (closing * (settings.approach_steps - settings.contact_phase))


def check_placement(case: ImpactCase, settings: Settings) -> None:
    """Raise ValueError naming dt_s and the smallest step that works when the bodies cannot be
    placed apart before the contact (``min_dt_s``)."""
    check_hittable(case)
    smallest = min_dt_s(case, settings)
    if not settings.dt_s > smallest:
        raise ValueError(
            f"dt_s={settings.dt_s:g} is too small to place this impact: the contact is first "
            f"seen overlap_m={settings.overlap_m:g} m deep, {settings.approach_steps} steps after "
            f"the start, at a closing speed of {case.closing_speed_mps:.4g} m/s; allowed: "
            f"dt_s > {smallest:.3g} s (or a smaller overlap_m)"
        )


#: The fields of ``ImpactCase`` that placing and measuring an impact read, as columns.
CASE_FIELDS = (
    "s_m",
    "v0_mps",
    "u0_mps",
    "omega0_radps",
    "theta_rad",
    "phi_rad",
    "hands_from_knob_m",
)


def distinct_cases(cases: Sequence[ImpactCase]) -> tuple[np.ndarray, np.ndarray]:
    """The distinct case objects of ``cases`` (by identity), ordered by it: the row where each
    first appears, and each row's index into them."""
    if len(cases) <= 1:  # (one case is its own: no sort to make)
        return np.arange(len(cases)), np.arange(len(cases))
    ids = np.fromiter(map(id, cases), dtype=np.int64, count=len(cases))
    _, first, inv = np.unique(ids, return_index=True, return_inverse=True)
    return first, inv.reshape(-1)


def case_columns(
    xp, cases: Sequence[ImpactCase], distinct: tuple[np.ndarray, np.ndarray] | None = None
) -> SimpleNamespace:
    """The cases' CASE_FIELDS and normal speeds (v0n, u0n, closing) in the namespace ``xp``
    of ``geometry`` (arrays over a batch; one case's own floats for one world), and
    ``turned``: None, or where a case has an undercut or a spinning ball, their columns
    (``undercut_m``, ``cos_tilt``, ``spin_x``/``_y``/``_z`` rad/s). A batch that repeats
    case objects (a grid tiled over many worlds) reads each distinct one once (``distinct``:
    ``distinct_cases``, where the caller knows it)."""
    if xp is not g.SCALARS and len(cases) > 1:
        first, inv = distinct_cases(cases) if distinct is None else distinct
        if len(first) < len(cases):
            return take_rows(_columns(xp, [cases[i] for i in first]), inv)
    return _columns(xp, cases)


def take_rows(cols: SimpleNamespace, rows) -> SimpleNamespace:
    """Case columns (and ``turned``'s) taken at ``rows`` (indices or a slice); what is not an
    array, one value for all, kept."""
    return SimpleNamespace(
        **{
            k: v[rows]
            if isinstance(v, np.ndarray)
            else take_rows(v, rows)
            if isinstance(v, SimpleNamespace)
            else v
            for k, v in vars(cols).items()
        }
    )


def _columns(xp, cases: Sequence[ImpactCase]) -> SimpleNamespace:
    """``case_columns`` of every case, one by one."""
    turned = None
    if any(c.undercut_m != 0.0 or c.spin_radps != (0.0, 0.0, 0.0) for c in cases):
        pick = (
            (lambda f: f(cases[0]))
            if xp is g.SCALARS
            else (lambda f: np.array([f(c) for c in cases]))
        )
        turned = SimpleNamespace(
            undercut_m=pick(attrgetter("undercut_m")),
            cos_tilt=pick(lambda c: math.cos(c.tilt_rad)),
            **{f"spin_{k}": pick(lambda c, i=i: c.spin_radps[i]) for i, k in enumerate("xyz")},
        )
    if xp is g.SCALARS:
        (c,) = cases
        return SimpleNamespace(
            **{f: getattr(c, f) for f in CASE_FIELDS},
            v0n_mps=c.v0n_mps,
            u0n_mps=c.u0n_mps,
            closing_speed_mps=c.closing_speed_mps,
            turned=turned,
        )
    values = np.fromiter(
        chain.from_iterable(map(attrgetter(*CASE_FIELDS), cases)),
        float,
        count=len(CASE_FIELDS) * len(cases),
    ).reshape(len(cases), -1)
    cc = SimpleNamespace(**dict(zip(CASE_FIELDS, values.T)))
    cc.v0n_mps = cc.v0_mps * np.cos(cc.theta_rad)
    cc.u0n_mps = cc.u0_mps * np.cos(cc.phi_rad)
    cc.closing_speed_mps = cc.v0n_mps + cc.u0n_mps + cc.omega0_radps * cc.s_m
    cc.turned = turned
    return cc


def check_placements(
    xp, cases: Sequence[ImpactCase], cc: SimpleNamespace, each: Sequence[Settings]
) -> None:
    """``check_placement`` for every case under its own settings (``cc`` the cases' columns
    with their ``contact_phase``; the other placement fields shared): the cases the columns
    flag are checked one by one, which raises with the message."""
    bat, st = cases[0].bat, each[0]
    off = (cc.s_m < bat.s_min_m - HITTABLE_SLACK_M) | (cc.s_m > bat.s_max_m + HITTABLE_SLACK_M)
    closing = cc.closing_speed_mps * (1.0 if cc.turned is None else cc.turned.cos_tilt)
    smallest = st.overlap_m / (closing * (st.approach_steps - cc.contact_phase))
    for i in xp.indices(off | xp.not_(st.dt_s > smallest)):
        check_placement(cases[i], each[i])


def start_states(xp, bat: Bat, ball: Ball, cc: SimpleNamespace, settings: Settings):
    """The states T seconds before contact (module docstring), one per case of the columns
    ``cc`` (each with its ``contact_phase``), as the batch takes them; returns (states, T).
    An undercut ball touches at (s, R cos tilt, undercut), first seen ``overlap_m`` deep along
    the tilted normal, which it closes at cos(tilt) times the planar closing speed; a spinning
    ball keeps its spin in free flight."""
    vc, turned = cc.closing_speed_mps, cc.turned
    if turned is not None:
        vc = vc * turned.cos_tilt
    T = (settings.approach_steps - cc.contact_phase) * settings.dt_s - settings.overlap_m / vc
    v_t, v_n = cc.v0_mps * xp.sin(cc.theta_rad), -cc.v0n_mps
    u_t, u_n = cc.u0_mps * xp.sin(cc.phi_rad), cc.u0n_mps
    reach = bat.radius_m + ball.radius_m
    if turned is None:
        return xp.from_cols(
            (
                cc.s_m - T * v_t,
                reach - T * v_n,
                v_t,
                v_n,
                0.0 * T,
                -T * u_t,
                -T * u_n,
                -T * cc.omega0_radps,
                u_t,
                u_n,
                cc.omega0_radps,
            )
        ), T
    zero = 0.0 * T
    return xp.from_cols(
        (
            cc.s_m - T * v_t,
            reach * turned.cos_tilt - T * v_n,
            v_t,
            v_n,
            turned.spin_z + zero,
            -T * u_t,
            -T * u_n,
            -T * cc.omega0_radps,
            u_t,
            u_n,
            cc.omega0_radps,
            turned.undercut_m + zero,
            zero,
            turned.spin_x + zero,
            turned.spin_y + zero,
            zero,
            zero,
            zero,
            zero,
            zero,
        )
    ), T


def start_state(case: ImpactCase, settings: Settings) -> tuple[State, float]:
    """One case's start state, T seconds before contact (module docstring); returns (state, T)."""
    cc = case_columns(g.SCALARS, [case])
    cc.contact_phase = settings.contact_phase
    return start_states(g.SCALARS, case.bat, case.ball, cc, settings)


@dataclass(frozen=True, kw_only=True)
class SwingPlan:
    """How to swing the bat into an impact: ``steps`` steps under ``swing.torque_nm`` about the
    hands pinned at ``pivot_xy_m`` (world, m), from rest at ``bat_start`` (world), then release
    (the analytic omega and angle at release: rad/s, rad)."""

    swing: HingedSwing
    steps: int
    pivot_xy_m: tuple[float, float]
    bat_start: State
    omega_release_radps: float
    angle_release_rad: float
    dt_s: float

    def hands(self, bat: Bat) -> Hands:
        """The swing's drive as the engine applies it: the hands' torque, hinged at the hands."""
        return hands_for(self.swing.drive(), bat, self.pivot_xy_m)


def hands_for(drive: Drive, bat: Bat, pivot_xy_m: tuple[float, float] = (0.0, 0.0)) -> Hands:
    """An ``analytic.dynamics.Drive`` resolved on one bat, as an engine applies it: its force
    at its arm from the COM, its torque, and its pivot (if any) hinged at ``pivot_xy_m``."""
    drive.check(bat)
    pivot = (
        None if drive.pivot_from_knob_m is None else drive.pivot_from_knob_m - bat.com_from_knob_m
    )
    return Hands(
        force_n=drive.force_n,
        angle_rad=drive.force_angle_rad,
        arm_m=drive.force_arm_m(bat),
        torque_nm=drive.torque_nm,
        pivot_from_com_m=pivot,
        pivot_xy_m=pivot_xy_m,
    )


def swing_case(
    bat: Bat,
    ball: Ball,
    *,
    s_m: float,
    v0_mps: float,
    e: float,
    swing: HingedSwing,
    settings: Settings,
    **contact,
) -> tuple[ImpactCase, SwingPlan]:
    """The impact that a hinged swing delivers, and the plan to simulate it in one run.

    The swing lasts a whole number of steps n = round(t/dt); at release (t_r = n dt, torque off,
    hands let go) the bat turns at omega0 = tau t_r / I_p and its COM moves at u0 = omega0 d on
    the hands' circle. ``approach_steps`` later the free bat meets the ball at s: by then it has
    turned omega0 T, so the impact frame sees the COM velocity tilted by phi = omega0 T (its
    straight-line motion from release). The ball waits far away during the swing.
    ``contact``: the case's friction and out-of-plane fields (``mu``, ``undercut_m``,
    ``spin_radps``), passed on to it.
    """
    dt = settings.dt_s
    steps = max(1, round(swing.duration_s(bat) / dt))
    t_r = steps * dt
    w0 = swing.omega_at(bat, t_r)
    d = swing.arm_m(bat)
    phi = 0.0
    for _ in range(3):  # T depends on the closing speed, which depends on phi; converges at once
        case = ImpactCase(
            bat=bat,
            ball=ball,
            s_m=s_m,
            v0_mps=v0_mps,
            u0_mps=w0 * d,
            omega0_radps=w0,
            e=e,
            phi_rad=phi,
            hands_from_knob_m=swing.hands_from_knob_m,
            **contact,
        )
        release, T = start_state(case, settings)
        phi = w0 * T
    case = ImpactCase(
        bat=bat,
        ball=ball,
        s_m=s_m,
        v0_mps=v0_mps,
        u0_mps=w0 * d,
        omega0_radps=w0,
        e=e,
        phi_rad=phi,
        hands_from_knob_m=swing.hands_from_knob_m,
        **contact,
    )
    release, _ = start_state(case, settings)
    px = release.bat_x_m - d * math.cos(release.bat_angle_rad)
    py = release.bat_y_m - d * math.sin(release.bat_angle_rad)
    a0 = release.bat_angle_rad - swing.angle_swept(bat, t_r)
    start = release._replace(
        bat_x_m=px + d * math.cos(a0),
        bat_y_m=py + d * math.sin(a0),
        bat_angle_rad=a0,
        bat_vx_mps=0.0,
        bat_vy_mps=0.0,
        bat_omega_radps=0.0,
        ball_x_m=0.0,
        ball_y_m=PARKED_BALL_Y_M,
        ball_vx_mps=0.0,
        ball_vy_mps=0.0,
        ball_omega_radps=0.0,
    )
    return case, SwingPlan(
        swing=swing,
        steps=steps,
        pivot_xy_m=(px, py),
        bat_start=start,
        omega_release_radps=w0,
        angle_release_rad=release.bat_angle_rad,
        dt_s=dt,
    )
