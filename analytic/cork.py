"""Corked bats: a cylinder drilled into the barrel end along the axis and filled.

A hole of radius r and depth h, centred on the axis at x_c = L - h/2, replaces wood of density
rho_wood by fill of density rho_fill (0 for a hollow bat). ``corked_bat`` is exact;
``corked_bat_paper`` reproduces the paper's section 7.1 for the audit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from . import checks, presets
from .model import WOOD_DENSITY_KGM3, Bat

#: Any fill, from none (hollow) to the densest element, osmium at 22.59 g/cm^3 (CRC Handbook
#: of Chemistry and Physics): past it a "fill" is no material.
MAX_FILL_KGM3 = 22_590.0
#: Woods, from balsa (about 100 kg/m^3) to lignum vitae (about 1,300), dry (USDA Forest
#: Products Laboratory, Wood Handbook, FPL-GTR-190, 2010, ch. 5); bat woods (ash, maple,
#: birch) lie at 600-750.
WOOD_KGM3 = (100.0, 1_400.0)


@dataclass(frozen=True, kw_only=True)
class Hole:
    """The drilled cylinder and what fills it. Units: m and kg/m^3. Its own sizes and densities
    are checked here; whether it fits a bat, by ``check_fits``."""

    radius_m: float
    depth_m: float
    fill_density_kgm3: float
    wood_density_kgm3: float

    def __post_init__(self) -> None:
        checks.positive("hole_radius_m", self.radius_m)
        checks.positive("hole_depth_m", self.depth_m)
        checks.in_range("fill_density_kgm3", self.fill_density_kgm3, 0.0, MAX_FILL_KGM3)
        checks.in_range("wood_density_kgm3", self.wood_density_kgm3, *WOOD_KGM3)

    def check_fits(self, bat: Bat) -> None:
        """Raise ValueError if the hole leaves the bat no wall (as wide as the bat where it is
        drilled: ``wall_radius_m``) or no bottom (as deep as the bat is long), or if the bat
        is hollow already (``presets.HOLLOW``)."""
        if any(bat == b for b in presets.HOLLOW):
            raise ValueError(
                f"bat '{bat.name}' is a hollow metal shell, with no wood in its "
                "barrel to drill and fill; allowed: a solid wood bat (r161)"
            )
        checks.in_range("hole_depth_m", self.depth_m, 0.0, bat.length_m, lo_open=True, hi_open=True)
        wall = self.wall_radius_m(bat)
        if not self.radius_m < wall:
            raise ValueError(
                f"hole_radius_m={self.radius_m!r} is out of range: it leaves no wall, "
                f"'{bat.name}' being {wall:.6g} m in radius where a hole_depth_m="
                f"{self.depth_m:g} hole is drilled "
                f"({bat.length_m - self.depth_m:.4g}-{bat.length_m:.4g} m from the knob); "
                f"allowed: 0 < hole_radius_m < {wall:.6g} (or a shallower hole)"
            )

    def wall_radius_m(self, bat: Bat) -> float:
        """The bat's least radius (m) over the span the hole is drilled through, from the
        barrel end to ``depth_m`` short of it: its capsule's radius, and where its profile is
        known (``presets.profile``, piecewise linear: least at a station or an end) the
        profile's there too. A hole must be narrower, or it leaves no wall."""
        prof = presets.profile(bat)
        if prof is None:
            return bat.radius_m
        x0 = bat.length_m - self.depth_m
        inside = [x for x in prof.stations_m if x0 < x < bat.length_m]
        return min(bat.radius_m, float(min(prof.radius_m([x0, *inside, bat.length_m]))))

    @property
    def volume_m3(self) -> float:
        """pi r^2 h (m^3)."""
        return math.pi * self.radius_m**2 * self.depth_m

    @property
    def dmass_kg(self) -> float:
        """dM = (rho_fill - rho_wood) pi r^2 h (kg); negative for a lighter fill."""
        return (self.fill_density_kgm3 - self.wood_density_kgm3) * self.volume_m3


def _hole(bat: Bat, hole_radius_m, hole_depth_m, fill_density_kgm3, wood_density_kgm3) -> Hole:
    h = Hole(
        radius_m=hole_radius_m,
        depth_m=hole_depth_m,
        fill_density_kgm3=fill_density_kgm3,
        wood_density_kgm3=wood_density_kgm3,
    )
    h.check_fits(bat)
    return h


def _check_result(bat: Bat, mass_kg: float, inertia_kgm2: float) -> None:
    if not mass_kg > 0.0:
        raise ValueError(
            f"corked mass {mass_kg!r} kg of '{bat.name}' is not positive: the hole "
            "removes more wood than the bat has; allowed: a smaller or denser fill"
        )
    if not inertia_kgm2 > 0.0:
        raise ValueError(
            f"corked inertia {inertia_kgm2!r} kg m^2 of '{bat.name}' is not "
            "positive; allowed: a hole that leaves the bat a positive inertia"
        )


def _label(bat: Bat, h: Hole) -> str:
    return (
        f"{bat.name} corked {2 * h.radius_m * 1e3:.1f}x{h.depth_m * 1e3:.0f} mm "
        f"@ {h.fill_density_kgm3:g} kg/m3"
    )


def corked_bat(
    bat: Bat,
    *,
    hole_radius_m: float = 0.0127,
    hole_depth_m: float = 0.254,
    fill_density_kgm3: float = 200.0,
    wood_density_kgm3: float = WOOD_DENSITY_KGM3,
) -> Bat:
    """The bat with its barrel end drilled and filled, exact.

        M'    = M + dM,                 dM = (rho_fill - rho_wood) pi r^2 h
        x'_cm = (M x_cm + dM x_c) / M', x_c = L - h/2
        J'    = J + M (x_cm - x'_cm)^2 + dM (r^2/4 + h^2/12 + (x_c - x'_cm)^2)
    i.e. the old bat and the (signed) cylinder, each moved to the NEW COM by parallel axes; the
    cylinder's own transverse moment per unit mass is r^2/4 + h^2/12. Defaults: a 1 in x 10 in
    hole filled with cork (200 kg/m^3) in the R161's wood (``WOOD_DENSITY_KGM3``, 584 kg/m^3).
    """
    h = _hole(bat, hole_radius_m, hole_depth_m, fill_density_kgm3, wood_density_kgm3)
    dM = h.dmass_kg
    x_c = bat.length_m - h.depth_m / 2
    M1 = bat.mass_kg + dM
    _check_result(bat, M1, 1.0)
    x1 = (bat.mass_kg * bat.com_from_knob_m + dM * x_c) / M1
    own = h.radius_m**2 / 4 + h.depth_m**2 / 12
    J1 = (
        bat.inertia_cm_kgm2
        + bat.mass_kg * (bat.com_from_knob_m - x1) ** 2
        + dM * (own + (x_c - x1) ** 2)
    )
    _check_result(bat, M1, J1)
    axial = None
    if bat.inertia_axial_kgm2 is not None:
        axial = bat.inertia_axial_kgm2 + dM * h.radius_m**2 / 2
    return replace(
        bat,
        name=_label(bat, h),
        mass_kg=M1,
        com_from_knob_m=x1,
        inertia_cm_kgm2=J1,
        inertia_axial_kgm2=axial,
    )


def corked_bat_paper(
    bat: Bat,
    *,
    hole_radius_m: float = 0.0127,
    hole_depth_m: float = 0.254,
    fill_density_kgm3: float = 200.0,
    wood_density_kgm3: float = WOOD_DENSITY_KGM3,
) -> Bat:
    """The paper's corked bat (its eqs. 7.1.1-7.1.4), kept for the audit.

    With L0 the COM-to-top distance and L = L0 - h the COM-to-hole-bottom distance:
        dM  = drho pi r^2 (L0 - L)                      (exact)
        R   = drho pi r^2 (L0^2 - L^2) / (2 (M + dM))   (exact COM shift)
        dJ0 = drho pi r^2 (L0^3 - L^3) / 3              (thin rod: drops dM r^2/4)
        J'  = J + (M + dM) R^2 + dJ0                    (parallel axes with the wrong sign)
    The exact J' is J + dJ0 + dM r^2/4 - (M + dM) R^2, so the paper's J' exceeds it by
    2 (M + dM) R^2 - dM r^2/4.
    """
    h = _hole(bat, hole_radius_m, hole_depth_m, fill_density_kgm3, wood_density_kgm3)
    dM = h.dmass_kg
    L0 = bat.length_m - bat.com_from_knob_m
    L = L0 - h.depth_m
    drho_area = (h.fill_density_kgm3 - h.wood_density_kgm3) * math.pi * h.radius_m**2
    M1 = bat.mass_kg + dM
    _check_result(bat, M1, 1.0)
    R = drho_area * (L0**2 - L**2) / (2 * M1)
    J1 = bat.inertia_cm_kgm2 + M1 * R**2 + drho_area * (L0**3 - L**3) / 3
    _check_result(bat, M1, J1)
    return replace(
        bat,
        name=_label(bat, h) + " (paper)",
        mass_kg=M1,
        com_from_knob_m=bat.com_from_knob_m + R,
        inertia_cm_kgm2=J1,
    )
