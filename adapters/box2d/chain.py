"""Box2D v3's segmented bat (``adapters.segmented``): one dynamic body per segment, its origin at
its COM, carrying a capsule of the bat's radius whose cylinder spans the segment's
[i l, (i+1) l]; the mass set as the bat adapter sets it (the shapes' density first, for the
extents continuous collision needs, then ``mass_data``: float32). Neighbours are joined at their
common end by a revolute joint (``collide_connected`` False) with its spring enabled; every
segment's shape has one negative ``group_index``, so no two segments collide, only the ball.
World values, restitution (bat 0, ball e: the max) and friction (0) as the bat adapter's.

The spring's stiffness (Box2D 3.1.1, src/revolute_joint.c b2PrepareRevoluteJoint and
b2SolveRevoluteJoint, src/solver.h b2MakeSoft): a soft constraint on the relative angle C with
``axialMass`` m = 1 / (1/I_A + 1/I_B) (the two bodies' own inverse inertias: not the joint
coordinate's effective inertia in the chain) and omega = 2 pi hertz, zeta = dampingRatio;
b2MakeSoft's biasRate omega / (2 zeta + h omega), massScale and impulseScale are the implicit
(backward Euler) step of a spring m omega^2 and damper 2 zeta m omega on C. So the torque per
radian is k = m (2 pi hertz)^2 and the damping d = 2 zeta m (2 pi hertz): hertz =
sqrt(k / m) / (2 pi), zeta = d / (2 m omega), m from the inertias Box2D holds (read back). The
spring is solved in both the solve and relax passes of each sub-step, its impulse warm-started
from the last sub-step. k = 0 gives hertz 0, which disables the spring (and so a damper d).

The joints' point constraint is rigid in velocity (relax pass) and corrects position error
softly (60 Hz, fixed in pyb2d3). Joints and contacts keep warm-start impulses: ``set_state``
makes new joints and disables/re-enables the bodies (which destroys their contacts).
Box2D's "touching" counts speculative contacts, so ``in_contact`` reports whether the ball's
velocity changed in the last step (only segments act on it), as the bat adapter does.

Measured (R161, N = 8, reference profile: dt = 1e-6 s, 1 sub-step):
- the impact sees the touched segment alone: each sub-step makes one solve and one relax sweep
  (ITERATIONS = RELAX_ITERATIONS = 1, src/solver.c), and the restitution impulse after the
  sub-steps acts on the contact only, so the ball leaves with Newton's restitution on a FREE
  segment (x = 0.65 m: -15.19919 m/s, the free segment's -15.19919, the chain's -5.264; 8
  sub-steps: -15.1918); the joints pass the blow on in the next steps and the chain meets the
  ball again, several times: v1 off by 0.6 to 4.4 m/s;
- the spring is implicit on the bodies' own inertias, omega_j = sqrt(k / m) of 1.3e4 to 2.9e4
  rad/s (25 times the lowest mode's): it stiffens by 1 / (1 + (h omega_j)^2) and damps the
  joint's relative spin by about (h omega_j)^2 a step. The lowest mode's period is 1.7e-4 long
  (4.0e-4, 9.9e-4 at dt = 2, 4 us; 7.2e-5 at 0.5 us) and it loses 6% of its amplitude a period
  with no damper; the bending energy left after an impact is 2 to 20 J of the reference's 24 to
  45 J (at N = 64, h omega_j = 0.48: 0.1 J of 60 J).
"""

from __future__ import annotations

import math

import numpy as np

from ..loading import import_engine
from ..segmented import ChainEngine, ChainScene
from . import RECORD
from .adapter import _rot, make_world

b2 = import_engine(RECORD)

#: The segments' shape group: shapes sharing a negative group index never collide.
SEGMENT_GROUP = -1


def spring_tuning(k: float, d: float, inertia_a: float, inertia_b: float) -> tuple[float, float]:
    """(hertz, dampingRatio) of a revolute joint's spring whose torque per radian is ``k`` and
    per rad/s ``d`` between bodies of inertias ``inertia_a``, ``inertia_b`` (module docstring:
    k = m (2 pi f)^2, d = 2 zeta m (2 pi f), m = 1 / (1/I_A + 1/I_B))."""
    if k == 0.0:
        if d != 0.0:
            raise ValueError(
                "Box2D's joint spring cannot damp without a stiffness (hertz 0 disables it)"
            )
        return 0.0, 0.0
    m = 1.0 / (1.0 / inertia_a + 1.0 / inertia_b)
    omega = math.sqrt(k / m)
    return omega / (2.0 * math.pi), d / (2.0 * m * omega)


class Box2dChain(ChainEngine):
    """Box2D v3's segmented bat, at the bat adapter's settings and contact mapping."""

    record = RECORD

    def __init__(self, settings) -> None:
        super().__init__(settings)
        self._world = None

    def close(self) -> None:
        if self._world is not None:
            self._world.destroy()
            self._world = None

    @staticmethod
    def _shape_def(group: int):
        sd = b2.ShapeDef()
        sd.density = 1.0
        sd.update_body_mass = True  # shapes set the extents continuous collision uses
        sd.enable_contact_events = False
        mat = b2.SurfaceMaterial()
        mat.friction, mat.restitution, mat.rolling_resistance = 0.0, 0.0, 0.0
        sd.material = mat
        filt = b2.Filter()
        filt.group_index = group
        sd.filter = filt
        return sd

    def build(self, scene: ChainScene) -> None:
        self.close()
        chain, ball = scene.chain, scene.ball
        self._world = world = make_world(self.settings)
        self._sub_steps = self.settings.sub_step_count
        self._chain = chain
        ell, r = chain.segment_length_m, chain.bat.radius_m
        sd = self._shape_def(SEGMENT_GROUP)
        self._segs, self._shapes = [], []
        for i, (m, c, inertia) in enumerate(
            zip(chain.masses_kg, chain.coms_m, chain.inertias_kgm2, strict=True)
        ):
            body = world.create_dynamic_body(position=(0.0, 0.0), enable_sleep=False)
            shape = body.create_capsule_shape(
                sd, b2.capsule((i * ell - c, 0.0), ((i + 1) * ell - c, 0.0), r)
            )
            self._set_mass(body, m, inertia)
            self._segs.append(body)
            self._shapes.append(shape)
        self._ball = world.create_dynamic_body(
            position=(0.0, 1.0), enable_sleep=False, is_bullet=self.settings.bullet
        )
        self._ball_shape = self._ball.create_circle_shape(
            self._shape_def(0), b2.circle((0.0, 0.0), ball.radius_m)
        )
        self._set_mass(self._ball, ball.mass_kg, ball.inertia_kgm2)
        self._ball_shape.restitution = scene.e  # Box2D takes the larger: max(0, e) = e
        bat_mu, ball_mu = RECORD.can.friction_rule.per_body(0.0)  # sqrt(0 * 0) = 0
        for shape in self._shapes:
            shape.friction = bat_mu
        self._ball_shape.friction = ball_mu
        self._joints: list = []
        self._make_joints()
        self._v_before: tuple[float, float] | None = None

    @staticmethod
    def _set_mass(body, mass: float, inertia: float) -> None:
        md = b2.MassData()
        md.mass, md.center, md.rotational_inertia = mass, (0.0, 0.0), inertia
        body.mass_data = md

    def _make_joints(self) -> None:
        """Fresh revolute joints (no warm-start impulse) with their springs."""
        for joint in self._joints:
            joint.destroy()
        self._joints = []
        chain, ell = self._chain, self._chain.segment_length_m
        for j, (k, d) in enumerate(
            zip(chain.stiffnesses_nmprad, chain.dampings_nmsprad, strict=True)
        ):
            a, b = self._segs[j], self._segs[j + 1]
            end = (j + 1) * ell  # from the knob
            jd = b2.RevoluteJointDef()
            jd.body_a, jd.body_b = a, b
            jd.local_anchor_a = (end - chain.coms_m[j], 0.0)
            jd.local_anchor_b = (end - chain.coms_m[j + 1], 0.0)
            jd.reference_angle = 0.0
            jd.collide_connected = False
            hertz, zeta = spring_tuning(
                k, d, a.mass_data.rotational_inertia, b.mass_data.rotational_inertia
            )
            jd.enable_spring = hertz > 0.0
            jd.hertz, jd.damping_ratio = hertz, zeta
            self._joints.append(self._world.create_joint(jd))

    def mass_properties(self) -> np.ndarray:
        ell = self._chain.segment_length_m
        rows = []
        for i, body in enumerate(self._segs):
            md = body.mass_data
            rows.append(
                (
                    md.mass,
                    md.center.x - body.shapes[0].capsule.center1.x + i * ell,
                    md.rotational_inertia,
                )
            )
        return np.array(rows, dtype=float)

    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        for body in (self._ball, *self._segs):
            body.enabled = False  # destroys its contacts (their warm-start impulses)
            body.enabled = True
        for body, (x, y, a, vx, vy, w) in zip(self._segs, segments, strict=True):
            body.set_transform((float(x), float(y)), _rot(float(a)))
            body.linear_velocity, body.angular_velocity = (float(vx), float(vy)), float(w)
        self._ball.set_transform((float(ball[0]), float(ball[1])), _rot(0.0))
        self._ball.linear_velocity = (float(ball[2]), float(ball[3]))
        self._ball.angular_velocity = 0.0
        self._make_joints()
        self._v_before = None

    def step(self) -> None:
        v = self._ball.linear_velocity
        self._v_before = (v.x, v.y)
        self._world.step(self.settings.dt_s, self._sub_steps)

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        bp, bv = self._ball.position, self._ball.linear_velocity
        rows = []
        for body in self._segs:
            p, v, q = body.position, body.linear_velocity, body.rotation
            rows.append((p.x, p.y, math.atan2(q.s, q.c), v.x, v.y, body.angular_velocity))
        return np.array([bp.x, bp.y, bv.x, bv.y]), np.array(rows)

    def in_contact(self) -> bool:
        # Only the segments' contacts act on the ball: one acted if its velocity changed.
        if self._v_before is None:
            return False
        v = self._ball.linear_velocity
        return (v.x, v.y) != self._v_before
