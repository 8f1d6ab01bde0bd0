"""Every tolerance and threshold the harness judges with, in one table: its value here, its
reason in ``WHY`` (what it covers, and what measured it). The judge (``judge``, and its
friction, soft-law and segmented-bat parts) reads these names; the tests import them rather
than restate them, and ``table()`` lists them for the report."""

from __future__ import annotations

ROUND_OPS = 1e4
GEOM_SAFETY = 10.0
SOLVE_SAFETY = 4.0
HINGE_K = 6.0
FD_STEP_M = 1e-6
CURVATURE_STEP_M = 1e-3
LINGER_STEPS = 2
OFF_SPAN_STEPS = 3
HITTABLE_SLACK_M = 1e-12
MASS_CHECK_REL = 1e-9
MASS_CHECK_ULPS = 8
ENERGY_GAIN_REL = 1e-6
ENERGY_GAIN_ULPS = 1000
JUMP_REACHES = 2.0
FLAG_REACHES = 1.0
DEFLECTED = 0.01
LAW_SAFETY = 2.0
LAW_MAX_REL_ERROR = 0.05
CHAIN_MASS_ULPS = 1e3
CHAIN_ENERGY_SLACK = 1e-3
CHAIN_MAX_EPISODE_S = 0.05
CHAIN_JUDGED_SHARE = 0.25
GRAD_ZERO_SHARE = 1e-3
GRAD_EXPLODE = 10.0
PLACEMENT_STEP = 1e-6

WHY = {
    "ROUND_OPS": "float operations of an impact, each within eps",
    "GEOM_SAFETY": "covers the factors of order 1 the slide estimate neglects",
    "SOLVE_SAFETY": "a linear solve's relative error is at most its condition number times "
    "eps (MJX's float32 impulse, condition 1e4: 0.87 of that measured on the "
    "41-point sweep)",
    "HINGE_K": "empirical bound on the hinges' (omega dt)^2 constant (0.05-5.5 measured)",
    "FD_STEP_M": "finite-difference step for dv1/ds (m)",
    "CURVATURE_STEP_M": "step for d2v1/ds2 (m): v1(s) is a smooth rational function",
    "LINGER_STEPS": "steps a contact may stay active after its impulse (PyBullet: 1.16, e = 0)",
    "OFF_SPAN_STEPS": "steps the ball may stay past the cylinder's end while touching before "
    "the episode ends 'left_cylinder' (an impulse at the grid's very end is "
    "seen there for its 1-3 steps; a ball sliding off the end in sustained "
    "contact is stopped after them)",
    "HITTABLE_SLACK_M": "slack on the hittable range (m): L - r - x_cm is a few ulps off",
    "MASS_CHECK_REL": "relative tolerance of the mass read-back: engines store mass properties "
    "in float64 and some derive them through a rotation or an "
    "eigen-decomposition, which costs a few ulps",
    "MASS_CHECK_ULPS": "float32 ulps of the mass read-back where that is more (0.871 kg reads "
    "back 9e-9 off)",
    "ENERGY_GAIN_REL": "kinetic energy may grow by this fraction before 'energy_gained': "
    "float64 rounding over thousands of steps stays far below it, the "
    "defects we look for (+1% and more) far above",
    "ENERGY_GAIN_ULPS": "ulps of energy gain allowed where more: float32 moves the energy "
    "1e-6..1e-4 (e = 1; PhysX 2.5e-6, MJX 3.5e-5)",
    "JUMP_REACHES": "contact reaches (r_ball + r_bat) a body's centre may move between two "
    "readings beyond twice k dt its larger speed: a position correction "
    "pushes apart by less than one reach, a reset of the state (MuJoCo puts a "
    "blown-up world back at its model's pose) moves the ball ~1 m",
    "FLAG_REACHES": "contact reaches (r_ball + r_bat) of gap between the surfaces beyond which "
    "an adapter's contact flag contradicts the geometry it reads (a passive "
    "check, as Gymnasium's env checker): no engine's contact margin is near it "
    "(PyBullet's and PhysX's are millimetres; a soft contact overlaps)",
    "DEFLECTED": "share of its approach speed by which a ball's velocity changed when it met "
    "the bat, whether or not a contact was seen (a contact shorter than a step "
    "can fall between two readings: Drake's 0.65 ms at dt = 1.5 ms); free flight "
    "keeps it to rounding, the slightest bounce changes it by tens of percent",
    "LAW_SAFETY": "soft contacts: factor over the first-order step error of their law "
    "(measured for MuJoCo at w = 3000 rad/s, paper's swing, s = 0.1 m, "
    "dt = 1e-5..1e-7: 0.86 of the term for Euler, 0.22 for RK4)",
    "LAW_MAX_REL_ERROR": "restitution error of a step (the engine's own estimate) beyond which "
    "the soft law's first-order bound no longer holds and the row is "
    "unjudged (an implicit step of 8% of a contact was 2.6 m/s off and "
    "'within' a 13 m/s bound)",
    "CHAIN_MASS_ULPS": "ulps of the segmented bat's mass read-back: each segment's mass and "
    "inertia pass through the engine's own conversions (a few operations "
    "each) of values 8-16 times smaller than the bat's",
    "CHAIN_ENERGY_SLACK": "share by which a segmented bat's energy (kinetic and the joints' "
    "springs) may grow before 'energy_gained': its joints are "
    "constraints solved to the engine's tolerance, not to rounding, "
    "and the springs' energy is read from joint angles kept only to it",
    "CHAIN_MAX_EPISODE_S": "a segmented bat's episode longer than this is 'no_separation' (s): "
    "its reference ends within a few ms",
    "CHAIN_JUDGED_SHARE": "a segmented bat's tolerance over this share of the closing speed "
    "judges nothing: the step resolves the chain too coarsely, and the "
    "row is 'unjudged'",
    "GRAD_ZERO_SHARE": "a gradient below this share of the closed form's (and outside its "
    "tolerance) is 'zero': the vanishing gradient of a hard contact, whose "
    "impulse the step sets whatever the input",
    "GRAD_EXPLODE": "a gradient more than this many times the closed form's (plus its "
    "tolerance) is 'exploding': stiff contact's gradients grow with the "
    "stiffness (Suh et al., ICML 2022), a bias stays within a few times",
    "PLACEMENT_STEP": "relative step of the central difference that differentiates the "
    "harness's placement (float64 geometry, smooth: truncation and rounding "
    "both below 1e-9 of the tangent)",
}


def table() -> list[tuple[str, float, str]]:
    """(name, value, reason) of every term, in the order above."""
    return [(name, globals()[name], why) for name, why in WHY.items()]
