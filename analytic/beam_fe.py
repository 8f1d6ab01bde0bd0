"""Finite elements of a free-free beam with a varying circular section (``analytic.beam``).

Two DOFs per node, (w, rotation): Euler-Bernoulli's Hermite cubic with rotary inertia, or
Timoshenko's linear element with the shear term integrated at the element's middle (one point:
the reduced integration that keeps a thin element from locking). The section's properties are
integrated exactly at the Gauss points the beam hands in; the kinematics are what the element
interpolates.
"""

from __future__ import annotations

import numpy as np

#: Shear coefficient of a solid circular section (G. R. Cowper, J. Appl. Mech. 33, 335 (1966),
#: (6 + 6 nu)/(7 + 6 nu) at nu = 0.3; wood's nu_LR is 0.37-0.46 and moves it by 0.005).
KAPPA_CIRCLE = 0.886


def _assemble(element_k, element_m, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Global matrices from per-element (4, 4) blocks on DOFs (w_i, r_i, w_i+1, r_i+1)."""
    size = 2 * (count + 1)
    K, M = np.zeros((size, size)), np.zeros((size, size))
    for e in range(count):
        sl = slice(2 * e, 2 * e + 4)
        K[sl, sl] += element_k[e]
        M[sl, sl] += element_m[e]
    return K, M


def euler_bernoulli(nodes_m, youngs_pa, shear_pa, density_kgpm3, h, pts, wts, area, second):
    """Hermite cubic elements: K = int EI N'' N''^T, M = int rho (A N N^T + I N' N'^T)."""
    E, rho = youngs_pa, density_kgpm3  # (no shear term in this element)
    xi = (pts - nodes_m[:-1, None]) / h[:, None]
    hh = h[:, None]
    n = np.stack(
        [
            1 - 3 * xi**2 + 2 * xi**3,
            hh * (xi - 2 * xi**2 + xi**3),
            3 * xi**2 - 2 * xi**3,
            hh * (xi**3 - xi**2),
        ],
        axis=-1,
    )
    dn = (
        np.stack(
            [
                6 * (xi**2 - xi),
                hh * (1 - 4 * xi + 3 * xi**2),
                6 * (xi - xi**2),
                hh * (3 * xi**2 - 2 * xi),
            ],
            axis=-1,
        )
        / hh[..., None]
    )
    ddn = (
        np.stack([12 * xi - 6, hh * (6 * xi - 4), 6 - 12 * xi, hh * (6 * xi - 2)], axis=-1)
        / (hh**2)[..., None]
    )
    outer = np.einsum
    k_e = outer("eg,egi,egj->eij", E * second * wts, ddn, ddn)
    m_e = outer("eg,egi,egj->eij", rho * area * wts, n, n) + outer(
        "eg,egi,egj->eij", rho * second * wts, dn, dn
    )
    return _assemble(k_e, m_e, len(h))


def timoshenko(nodes_m, youngs_pa, shear_pa, density_kgpm3, h, pts, wts, area, second):
    """Linear elements in w and the section's rotation psi: bending int EI psi'^2, shear
    kappa G A (w' - psi)^2 at the middle, mass int rho (A w^2 + I psi^2)."""
    E, G, rho = youngs_pa, shear_pa, density_kgpm3
    xi = (pts - nodes_m[:-1, None]) / h[:, None]
    count = len(h)
    ei = np.sum(E * second * wts, axis=1) / h**2
    kga = np.sum(KAPPA_CIRCLE * G * area * wts, axis=1)
    bend = np.array([0.0, -1.0, 0.0, 1.0])
    shear = np.stack([-1 / h, -0.5 * np.ones(count), 1 / h, -0.5 * np.ones(count)], axis=-1)
    k_e = ei[:, None, None] * np.outer(bend, bend)[None] + kga[:, None, None] * np.einsum(
        "ei,ej->eij", shear, shear
    )
    lin = np.stack([1 - xi, xi], axis=-1)
    mw = np.einsum("eg,egi,egj->eij", rho * area * wts, lin, lin)
    mr = np.einsum("eg,egi,egj->eij", rho * second * wts, lin, lin)
    m_e = np.zeros((count, 4, 4))
    m_e[:, 0::2, 0::2] = mw
    m_e[:, 1::2, 1::2] = mr
    return _assemble(k_e, m_e, count)
