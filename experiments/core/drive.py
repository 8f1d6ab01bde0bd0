"""The bat driven about the hands in the engine: swung into place before an impact
(``swing_into_place``, for ``fire``'s hinged swings), or driven alone for a set time
(``run_motion``, for the swing study), through the harness's one stepping loop."""

from __future__ import annotations

from adapters import Scene, Settings, State
from analytic import presets
from analytic.dynamics import MotionState
from analytic.dynamics import start_state as motion_start

from . import geometry as g
from .episode import Coast, run_episode
from .hosting import hosted
from .placement import PARKED_BALL_Y_M, SwingPlan, hands_for


def swing_into_place(batch, plans: list[SwingPlan], starts, bat):
    """Swing every world's bat from rest about the hands and release it (the ball parked far
    away); returns the start states with the engine's bats, and each release's omega and
    angle (rad/s, rad) as columns."""
    if len({p.steps for p in plans}) != 1:
        raise ValueError("swings of one batch must last the same number of steps")
    xp = batch.xp
    batch.set_state(xp.stack([p.bat_start for p in plans]))
    batch.set_drive([p.hands(bat) for p in plans])
    run_episode(batch, Coast(), plans[0].steps)
    batch.set_drive(None)
    swung = batch.read()
    cols = xp.cols(swung)
    return xp.with_bat(starts, swung), (cols[g.BAT_W], cols[g.BAT_ANGLE])


def run_motion(
    name: str, settings: Settings, bat, drive, t_s: float, angle_rad: float = 0.0
) -> MotionState:
    """Drive the bat alone (the ball parked far away) from rest at ``angle_rad`` for
    round(t/dt) steps under ``drive`` (an ``analytic.dynamics.Drive``), hinged at the world's
    origin if the drive has a pivot; the bat's state at the end, as ``analytic.dynamics``
    gives it."""
    host = hosted(name, settings)
    batch = host.batch(Scene(bat=bat, ball=presets.BASEBALL, e=presets.E_WOOD), 1)
    s0 = motion_start(bat, drive, angle_rad)
    rest = State(
        ball_x_m=0.0,
        ball_y_m=PARKED_BALL_Y_M,
        ball_vx_mps=0.0,
        ball_vy_mps=0.0,
        ball_omega_radps=0.0,
        bat_x_m=s0.x_m,
        bat_y_m=s0.y_m,
        bat_angle_rad=angle_rad,
        bat_vx_mps=0.0,
        bat_vy_mps=0.0,
        bat_omega_radps=0.0,
    )
    batch.set_state(batch.xp.stack([rest]))
    steps = round(t_s / settings.dt_s)
    batch.set_drive([hands_for(drive, bat)])
    run_episode(batch, Coast(), steps)
    batch.set_drive(None)
    r = [float(v) for v in batch.xp.row(batch.read(), 0)]
    return MotionState(
        t_s=steps * settings.dt_s,
        x_m=r[g.BAT_X],
        y_m=r[g.BAT_Y],
        angle_rad=r[g.BAT_ANGLE],
        vx_mps=r[g.BAT_VX],
        vy_mps=r[g.BAT_VY],
        omega_radps=r[g.BAT_W],
    )
