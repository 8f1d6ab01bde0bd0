"""The general 3D impulse (EQ 141) conserves what it must, for arbitrary inertia tensors."""

from __future__ import annotations

import numpy as np
from hypothesis import assume, given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from analytic import RigidBody3D, impulse_3d

from .conftest import EPS

TOL_REL = 1e4 * EPS  # 3x3 inverses and cross products of inputs of order 1: ~1e-12 relative

vec = st.lists(st.floats(-5.0, 5.0), min_size=3, max_size=3).map(np.array)


@st.composite
def bodies(draw):
    principal = np.array(draw(st.lists(st.floats(0.01, 2.0), min_size=3, max_size=3)))
    rot = Rotation.from_rotvec(draw(vec)).as_matrix()
    inertia_kgm2 = rot @ np.diag(principal) @ rot.T
    return RigidBody3D(
        mass_kg=draw(st.floats(0.1, 3.0)),
        inertia_kgm2=inertia_kgm2,
        velocity_mps=draw(vec),
        omega_radps=draw(vec),
    )


@given(bodies(), bodies(), vec, vec, vec, st.floats(0.0, 1.0))
def test_momenta_conserved_and_restitution_holds(a, b, r_a, r_b, n, e):
    # Linear momentum sum, angular momentum about the contact point (positions x_A = p - r_A,
    # x_B = p - r_B with p = 0), and n.(pdot_A - pdot_B) after = -e * before.
    n_len = np.linalg.norm(n)
    assume(n_len >= 0.1)
    n = n / n_len
    v_rel = n @ (a.point_velocity(r_a) - b.point_velocity(r_b))
    assume(v_rel <= -0.1)  # only approaching contacts are impacts
    res = impulse_3d(a, b, r_a_m=r_a, r_b_m=r_b, normal=n, e=e)

    def momenta(A, B):
        p = A.mass_kg * A.velocity_mps + B.mass_kg * B.velocity_mps
        L = (
            np.cross(-r_a, A.mass_kg * A.velocity_mps)
            + A.inertia_kgm2 @ A.omega_radps
            + np.cross(-r_b, B.mass_kg * B.velocity_mps)
            + B.inertia_kgm2 @ B.omega_radps
        )
        return p, L

    (p0, L0), (p1, L1) = momenta(a, b), momenta(res.a, res.b)
    scale = (
        1.0
        + abs(res.j_ns) * (1 + np.linalg.norm(r_a) + np.linalg.norm(r_b))
        + sum(np.linalg.norm(x) for x in (*p0, *L0))
    )
    np.testing.assert_allclose(p1, p0, atol=TOL_REL * scale)
    np.testing.assert_allclose(L1, L0, atol=TOL_REL * scale)
    v_rel1 = n @ (res.a.point_velocity(r_a) - res.b.point_velocity(r_b))
    assert abs(v_rel1 + e * v_rel) <= TOL_REL * scale * 10
    if e == 1.0:
        ke0 = a.kinetic_energy_j() + b.kinetic_energy_j()
        ke1 = res.a.kinetic_energy_j() + res.b.kinetic_energy_j()
        assert abs(ke1 - ke0) <= TOL_REL * scale * (1 + ke0)
