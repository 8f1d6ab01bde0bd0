"""The MJX adapter: MuJoCo's MJCF put on a JAX device, every world stepped by one jitted,
vmapped ``mjx.step`` (see the package docstring for the regulariser and the precision).

Compiles are few: the step is jitted once per model structure, precision and world count, and
world counts are padded to a bucket (a power of two up to 4096, then a multiple of 4096), the
padding worlds copies of the first. The model is an argument of the jitted step, so changing a
value (dt, solref, the hands) compiles nothing.
"""

from __future__ import annotations

import contextlib
import functools
import math
from collections.abc import Sequence

import mujoco
import numpy as np

from ..device import ArrayDevice, EpisodeConstants
from ..frames import in_plane, mujoco_columns, mujoco_coordinates, mujoco_rows
from ..interface import STATE_FIELDS, BatchedEngine, Hands, MassProperties, Scene
from ..mujoco.model import port_model
from . import INTEGRATORS, KNOB_FLOAT32, RECORD, RECORD_64
from .gradients import derivative, knob_derivative
from .runtime import bucket, jax, jnp, mjx


def _advance(m, d, bad):
    """One step of one world; its planar state row (the 11 PLANAR_FIELDS, the bat's yaw in
    the engine's precision), whether the bat and ball touch (the step's collision found them
    overlapping: MuJoCo's ncon > 0 at margin 0), and whether any reading so far was not
    finite (``read`` takes the rest of the state from the data's qpos and qvel)."""
    d = mjx.step(m, d)
    q, v = d.qpos, d.qvel
    row = jnp.stack(
        [q[7], q[8], v[6], v[7], v[11], q[0], q[1], 2.0 * jnp.arctan2(q[6], q[3]), v[0], v[1], v[5]]
    )
    touching = jnp.any(d._impl.contact.dist < 0.0)
    return d, row, touching, bad | ~jnp.all(jnp.isfinite(row))


@functools.lru_cache(maxsize=32)
def _traced(model_def, data_def):
    """The jitted, vmapped step over the model's and the data's leaves. Passing MJX's Model
    itself to a jitted function flattens it and compares its static numpy fields on every
    call: 40% of a step at a few worlds."""

    def advance(m_leaves, d_leaves, bad):
        m = jax.tree_util.tree_unflatten(model_def, m_leaves)
        d = jax.tree_util.tree_unflatten(data_def, d_leaves)
        d, row, touching, bad = jax.vmap(_advance, in_axes=(None, 0, 0))(m, d, bad)
        return jax.tree_util.tree_leaves(d), row, touching, bad

    return jax.jit(advance)


@jax.jit
def _columns(qpos, qvel, planar, angle):
    """Every world's state as (20, rows) columns on the device, as ``read`` makes its rows
    (``frames.mujoco_rows``, the planar yaw as the step computed it), in the engine's
    precision: the same numbers ``read`` casts to float64."""
    return jnp.stack(mujoco_columns(jnp, qpos, qvel, planar, angle))


#: The x64 mode of the last JAX call made here (``MjxEngine._scope``), None before the first.
_LAST_X64: list[bool | None] = [None]


class _Flat:
    """A model and data as the jitted step takes them: the model's leaves, the data's
    structure, the step traced for them, the data's leaves as last stepped (None once
    unflattened back into the data) and where its qpos and qvel lie among them."""

    def __init__(self, model, data) -> None:
        self.m_leaves, m_def = jax.tree_util.tree_flatten(model)
        paths, self.d_def = jax.tree_util.tree_flatten_with_path(data)
        names = [jax.tree_util.keystr(path) for path, _ in paths]
        self.qpos_at, self.qvel_at = names.index(".qpos"), names.index(".qvel")
        self.advance = _traced(m_def, self.d_def)
        self.d_leaves = None


class MjxEngine(BatchedEngine):
    """MJX behind the batched interface, in JAX's default float32."""

    record = RECORD

    @contextlib.contextmanager
    def _scope(self):
        """JAX's x64 mode as this engine's precision asks, for the calls inside. JAX keeps the
        lowering of small jitted helpers (MJX's RK4 calls ``jnp.tril``) across a change of
        mode: the float64 step then calls a float32 one and fails to lower. Its caches are
        cleared whenever the mode differs from the last one used (disk-cached compiles)."""
        x64 = self.record.errors.precision == "float64"
        if _LAST_X64[0] is not None and _LAST_X64[0] != x64:
            jax.clear_caches()
        _LAST_X64[0] = x64
        with jax.enable_x64(x64):
            yield

    @classmethod
    def read_back_defaults(cls) -> dict:
        m = mujoco.MjModel.from_xml_string(
            '<mujoco><worldbody><geom size="1"/></worldbody></mujoco>'
        )
        mx = mjx.put_model(m, impl="jax")
        o = mx.opt
        return {
            "solref": tuple(np.asarray(mx.geom_solref[0]).tolist()),
            "solimp": tuple(np.asarray(mx.geom_solimp[0]).tolist()),
            "iterations": int(o.iterations),
            "tolerance": float(o.tolerance),
            "ls_iterations": int(o.ls_iterations),
            "dt_s": float(o.timestep),
            "integrator": next(
                i
                for i in INTEGRATORS
                if int(o.integrator) == getattr(mujoco.mjtIntegrator, f"mjINT_{i.upper()}")
            ),
            "cone": "elliptic" if int(o.cone) == mujoco.mjtCone.mjCONE_ELLIPTIC else "pyramidal",
        }

    def build(self, scene: Scene, worlds: int) -> None:
        st = self.settings
        m = _host_model(scene, st)
        self._e = scene.e  # what the tuned contacts' solref maps (``knob_derivative``)
        self._site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, "load")
        self._ids = {
            kind: mujoco.mj_name2id(m, obj, "bat")
            for kind, obj in (
                ("body", mujoco.mjtObj.mjOBJ_BODY),
                ("geom", mujoco.mjtObj.mjOBJ_GEOM),
            )
        }
        self._ball = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "ball")
        self._geoms = (self._ids["geom"], mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "ball"))
        self.n, self.rows = worlds, bucket(worlds)
        with self._scope():
            self.model = mjx.put_model(m, impl="jax")
            one = mjx.make_data(self.model, impl="jax")
            # copies made by vmap, as the step returns them (a broadcast view compiles the
            # step a second time: 6 s more)
            self.data = jax.vmap(lambda _: one)(jnp.arange(self.rows))
            self._bad = jnp.zeros(self.rows, dtype=bool)
        self._row, self._shift = np.zeros((self.rows, len(STATE_FIELDS))), np.zeros((self.rows, 2))
        self._stepped, self._touching = False, np.zeros(self.rows, dtype=bool)
        self._planar, self._planar_on = np.ones(self.rows, dtype=bool), None

    def set_body_friction(self, *, bat: float, ball: float) -> None:
        """Each geom's own sliding friction (MuJoCo combines them by max); as in MuJoCo C, an
        explicit pair (a tuned contact with friction) keeps the friction it was built with."""
        with self._scope():
            mx = self.model
            friction = np.asarray(mx.geom_friction).copy()
            friction[list(self._geoms), 0] = (bat, ball)
            self.model = mx.replace(geom_friction=jnp.asarray(friction, mx.geom_friction.dtype))

    def mass_properties(self) -> MassProperties:
        mx = self.model
        mass, ipos = np.asarray(mx.body_mass), np.asarray(mx.body_ipos)
        g, bat, ball = self._ids["geom"], self._ids["body"], self._ball

        def about_z(body: int) -> float:
            rot = np.zeros(9)
            mujoco.mju_quat2Mat(rot, np.asarray(mx.body_iquat[body], dtype=float))
            rot = rot.reshape(3, 3)
            return float((rot @ np.diag(np.asarray(mx.body_inertia[body])) @ rot.T)[2, 2])

        pos, size = np.asarray(mx.geom_pos[g]), np.asarray(mx.geom_size[g])
        knob_x = pos[0] - size[1] - size[0]
        return MassProperties(
            bat_mass_kg=float(mass[bat]),
            bat_com_from_knob_m=float(ipos[bat][0] - knob_x),
            bat_inertia_kgm2=about_z(bat),
            ball_mass_kg=float(mass[ball]),
            ball_inertia_kgm2=about_z(ball),
        )

    def set_state(self, states: np.ndarray) -> None:
        s = np.asarray(states, dtype=float)
        s = np.pad(s, ((0, self.rows - len(s)), (0, len(STATE_FIELDS) - s.shape[1])))
        s[len(states) :] = s[0]
        qpos, qvel = mujoco_coordinates(s)
        self._planar, self._planar_on = in_plane(s), None
        with self._scope():
            d = self.data
            self.data = d.replace(
                qpos=jnp.asarray(qpos, d.qpos.dtype),
                qvel=jnp.asarray(qvel, d.qvel.dtype),
                time=jnp.zeros_like(d.time),
                qacc_warmstart=jnp.zeros_like(d.qacc_warmstart),
            )
            self._bad = jnp.zeros(self.rows, dtype=bool)
        self._row, self._stepped, self._touching = s, False, np.zeros(self.rows, dtype=bool)
        self._shift = np.zeros((self.rows, 2))

    def set_drive(self, hands: Sequence[Hands] | None) -> None:
        # Site motors act in the bat's frame; the hands' hinge is the connect equality, whose
        # anchors (like the site's position) are the model's: shared by every world.
        with self._scope():
            d = self.data
            if hands is None:
                self.data = d.replace(
                    ctrl=jnp.zeros_like(d.ctrl), eq_active=jnp.zeros_like(d.eq_active)
                )
                return
            first = hands[0]
            if any(
                (h.arm_m, h.pivot_from_com_m) != (first.arm_m, first.pivot_from_com_m)
                for h in hands
            ):
                raise ValueError(
                    "hands of one batch must share arm_m and pivot_from_com_m; "
                    "allowed: equal values (they are MJX model fields)"
                )
            if first.pivot_from_com_m is not None:
                self._move_pivots_to(first.pivot_xy_m, hands)
            ctrl = np.array(
                [
                    (
                        h.force_n * math.cos(h.angle_rad),
                        h.force_n * math.sin(h.angle_rad),
                        h.torque_nm,
                    )
                    for h in hands
                ]
            )
            ctrl = np.concatenate([ctrl, np.repeat(ctrl[:1], self.rows - len(ctrl), axis=0)])
            mx = self.model
            site_pos = np.asarray(mx.site_pos).copy()
            site_pos[self._site] = (first.arm_m, 0.0, 0.0)
            eq_data = np.asarray(mx.eq_data).copy()
            hinged = first.pivot_from_com_m is not None
            if hinged:
                eq_data[0][:6] = (first.pivot_from_com_m, 0.0, 0.0, *first.pivot_xy_m, 0.0)
            self.model = mx.replace(
                site_pos=jnp.asarray(site_pos, mx.site_pos.dtype),
                eq_data=jnp.asarray(eq_data, mx.eq_data.dtype),
            )
            self.data = d.replace(
                ctrl=jnp.asarray(ctrl, d.ctrl.dtype), eq_active=jnp.full_like(d.eq_active, hinged)
            )

    def _move_pivots_to(self, xy, hands: Sequence[Hands]) -> None:
        """Translate each world so that its hands' pivot lies at ``xy``, the one anchor MJX's
        model holds for every world (nothing else in the scene: physics is the same); ``read``
        adds the shift back until the next ``set_state``."""
        shift = np.zeros((self.rows, 2))
        shift[: len(hands)] = np.array([h.pivot_xy_m for h in hands], dtype=float) - xy
        d = self.data
        qpos = np.asarray(d.qpos, dtype=float).copy()
        for col in (0, 7):  # the bat's and the ball's x, y
            qpos[:, col : col + 2] -= shift
        self.data = d.replace(qpos=jnp.asarray(qpos, d.qpos.dtype))
        self._row = np.asarray(self._row, dtype=float).copy()
        self._row[:, [0, 1]] -= shift
        self._row[:, [5, 6]] -= shift
        self._shift = self._shift + shift

    def derivative(self, states, tangents, steps: int, inertia_tangent_kgm2: float = 0.0):
        return derivative(  # JAX's jvp through mjx.step (its docstring)
            self, states, tangents, steps, inertia_tangent_kgm2
        )

    def knob_derivative(self, states, steps: int, knobs):
        if not self.record.can.knob_autodiff:  # float32 (KNOB_FLOAT32)
            raise NotImplementedError(f"{self.record.name} has no knob_derivative: {KNOB_FLOAT32}")
        return knob_derivative(  # jvp along the contact arrays each knob moves (its docstring)
            self, states, steps, knobs
        )

    def device_episode(self, constants: EpisodeConstants) -> ArrayDevice:
        """The worlds' columns as JAX holds them (``adapters.device``); the episode starts
        from ``set_state``, so no hands' shift is ever added (``_move_pivots_to``)."""
        return ArrayDevice(
            xp=jnp, jit=jax.jit, columns=self._device_columns, rows=self.rows, call=self._call
        )

    def _call(self, fn, *args):
        with self._scope():
            return fn(*args)

    def _device_columns(self):
        with self._scope():
            f = self._flat
            if f is not None and f.d_leaves is not None:
                qpos, qvel = f.d_leaves[f.qpos_at], f.d_leaves[f.qvel_at]
            else:
                qpos, qvel = self._data.qpos, self._data.qvel
            if self._planar_on is None:
                self._planar_on = jnp.asarray(self._planar)
            return _columns(qpos, qvel, self._planar_on, self._row[:, 7]), self._touching

    def device(self) -> str:
        d = jax.devices()[0]
        return f"{d.platform}: {d.device_kind}"

    @property
    def model(self):
        return self._model

    @model.setter
    def model(self, value) -> None:
        self._model, self._flat = value, None

    @property
    def data(self):
        if self._flat is not None and self._flat.d_leaves is not None:  # stepped since
            self._data = jax.tree_util.tree_unflatten(self._flat.d_def, self._flat.d_leaves)
            self._flat.d_leaves = None
        return self._data

    @data.setter
    def data(self, value) -> None:
        self._data, self._flat = value, None

    def step(self) -> None:
        with self._scope():
            if self._flat is None:
                self._flat = _Flat(self._model, self._data)
            f = self._flat
            if f.d_leaves is None:  # the data as last set or read
                f.d_leaves = jax.tree_util.tree_leaves(self._data)
            f.d_leaves, self._row, self._touching, self._bad = f.advance(
                f.m_leaves, f.d_leaves, self._bad
            )
            self._stepped = True

    def _coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """Every world's qpos and qvel (from the stepped leaves, not unflattening the data)."""
        f = self._flat
        if f is not None and f.d_leaves is not None:
            return np.array(f.d_leaves[f.qpos_at], float), np.array(f.d_leaves[f.qvel_at], float)
        return np.array(self._data.qpos, dtype=float), np.array(self._data.qvel, dtype=float)

    def read(self) -> np.ndarray:
        row = np.array(self._row, dtype=float)[: self.n]
        if self._stepped:  # the yaw of a row turned about z alone as MJX computed it
            qpos, qvel = self._coordinates()
            row = mujoco_rows(
                qpos[: self.n], qvel[: self.n], self._planar[: self.n], angle_rad=row[:, 7]
            )
        shift = self._shift[: self.n]
        row[:, [0, 1]] += shift
        row[:, [5, 6]] += shift
        return row

    def in_contact(self) -> np.ndarray:
        return np.asarray(self._touching)[: self.n]

    def failed(self) -> np.ndarray:
        return np.asarray(self._bad)[: self.n]


def _host_model(scene: Scene, st) -> mujoco.MjModel:
    """MuJoCo's ports' model (``mujoco.model.port_model``) with MJX's solver tolerance."""
    m = port_model(mujoco, scene, st)
    m.opt.tolerance = st.tolerance
    return m


class Mjx64Engine(MjxEngine):
    """MJX in float64."""

    record = RECORD_64
