"""The scene as MuJoCo's model, shared by every engine that implements MuJoCo's model (MuJoCo
C, MJX, MuJoCo Warp): the MJCF and the contact parameters that map e. Imports no engine."""

from __future__ import annotations

from analytic import Ball, Bat
from analytic.compliant import damping_ratio_for

from . import MujocoSettings


def friction_xml(mu: float, paired: bool) -> tuple[str, str]:
    """The MJCF for a contact with friction mu: (geom defaults, contact section). Frictionless:
    condim 1, no friction, no section (the model every frictionless run had). Paired: the
    bat-ball contact an explicit ``<pair>`` (condim 3, friction mu along both tangents), for
    its own ``solreffriction``, the automatic geom contact excluded; else (an untuned, native
    contact) condim 3 on both geoms, whose friction MuJoCo combines by its own rule (max)."""
    if mu == 0.0:
        return 'condim="1" friction="0 0 0"', ""
    if not paired:
        return f'condim="3" friction="{mu!r} 0 0"', ""
    return (
        'condim="3" friction="0 0 0"',
        '<contact><exclude body1="bat" body2="ball"/><pair name="bat_ball" geom1="bat" '
        f'geom2="ball" condim="3" friction="{mu!r} {mu!r} 0 0 0"/></contact>',
    )


#: A sensor of every contact, their count at each step's start (``worlds``: the contact flag of
#: each step ``mujoco.rollout`` takes, which returns states and sensor data alone).
CONTACT_SENSOR = '<sensor><contact name="contacts" data="found"/></sensor>'


def mjcf(
    bat: Bat, ball: Ball, mu: float = 0.0, paired: bool = True, contact_sensor: bool = False
) -> str:
    """The scene as MJCF: body frames at the COMs, mass properties set explicitly; friction
    as ``friction_xml`` makes it; with ``contact_sensor``, CONTACT_SENSOR (read only: the
    dynamics are the same bits, ``tests/test_pool.py``)."""
    a, b = bat.s_min_m, bat.s_max_m
    ib = ball.inertia_kgm2
    geoms, contact = friction_xml(mu, paired)
    return f"""<mujoco model="bat_ball">
  <compiler angle="radian" inertiafromgeom="false"/>
  <option gravity="0 0 0"/>
  <default><geom {geoms} margin="0" gap="0"/></default>
  <worldbody>
    <body name="bat">
      <freejoint name="bat"/>
      <inertial pos="0 0 0" mass="{bat.mass_kg!r}"
                diaginertia="{bat.axial_inertia_kgm2!r} {bat.inertia_cm_kgm2!r}
                             {bat.inertia_cm_kgm2!r}"/>
      <geom name="bat" type="capsule" fromto="{a!r} 0 0 {b!r} 0 0" size="{bat.radius_m!r}"/>
      <site name="load" pos="0 0 0"/>
    </body>
    <body name="ball" pos="0 1 0">
      <freejoint name="ball"/>
      <inertial pos="0 0 0" mass="{ball.mass_kg!r}" diaginertia="{ib!r} {ib!r} {ib!r}"/>
      <geom name="ball" type="sphere" size="{ball.radius_m!r}"/>
    </body>
  </worldbody>
  {contact}<equality><connect name="hands" body1="bat" anchor="0 0 0" active="false"/></equality>
  <actuator>
    <motor name="fx" site="load" gear="1 0 0 0 0 0"/>
    <motor name="fy" site="load" gear="0 1 0 0 0 0"/>
    <motor name="tz" site="load" gear="0 0 0 0 0 1"/>
  </actuator>{CONTACT_SENSOR if contact_sensor else ""}
</mujoco>"""


def contact_parameters(settings: MujocoSettings, e: float) -> tuple[tuple, tuple]:
    """solref and solimp that make the contact bounce with e (the package docstring)."""
    d = settings.impedance
    if settings.contact_model == "impulse":
        return (0.0, -(1.0 + e) / settings.dt_s), (d, d, 0.001, 0.5, 2.0)
    if settings.contact_model == "soft":
        w, zeta = settings.soft_omega_radps, damping_ratio_for(max(e, 1e-9))
        return (-w * w, -2.0 * zeta * w), (d, d, 0.001, 0.5, 2.0)
    return settings.solref, settings.solimp


def pair_parameters(settings: MujocoSettings, e: float) -> tuple[tuple, tuple, tuple]:
    """The frictional pair's solref, solimp and solreffriction. solref maps e as for the
    geoms (``contact_parameters``), at the impedance ``friction_impedance``: the friction rows
    are regularised as the normal one is, and stop a slip to within about (1 - d) of it in a
    step (measured on an oblique swing against the one-step law, ``analytic.friction``:
    2.8e-2 m/s of the ball's tangential speed at d = 0.99, 2.8e-4 at 0.9999, MuJoCo's
    largest); solreffriction (0, -1/dt) in the direct form asks each step to take the slip to
    rest, which the cone then bounds (Coulomb's law over one step)."""
    d = settings.friction_impedance
    solref, solimp = contact_parameters(settings, e)
    return solref, (d, d, *solimp[2:]), (0.0, -1.0 / settings.dt_s)


def port_model(mujoco, scene, st):
    """The MJCF compiled by MuJoCo C for its ports (MJX, MuJoCo Warp), with the settings'
    options and contact parameters (a ``RegularisedSettings``); with friction, the cone and (a
    tuned contact: an explicit pair) the pair's solref, solimp and solreffriction as MuJoCo
    C's, each carrying its d as the geoms' solref does (``carried``). ``mujoco``: the imported
    module (this one imports no engine)."""
    paired = st.contact_model != "native"
    m = mujoco.MjModel.from_xml_string(mjcf(scene.bat, scene.ball, scene.mu, paired))
    m.opt.timestep = st.dt_s
    m.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{st.integrator.upper()}")
    m.opt.iterations = st.iterations
    if st.ls_iterations is not None:
        m.opt.ls_iterations = st.ls_iterations
    m.eq_solref[0] = st.hinge_solref if st.hinge_solref is not None else (2 * st.dt_s, 1.0)
    solref, solimp = contact_parameters(st, scene.e)
    if paired:  # carry d where R no longer cancels it (the ports' package docstrings)
        solref = carried(solref, st.impedance, st)
    m.geom_solref[:], m.geom_solimp[:] = solref, solimp
    if scene.mu > 0.0:  # frictionless: the port's default cone (MJX refuses condim 1 in an
        m.opt.cone = getattr(mujoco.mjtCone, f"mjCONE_{st.cone.upper()}")  # elliptic one)
    if m.npair:
        solref, solimp, solreffriction = pair_parameters(st, scene.e)
        m.pair_solref[0], m.pair_solimp[0] = carried(solref, solimp[0], st), solimp
        m.pair_solreffriction[0] = carried(solreffriction, solimp[0], st)
    m.body_invweight0[:] *= st.invweight_scale
    return m


def carried(solref: tuple, d: float, st) -> tuple:
    """A direct-form solref times d + (1 - d) invweight_scale: 1 for a port's own regulariser
    (MuJoCo C's values), d once the regulariser is scaled away (the ports' docstrings)."""
    return tuple(x * (d + (1.0 - d) * st.invweight_scale) for x in solref)


#: The settings knobs a port's contact model turns into its contact arrays (the others it
#: ignores), each (settings field, element index or None for a scalar): what
#: ``contact_tangents`` differentiates.
CONTACT_KNOBS = {
    "native": (("solref", 0), ("solref", 1), *(("solimp", i) for i in range(5))),
    "soft": (("soft_omega_radps", None), ("impedance", None)),
    "impulse": (("impedance", None),),
}
#: The contact arrays of a port's model (one row per geom or pair, every row alike).
CONTACT_ARRAYS = {"geom_solref": 2, "geom_solimp": 5, "pair_solref": 2, "pair_solimp": 5}


def contact_tangents(st, e: float, knob: tuple) -> dict[str, tuple[float, ...]]:
    """The derivative of one row of each of ``port_model``'s contact arrays (CONTACT_ARRAYS)
    with respect to a settings knob, chained through ``contact_parameters`` and ``carried``:
    native, solref and solimp as given (the identity); soft, solref = c (-w^2, -2 zeta w)
    with zeta fixed by e and c = d + (1-d) s (s = ``invweight_scale``), a pair's with c at
    ``friction_impedance``; impulse, solref = c (0, -(1+e)/dt); both with solimp (d, d, ...).
    A knob not in CONTACT_KNOBS for the settings' contact model: ValueError."""
    supported = CONTACT_KNOBS[st.contact_model]
    if knob not in supported:
        raise ValueError(
            f"knob {knob!r} does not act on the {st.contact_model} contact; supported: "
            f"{', '.join(map(repr, supported))}"
        )
    out = {name: (0.0,) * size for name, size in CONTACT_ARRAYS.items()}
    field, index = knob
    if st.contact_model == "native":  # port_model writes solref and solimp as given
        out[f"geom_{field}"] = tuple(
            float(j == index) for j in range(CONTACT_ARRAYS[f"geom_{field}"])
        )
        return out
    s = st.invweight_scale
    solref, _ = contact_parameters(st, e)
    if field == "impedance":  # dc/dd = 1 - s; the pair's c is friction_impedance's
        out["geom_solref"] = tuple((1.0 - s) * x for x in solref)
        out["geom_solimp"] = (1.0, 1.0, 0.0, 0.0, 0.0)
        return out
    w = st.soft_omega_radps  # d(-w^2, -2 zeta w)/dw = (2 solref0 / w, solref1 / w)
    slope = (2.0 * solref[0] / w, solref[1] / w)
    out["geom_solref"] = carried(slope, st.impedance, st)
    out["pair_solref"] = carried(slope, st.friction_impedance, st)
    return out
