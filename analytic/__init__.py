"""Closed-form rigid-body reference for the bat-ball impact; numpy only, no engine.

from analytic import Bat, Ball, ImpactCase, Outcome, predict, sweet_spot, presets
case = ImpactCase(bat=presets.R161, ball=presets.BASEBALL, s_m=0.1, v0_mps=46.9,
                  u0_mps=17.87, omega0_radps=32.0, e=0.5)
predict(case).v1_mps
"""

from . import flight, gradients, presets
from .ball import COR_DATA, REALISTIC_BALL, CorLaw, CorPoint, RealisticBall
from .collide import CollisionEpisode, collide
from .cork import Hole, corked_bat, corked_bat_paper
from .friction import FrictionalImpulse, FrictionOutcome, frictional_impulse, predict_friction
from .impact import (
    PaperOblique,
    SweetRegion,
    batted_ball_speed,
    center_of_percussion,
    collision_efficiency,
    hittable_sweet_spot,
    predict,
    predict_arrays,
    predict_oblique_paper,
    sweet_region,
    sweet_spot,
    sweet_zone,
)
from .impulse3d import Impulse3D, RigidBody3D, impulse_3d
from .marks import EpisodeMark, episode_cop_mark, episode_sweet_spot, episode_sweet_spot_mark
from .model import WOOD_DENSITY_KGM3, Ball, Bat, ImpactCase, Outcome
from .swing import MEASURED_EXPONENT, Swing, SwingModel, swing_for

__all__ = [
    "COR_DATA",
    "REALISTIC_BALL",
    "Ball",
    "Bat",
    "CollisionEpisode",
    "CorLaw",
    "CorPoint",
    "FrictionOutcome",
    "FrictionalImpulse",
    "Hole",
    "ImpactCase",
    "Impulse3D",
    "MEASURED_EXPONENT",
    "Outcome",
    "PaperOblique",
    "RealisticBall",
    "RigidBody3D",
    "SweetRegion",
    "Swing",
    "SwingModel",
    "WOOD_DENSITY_KGM3",
    "batted_ball_speed",
    "EpisodeMark",
    "center_of_percussion",
    "collide",
    "episode_cop_mark",
    "episode_sweet_spot_mark",
    "collision_efficiency",
    "corked_bat",
    "corked_bat_paper",
    "episode_sweet_spot",
    "frictional_impulse",
    "gradients",
    "hittable_sweet_spot",
    "impulse_3d",
    "predict",
    "predict_arrays",
    "predict_friction",
    "flight",
    "predict_oblique_paper",
    "presets",
    "sweet_region",
    "sweet_spot",
    "sweet_zone",
    "swing_for",
]
