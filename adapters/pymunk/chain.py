"""pymunk's segmented bat (``adapters.segmented``): one Body per segment, its origin at its COM,
carrying a Segment shape (Chipmunk's capsule) of the bat's radius whose cylinder spans the
segment's [i l, (i+1) l]; neighbours joined at their common end by a ``PivotJoint`` (the hands'
``joint_error_bias``) and a ``DampedRotarySpring(rest_angle=0, stiffness=k, damping=d)``.
All segments share one ``ShapeFilter`` group, so they collide with the ball only; the joints
also set ``collide_bodies = False``. Restitution and friction as the bat adapter's (segments'
elasticity 1, ball e: the product is e; frictionless).

The spring (cpDampedRotarySpring.c, Chipmunk 7) is Chipmunk's only joint spring, and it is
EXPLICIT: ``preStep`` applies the impulse (a.angle - b.angle - rest) * stiffness * dt from the
angles the step's position update has just made, before the solver iterations; ``stiffness`` is
the torque per radian itself (no conversion), and the impulse passes through no constraint
solve (the pivot then redistributes it). With positions updated first, this is
symplectic Euler for the joint: the period is off by O((omega dt)^2). The damper is a per-step
exponential decay of the relative spin, 1 - exp(-d dt (1/I_a + 1/I_b)), with the two bodies'
free inertias (not the pivot-coupled effective inertia): exact for d = 0 only, which
``Chain.from_beam`` uses. Springs, pivots and the ball's arbiters keep accumulated impulses
between steps (warm starts): ``set_state`` makes new joints and re-adds the ball's shape.

Measured (R161, 40 m/s, e = 0.5, dt = 1e-5 s): the pivots and the contact are solved together by
``iterations`` sequential-impulse passes, which a chain needs many of: at N = 8 a one-touch
impact's v1 is off the linear chain by 4e-5 to 8e-4 m/s with Chipmunk's 10, 1e-9 to 2e-8 with
20, rounding (4e-14) with 50 or more. Unconverged pivots also pass the explicit springs' kicks
(sized for each body's free inertia) on only in part: at N = 16 the chain gains energy with 10
iterations (its lowest mode's period 97% short) and is sound with 200; at N = 64 the stiffest
mode has omega dt = 6.7 > 2, beyond any explicit spring's stability (non-finite).
Chipmunk finds contacts after the step's position update: a ball that touches exactly at a
step's end is met in the next step a whole step deep (v0 dt, 0.4 mm), an overlap the slop (0.1
m) never removes; at x = 0.72 m that brings the vibrating chain back to the ball (a second touch
the linear chain has not: v1 off by 5.7 m/s), gone when the first step sees 1e-9 m of overlap.
No swept collision: at 1/60 s the ball passes through the chain unseen.
"""

from __future__ import annotations

import numpy as np

from ..loading import import_engine
from ..segmented import ChainEngine, ChainScene
from . import RECORD
from .adapter import make_space

pymunk = import_engine(RECORD)

#: The ShapeFilter group of every segment: shapes in one non-zero group never collide.
SEGMENT_GROUP = 1


class PymunkChain(ChainEngine):
    """Chipmunk2D's segmented bat, at the bat adapter's settings and contact mapping."""

    record = RECORD

    def build(self, scene: ChainScene) -> None:
        st, chain, ball = self.settings, scene.chain, scene.ball
        space = make_space(st)
        self._space, self._chain = space, chain
        ell, r = chain.segment_length_m, chain.bat.radius_m
        group = pymunk.ShapeFilter(group=SEGMENT_GROUP)
        self._segs, self._shapes = [], []
        for i, (m, c, inertia) in enumerate(
            zip(chain.masses_kg, chain.coms_m, chain.inertias_kgm2, strict=True)
        ):
            body = pymunk.Body(m, inertia)  # origin at the COM: position/velocity are the COM's
            shape = pymunk.Segment(body, (i * ell - c, 0.0), ((i + 1) * ell - c, 0.0), r)
            shape.filter = group
            space.add(body, shape)
            self._segs.append(body)
            self._shapes.append(shape)
        self._ball = pymunk.Body(ball.mass_kg, ball.inertia_kgm2)
        self._ball_shape = pymunk.Circle(self._ball, ball.radius_m)
        space.add(self._ball, self._ball_shape)
        bat_mu, ball_mu = RECORD.can.friction_rule.per_body(0.0)  # arbiter u = 0 * 1 = 0
        for shape in self._shapes:
            shape.elasticity, shape.friction = 1.0, bat_mu  # arbiter e = 1.0 * e
        self._ball_shape.elasticity, self._ball_shape.friction = scene.e, ball_mu
        self._joints: list = []
        self._make_joints()

    def _make_joints(self) -> None:
        """Fresh pivots and springs (no accumulated impulse) at the segments' common ends."""
        chain, space = self._chain, self._space
        space.remove(*self._joints)
        self._joints = []
        ell = chain.segment_length_m
        for j, (k, d) in enumerate(
            zip(chain.stiffnesses_nmprad, chain.dampings_nmsprad, strict=True)
        ):
            a, b = self._segs[j], self._segs[j + 1]
            end = (j + 1) * ell  # from the knob
            pivot = pymunk.PivotJoint(
                a, b, (end - chain.coms_m[j], 0.0), (end - chain.coms_m[j + 1], 0.0)
            )
            pivot.error_bias = self.settings.joint_error_bias
            # torque on b = k (a.angle - b.angle): k is N m/rad as it stands (module docstring)
            spring = pymunk.DampedRotarySpring(a, b, 0.0, k, d)
            for joint in (pivot, spring):
                joint.collide_bodies = False
                self._joints.append(joint)
        space.add(*self._joints)

    def mass_properties(self) -> np.ndarray:
        ell = self._chain.segment_length_m
        rows = [
            (body.mass, body.center_of_gravity.x - shape.a.x + i * ell, body.moment)
            for i, (body, shape) in enumerate(zip(self._segs, self._shapes, strict=True))
        ]
        return np.array(rows, dtype=float)

    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        for body, (x, y, a, vx, vy, w) in zip(self._segs, segments, strict=True):
            body.position, body.angle = (float(x), float(y)), float(a)
            body.velocity, body.angular_velocity = (float(vx), float(vy)), float(w)
        b = self._ball
        b.position, b.angle = (float(ball[0]), float(ball[1])), 0.0
        b.velocity, b.angular_velocity = (float(ball[2]), float(ball[3])), 0.0
        # Removing a shape drops its cached arbiters (their warm-start impulses); new joints
        # drop the joints' accumulated impulses.
        self._space.remove(self._ball_shape)
        self._space.add(self._ball_shape)
        self._make_joints()
        for body in self._segs:
            self._space.reindex_shapes_for_body(body)

    def step(self) -> None:
        self._space.step(self.settings.dt_s)

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        b = self._ball
        ball = np.array([*b.position, *b.velocity], dtype=float)
        rows = [(*s.position, s.angle, *s.velocity, s.angular_velocity) for s in self._segs]
        return ball, np.array(rows, dtype=float)

    def in_contact(self) -> bool:
        # Chipmunk lists only the arbiters that touched in the last step; only segments touch
        # the ball.
        found = []
        self._ball.each_arbiter(found.append)
        return bool(found)
