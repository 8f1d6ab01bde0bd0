"""MuJoCo C's segmented bat (``adapters.mujoco.chain``) as MuJoCo's ports take it: the host
model and data that the MJX and MuJoCo Warp chains put on their devices, set states through
and read COM rows back from. Imports no port (MuJoCo Warp's chain uses it too)."""

from __future__ import annotations

import numpy as np

from ..mujoco.chain import MujocoChain
from ..mujoco.model import carried
from ..segmented import ChainScene


def host_chain(settings, scene: ChainScene) -> MujocoChain:
    """MuJoCo C's chain (``chain_mjcf``, its options, contact solref/solimp and solver
    tolerance) with what ``adapters.mujoco.model.port_model`` changes for a port (a
    ``RegularisedSettings``): the line search's iterations, the impulse/soft solref carrying
    d (``carried``) and ``body_invweight0`` times ``invweight_scale``. No friction: the
    chain's geoms are condim 1 with the port's default cone, as ``port_model`` leaves a
    frictionless scene."""
    st = settings
    host = MujocoChain(st)
    host.build(scene)
    m = host.model
    if st.ls_iterations is not None:
        m.opt.ls_iterations = st.ls_iterations
    if st.contact_model != "native":  # carry d where R no longer cancels it
        m.geom_solref[:] = carried(tuple(float(x) for x in m.geom_solref[0]), st.impedance, st)
    m.body_invweight0[:] *= st.invweight_scale
    return host


def segment_rows(host: MujocoChain, mass, ipos, inertia) -> np.ndarray:
    """Per segment (mass, COM from the knob, inertia about z) from a port's body arrays (the
    segments' principal axes are the bodies' own: ``diaginertia``, identity ``body_iquat``)."""
    ell = host._ell
    rows = [
        (float(mass[b]), float(ipos[b][0]) + i * ell, float(inertia[b][2]))
        for i, b in enumerate(host._segs)
    ]
    return np.array(rows, dtype=float)


def read_through(host: MujocoChain, qpos, qvel) -> tuple[np.ndarray, np.ndarray]:
    """The ball (4,) and segments (N, 6) of a port's qpos and qvel, through MuJoCo C's
    kinematics (``MujocoChain.read``) in float64."""
    host.data.qpos[:] = np.asarray(qpos, dtype=float).reshape(-1)
    host.data.qvel[:] = np.asarray(qvel, dtype=float).reshape(-1)
    return host.read()
