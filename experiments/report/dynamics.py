"""Swing dynamics: the rigid body in every engine and integrator, the swing into the impact,
and the swing-speed models side by side (swing*.csv, the hinged baseline sweep)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..core.judge import Status
from .base import (
    Results,
    bullets,
    label,
    lead,
    method,
    methods,
    names,
    num,
    precision,
    span,
    step,
)
from .data import need
from .impact import into_impact, models

SCENES = {
    "a": "a: force through COM",
    "b": "b: pure torque",
    "c0": "c: knob force, q = 0",
    "c45": "c: knob force, q = 45 deg",
    "c90": "c: knob force, q = 90 deg",
    "d": "d: torque, hinged at the hands",
}


def section(res: Results) -> str:
    swing = res.csv("swing.csv")
    meta = res.json("swing.json")
    dts = sorted(swing.dt_s.unique())
    head = "\n\n".join(
        [
            res.chart("swing.png", "swing scenes: error against time step"),
            lead(
                "The seed lecture's rigid body, in every engine and integrator, against closed "
                "form (`analytic.dynamics`), in four scenes:",
                [
                    "(a) a force through the COM",
                    "(b) a pure torque",
                    "(c) a force at the knob at q = 0, 45, 90 deg held in the bat's frame",
                    "(d) a torque on the bat hinged at the hands",
                ],
            ),
            "Where the force turns with the bat and no elementary closed form exists, the "
            "reference is solve_ivp, itself checked against the Fresnel-integral impulse-momentum "
            f"result. Errors at t = {meta['t_end_s']:g} s for dt = {step(dts[-1])} ... "
            f"{step(dts[0])} (`results/swing.csv`), fitted orders in `results/swing_orders.csv`:",
        ]
    )
    orders = res.csv("swing_orders.csv")
    (sweep,) = need(res, "swing")
    rigid = swing[swing.engine.isin(sweep.rigid)]
    points = [
        *free(rigid, orders),
        hinge(rigid, orders),
        single(swing, orders, meta, sweep),
        into_impact(res),
        end_point(res),
    ]
    return "\n\n".join([head, bullets(points), *models(res)])


def _methods(swing: pd.DataFrame, bits: str) -> list[str]:
    return list(dict.fromkeys(swing[swing.engine.map(precision) == bits].method))


def _order(orders: pd.DataFrame, scene: str, method: str, quantity: str) -> float:
    r = orders[
        (orders.scene == SCENES[scene]) & (orders.method == method) & (orders.quantity == quantity)
    ]
    return float(r.p.iloc[0]) if len(r) else math.nan


def _smallest(orders: pd.DataFrame, scene: str, method: str, quantity: str) -> float:
    r = orders[
        (orders.scene == SCENES[scene]) & (orders.method == method) & (orders.quantity == quantity)
    ]
    return float(r.err_at_smallest_dt.iloc[0]) if len(r) else math.nan


def free(swing: pd.DataFrame, orders: pd.DataFrame) -> list[str]:
    f64 = _methods(swing, "float64")
    still = swing[swing.scene.isin([SCENES["a"], SCENES["c0"]]) & swing.method.isin(f64)]
    worst = still[["angle_err_rad", "omega_err_radps", "com_speed_err_mps"]].max().max()
    turn = swing[
        swing.scene.isin([SCENES["b"], SCENES["c45"], SCENES["c90"]]) & swing.method.isin(f64)
    ]
    first = [m for m in f64 if abs(_order(orders, "b", m, "angle_err_rad") - 1) < 0.05]
    exact = [m for m in f64 if _smallest(orders, "b", m, "angle_err_rad") < 1e-9]
    second = [m for m in first if abs(_order(orders, "c90", m, "com_speed_err_mps") - 2) < 0.1]
    fourth = [m for m in exact if _order(orders, "c90", m, "com_speed_err_mps") > 3.5]
    p1 = [_order(orders, "b", m, "angle_err_rad") for m in first]
    return [
        lead(
            "**(a) and (c, q = 0): no turning, exact to rounding in every float64 engine**:",
            [
                f"errors at most {num(worst)}; velocity exact",
                "q = 0 gives no rotation, as the lecture says",
            ],
        ),
        lead(
            "**(b) and (c, q = 45/90): the bat turns**:",
            [
                f"omega exact: at most {num(turn.omega_err_radps.max())} rad/s off",
                "the angle off by alpha T dt / 2 (p = "
                f"{span(min(p1), max(p1), lambda v: f'{v:.2f}')}"
                f") in {methods(first)}, with the opposite sign in pymunk (it moves positions "
                "before velocities)",
                f"{methods(exact)} integrate{'s' if len(exact) == 1 else ''} the quadratic exactly",
                f"the turning force's COM velocity: second order in {methods(second)}"
                + (f", fourth in {methods(fourth)}" if fourth else ""),
                "a body-frame force must be turned with the angle the engine has when it updates "
                "velocities: pymunk moves positions first, so the adapter sets the force inside "
                "the "
                "body's velocity function (set before the step, it was one step stale and first "
                "order)",
                "loads in MuJoCo are site actuators in the bat's frame, so RK4 re-evaluates them "
                "at "
                "its stages",
            ],
        ),
    ]


def hinge(swing: pd.DataFrame, orders: pd.DataFrame) -> str:
    f64 = _methods(swing, "float64")
    dt = step(swing.dt_s.min())
    p = {m: _order(orders, "d", m, "omega_err_radps") for m in f64}
    second = [m for m in f64 if p[m] >= 1.7 and "RK4" not in m]
    higher = [m for m in f64 if "RK4" in m and p[m] < 3]
    return lead(
        "**(d) the hinge: omega = tau t / I_p is kept to second order** by each engine's "
        "releasable pivot:",
        [
            "pymunk PivotJoint with error_bias 0, PyBullet point-to-point constraint with erp 1, "
            "MuJoCo connect equality with solref (2 dt, 1)",
            lead(
                f"omega error at {dt}:",
                [
                    f"{num(_smallest(orders, 'd', m, 'omega_err_radps'))} rad/s ({method(m)}, "
                    f"p = {p[m]:.2f})"
                    for m in second
                ],
            ),
            "with the engines' own default joint settings the hinge drifts at first order (the "
            "reference profiles replace them)",
            "a MuJoCo hinge joint would be exact but cannot be let go of",
            f"{methods(higher)} do{'es' if len(higher) == 1 else ''} not help the constraint "
            "(p = " + names(f"{p[m]:.2f}" for m in higher) + ")"
            if higher
            else "",
        ],
    )


def single(swing: pd.DataFrame, orders: pd.DataFrame, meta: dict, sweep) -> str:
    f32 = _methods(swing, "float32")
    f64 = _methods(swing[swing.engine.isin(sweep.rigid)], "float64")
    if not f32:
        return ""
    p = [_order(orders, s, m, "omega_err_radps") for s in ("b", "c45", "c90") for m in f32]
    b = swing[swing.scene == SCENES["b"]]
    w = float(b.omega_ref_radps.iloc[0])
    dt = float(swing.dt_s.min())
    ulp = float(np.spacing(np.float32(w)))
    drake = _methods(swing[swing.engine.isin(sweep.compliant)], "float64")
    soft_hinge = [m for m in f32 if abs(_order(orders, "d", m, "omega_err_radps") - 1) < 0.2]
    facts = [
        f"{methods(f32)}: errors grow as the step shrinks (fitted p = "
        f"{span(min(p), max(p), lambda v: f'{v:.1f}', ' to ')} in omega)",
        f"each step adds alpha dt to an omega of ~{w:.0f} rad/s whose float32 ulp is "
        f"{num(ulp)} rad/s",
        f"so {meta['t_end_s'] / dt:,.0f} steps of {step(dt)} leave omega off by "
        + names(
            f"{num(_smallest(orders, 'b', m, 'omega_err_radps'))} ({method(m)})"
            for m in sorted(f32, key=lambda m: -_smallest(orders, "b", m, "omega_err_radps"))
        )
        + f" rad/s after {meta['t_end_s']:g} s of constant torque",
        "where the float64 engines are exact to "
        f"{num(max(_smallest(orders, 'b', m, 'omega_err_radps') for m in f64))}",
    ]
    facts += [
        f"{method(m)}'s hinge is soft (fixed in its binding) and drifts at first order: "
        f"omega {num(_smallest(orders, 'd', m, 'omega_err_radps'))} rad/s off at {step(dt)}"
        for m in soft_hinge
    ]
    if drake:
        pa = [_order(orders, "b", m, "angle_err_rad") for m in drake]
        facts.append(
            f"{methods(drake)} behave like the float64 engines: omega exact to "
            f"{num(max(_smallest(orders, 'b', m, 'omega_err_radps') for m in drake))}, angle off "
            f"by alpha T dt / 2, p = {span(min(pa), max(pa), lambda v: f'{v:.2f}')} (the hinge "
            "is a lock on a planar joint chain)"
        )
    return lead(
        "**The single-precision engines lose the swing to rounding at small steps**:", facts
    )


def end_point(res: Results) -> str:
    hinged, small = need(res, "hinged", "default_dt")
    groups = []
    for sw, who in (
        (hinged, hinged.of_precision("float64")),
        (
            small,
            [
                e
                for e in small.of_precision("float64")
                if small.counts(e).get(Status.OK, 0) == len(small.model)
            ],
        ),
    ):
        pairs = [(e, sw.rows(e).v1_abs_err_mps.to_numpy()[-2:]) for e in who]
        pairs = [(e, near, end) for e, (near, end) in pairs if end * 100 < near]
        if pairs:
            groups.append((sw.stem, pairs))
    if not groups:
        return ""
    ratio = [near / end for _, pairs in groups for _, near, end in pairs]
    s_end = hinged.model.s_m.iloc[-1]
    return lead(
        f"**The last point of a sweep, at the end of the cylinder** (s = {s_end:g} m), is "
        f"{span(min(ratio), max(ratio))}x better than its neighbour when the contact is seen "
        "late:",
        [
            f"`{stem}`: "
            + names(f"{label(e)} {num(end)} against {num(near)}" for e, near, end in pairs)
            + " m/s"
            for stem, pairs in groups
        ]
        + [
            "a late contact slides the foot along the axis toward the barrel, which moves the "
            "impact point everywhere else",
            "at the end of the cylinder the closest point of the axis is pinned at the end, so "
            "only the normal tilts, a second-order error",
        ],
    )
