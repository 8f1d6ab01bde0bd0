"""The rigid answer to an impact with friction or out of the swing plane, as an episode.

``analytic.collide`` follows a frictionless impact in the swing plane through re-contacts and
sustained contact. With friction (``ImpactCase.mu``), an undercut or a spinning ball, the
reference is one impulse integrated through slip and stick (``analytic.friction``, Routh's
method), and it is the whole answer only if free flight then takes the bodies apart for good:
in the plane ``collide.separates_for_good`` / ``collide.free_flight``, out of it
``spatial.free_flight_3d``. Where they would meet again (a small e, the ball riding the
turning bat) the episode ends 'meets_again': there is no frictional reference beyond one
impulse, and an engine's row is left unjudged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .collide import (
    MAX_EPISODE_S,
    CollisionEpisode,
    PlanarState,
    first_touch,
    free_flight,
    separates_for_good,
)
from .friction import FrictionOutcome, predict_friction
from .model import ImpactCase
from .spatial import axis_of, free_flight_3d


@dataclass(frozen=True, kw_only=True)
class FrictionEpisode(CollisionEpisode):
    """``CollisionEpisode`` of one frictional impulse (``ended``: 'separated', 'left_cylinder',
    'time_limit' or 'meets_again'), with the impulse's outcome in 3D (``friction``: both
    bodies' velocities and spins, impact frame)."""

    friction: FrictionOutcome

    @property
    def ball_velocity_mps(self) -> tuple[float, float, float]:
        return self.friction.ball_velocity_mps

    @property
    def ball_spin_radps(self) -> tuple[float, float, float]:
        return self.friction.ball_spin_radps


def frictional_episode(
    case: ImpactCase, *, max_episode_s: float = MAX_EPISODE_S, law: str = "routh"
) -> FrictionEpisode:
    """One frictional impulse for ``case`` under ``law`` (``analytic.friction.LAWS``: Routh's,
    or a law an impulse engine solves in one step), then free flight (module docstring)."""
    bat, ball = case.bat, case.ball
    out = predict_friction(case, law=law)
    reach = bat.radius_m + ball.radius_m
    y0 = first_touch(case)
    bv, bw = np.array(out.bat_velocity_mps), np.array(out.bat_omega_radps)
    vb = np.array(out.ball_velocity_mps)
    y = np.array([case.s_m, y0[1], vb[0], vb[1], 0.0, 0.0, bv[0], bv[1], 0.0, bw[2]])
    if case.out_of_plane:
        tilt = case.tilt_rad
        rel = np.array([case.s_m, reach * math.cos(tilt), reach * math.sin(tilt)])
        _, why = free_flight_3d(
            rel,
            vb - bv,
            axis_of(0.0, 0.0),
            bw,
            reach_m=reach,
            ball_radius_m=ball.radius_m,
            s_min_m=bat.s_min_m,
            s_max_m=bat.s_max_m,
            t_max_s=max_episode_s,
        )
    elif separates_for_good(
        PlanarState.of(y), reach_m=reach, ball_radius_m=ball.radius_m, t_max_s=max_episode_s
    ):
        why = "separated"
    else:
        _, why = free_flight(
            PlanarState.of(y),
            reach_m=reach,
            ball_radius_m=ball.radius_m,
            s_min_m=bat.s_min_m,
            s_max_m=bat.s_max_m,
            t_max_s=max_episode_s,
        )
    m = ball.mass_kg
    V = case.u0n_mps + case.omega0_radps * case.s_m
    v1 = float(vb[1])
    hands = case.hands_from_knob_m - bat.com_from_knob_m
    return FrictionEpisode(
        v1_mps=v1,
        u1_mps=float(bv[1]),
        omega1_radps=float(bw[2]),
        impulse_ns=m * (v1 + case.v0n_mps),
        q=(v1 - V) / (case.v0n_mps + V),
        closing_speed_mps=case.closing_speed_mps,
        hand_dv_mps=float(bv[1] - case.u0n_mps) + float(bw[2] - case.omega0_radps) * hands,
        ke_before_j=out.ke_before_j,
        ke_after_j=out.ke_after_j,
        v1_t_mps=float(vb[0]),
        u1_t_mps=float(bv[0]),
        impacts=1,
        sustained_contact_s=0.0,
        peak_sustained_force_n=0.0,
        episode_s=0.0,
        ended="meets_again" if why == "contact" else why,
        end_state=PlanarState.of(y),
        friction=out,
    )
