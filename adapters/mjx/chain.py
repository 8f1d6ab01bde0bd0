"""MJX's segmented bat (``adapters.segmented``): MuJoCo C's chain (``adapters.mujoco.chain``:
a kinematic tree of capsules, the root free, each child hinged about z at its knob end with
the hinge's own ``stiffness`` and ``damping``, segments colliding with the ball only) at the
port's settings (``_port_chain.host_chain``), put on JAX with ``mjx.put_model`` and stepped
one world at a time by a jitted ``mjx.step`` (the model is an argument, so a new chain of the
same N compiles nothing: JAX's disk cache).

Springs: MuJoCo's passive force on hinge j is -stiffness (q_j - qpos_spring_j) - damping
qd_j (``mujoco/mjx/_src/passive.py``, as ``engine_passive.c``), in N m per rad: the MJCF's
``stiffness`` IS k_j, no conversion. MJX's Euler integrates the damping implicitly as C's
does (``mjx/_src/forward.py``: ``qM + dt diag(damping)``), the spring explicitly.

The state is set and read through the host's MuJoCo C data: ``set_state`` computes qpos and
qvel there (``MujocoChain.set_state``) and copies them to the device; ``read`` copies the
port's qpos and qvel back and runs C's kinematics (float64) for the COM rows. ``mjx64``
shares the class in float64 (JAX's x64 mode, scoped as the bat adapter scopes it).

Quirks (mujoco-mjx 3.17.0, jaxlib 0.10.2, CPU; measured at N = 8):
- XLA's CPU compiler fuses the kinematics' quaternion products down the tree's levels (one
  level per segment: ``scan.body_tree``) and recomputes the chain per element: a 0.35 s step
  (0.32 s of it ``mjx.kinematics``) after a 2-minute compile. The step is compiled without
  XLA's fusion pass (``COMPILER_OPTIONS``, JAX's ``compiler_options``: a supported option,
  no change to MJX): 1.9 ms a step after a 23 s compile (measured on a loaded 2-core host;
  an optimisation barrier patched into MJX's tree walk gave 2.7 ms, and its float32 rounding
  differs from this one's at 1e-4 of v1 after a touch).
- A jitted call with an uncommitted argument (``jnp.asarray`` of host data) compiles the step
  again for the committed arrays it returns: ``set_state`` commits them (``_committed``).
- float32 at the reference's own regulariser (d = 0.9999): the Newton step's Hessian
  M + J'DJ of a light hinged segment is ill-conditioned (condition 2.9e8 at a touch of
  x = 0.72 m, > 1/eps = 8.4e6) and MJX's solve returns a NaN qacc (``jax_debug_nans``: its
  NaN ``Mgrad`` in ``solver.Context.create``) with no contact force, qpos and qvel finite:
  the approaching ball goes on into the segment for a few steps until a solve succeeds. At
  the test's 11 points it happens on the first touch at x = 0.70 and 0.80 m; ``failed``
  counts a non-finite qacc as MuJoCo C does (``mjWARN_BADQACC``). float64 (``mjx64``): none.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from ..segmented import ChainEngine, ChainScene
from . import RECORD, RECORD_64
from ._port_chain import host_chain, read_through, segment_rows
from .adapter import MjxEngine, mjx

#: XLA's options for the step: no fusion pass (module docstring).
COMPILER_OPTIONS = {"xla_disable_hlo_passes": "fusion"}


def _traced():
    """The jitted one-world step: the new data, whether a ball-segment pair overlaps (MuJoCo's
    ncon > 0 at margin 0) and whether qpos, qvel and the solver's qacc are finite (a NaN qacc
    drops the contact force silently: module docstring)."""

    def advance(m, d):
        d = mjx.step(m, d)
        touching = jnp.any(d._impl.contact.dist < 0.0)
        finite = (
            jnp.all(jnp.isfinite(d.qpos))
            & jnp.all(jnp.isfinite(d.qvel))
            & jnp.all(jnp.isfinite(d.qacc))
        )
        return d, touching, finite

    return jax.jit(advance, compiler_options=COMPILER_OPTIONS)


_ADVANCE = _traced()


def _committed(values: np.ndarray, like: jax.Array) -> jax.Array:
    """``values`` as a device array of ``like``'s dtype, committed to its device as the
    step's outputs are: an uncommitted argument makes a second compile of the step."""
    return jax.device_put(jnp.asarray(values, like.dtype), like.sharding)


class MjxChain(ChainEngine):
    """MJX's segmented bat, one world, in JAX's default float32."""

    record = RECORD
    #: JAX's x64 mode as the record's precision asks (caches cleared on a change of mode).
    _scope = MjxEngine._scope

    def build(self, scene: ChainScene) -> None:
        self._host = host_chain(self.settings, scene)
        self.n = scene.chain.segments
        with self._scope():
            self.model = mjx.put_model(self._host.model, impl="jax")
            self.data = mjx.make_data(self.model, impl="jax")
        self._advance = _ADVANCE
        self._touching, self._bad = False, False

    def mass_properties(self) -> np.ndarray:
        mx = self.model
        return segment_rows(
            self._host,
            np.asarray(mx.body_mass),
            np.asarray(mx.body_ipos),
            np.asarray(mx.body_inertia),
        )

    def set_state(self, ball: np.ndarray, segments: np.ndarray) -> None:
        h = self._host
        h.set_state(ball, segments)
        with self._scope():
            d = self.data
            self.data = d.replace(
                qpos=_committed(h.data.qpos, d.qpos),
                qvel=_committed(h.data.qvel, d.qvel),
                time=jnp.zeros_like(d.time),
                qacc_warmstart=jnp.zeros_like(d.qacc_warmstart),
            )
        self._touching, self._bad = False, False

    def step(self) -> None:
        with self._scope():
            self.data, touching, finite = self._advance(self.model, self.data)
            self._touching = bool(touching)
            self._bad = self._bad or not bool(finite)

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        return read_through(self._host, np.asarray(self.data.qpos), np.asarray(self.data.qvel))

    def in_contact(self) -> bool:
        return self._touching

    def failed(self) -> bool:
        return self._bad

    def close(self) -> None:
        self.model = self.data = None


class Mjx64Chain(MjxChain):
    """MJX's segmented bat in float64."""

    record = RECORD_64
