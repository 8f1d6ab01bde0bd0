"""What the harness knows about an engine: one record, declared by the engine's adapter module.

Experiments and tests read engine facts only from here (through ``adapters.record(name)``): the
install hint, the version, the profiles, the plot style, the knob grid of the speed-vs-accuracy
study, the integrators of the swing study, the float precision the tolerances derive from, and
the reference its contact converges to. A new engine brings its record and nothing else.
"""

from __future__ import annotations

import contextlib
import importlib
import os
import sys
from dataclasses import dataclass, field
from enum import Enum
from importlib import metadata
from types import MappingProxyType, ModuleType
from typing import TYPE_CHECKING, Any, Iterator, Mapping

import numpy as np

if TYPE_CHECKING:
    from .base import Settings

#: Profiles every engine must offer: tuned for fidelity, and the engine's own defaults.
PROFILES = ("reference", "default")


class EngineNotInstalled(ImportError):
    """The chosen engine's Python package is missing."""


class ContactReference(str, Enum):
    """The continuous model an engine's contact converges to as its time step shrinks."""

    RIGID_IMPULSE = "rigid impulse"  #: Newton's restitution law, instantaneous (analytic.predict)
    LINEAR_SPRING_DAMPER = "linear spring-damper"  #: x'' = -b x' - k x in the contact coordinate
    #: F = k x^n (1 + d x'): a penalty force with Hunt-Crossley dissipation (analytic.compliant)
    HUNT_CROSSLEY = "Hunt-Crossley"


class RestitutionRule(str, Enum):
    """How an engine turns the two bodies' restitution values into the contact's e."""

    PRODUCT = "product"  #: e = e_bat * e_ball
    MAX = "max"          #: e = max(e_bat, e_ball)
    MEAN = "mean"        #: e = (e_bat + e_ball) / 2
    MIN = "min"          #: e = min(e_bat, e_ball)
    MAPPED = "mapped"    #: no restitution parameter: the adapter maps e onto other knobs

    def combine(self, bat: float, ball: float) -> float:
        """The contact's e from the two bodies' values (not defined for MAPPED)."""
        if self is RestitutionRule.MAPPED:
            raise ValueError("a mapped restitution has no per-body values to combine")
        return {"product": bat * ball, "max": max(bat, ball), "mean": 0.5 * (bat + ball),
                "min": min(bat, ball)}[self.value]


@dataclass(frozen=True, kw_only=True)
class KnobFamily:
    """One family of settings in the speed-vs-accuracy study; the study crosses it with its time
    steps. ``overrides`` are settings fields and values; ``quick`` keeps it in ``--quick``."""

    label: str
    overrides: tuple[tuple[str, Any], ...] = ()
    profile: str = "reference"
    quick: bool = False


@dataclass(frozen=True, kw_only=True)
class Integrator:
    """One of an engine's time integrators, for the swing study: its ``label``, the settings
    ``overrides`` that choose it, and its global ``order`` (1: the semi-implicit Euler family,
    which leaves a constant angular acceleration's angle off by alpha t dt / 2; 4: RK4)."""

    label: str
    overrides: tuple[tuple[str, Any], ...] = ()
    order: int = 1
    #: How the hands' hinge error shrinks with dt: 2 for a pivot re-projected every step (a
    #: relative (omega dt)^2), 1 for a soft joint whose drift is corrected at a fixed rate
    #: (Box2D's 60 Hz joints).
    hinge_order: int = 2


@dataclass(frozen=True, kw_only=True)
class EngineRecord:
    """Everything the harness knows about one engine.

    ``package``: the PyPI distribution that provides it, ``import_name`` the module it imports
    (they differ, e.g. Box2D vs box2d), ``extra`` the batsim extra that installs it (None: a
    core dependency). ``profiles``: at least PROFILES; the ``default`` profile is the engine out
    of the box (its own time step and solver values). ``color``/``marker``: plot style (None:
    one from the registry's palette). ``speed_accuracy``: its knob families besides the two
    profiles. ``integrators``: label -> settings overrides for the swing study. ``precision``:
    the float type it computes in ("float64" or "float32"). ``restitution_rule``: how it
    combines two bodies' restitution; ``threshold_setting``: the settings field of its
    restitution velocity threshold, if it has one. ``soft_contact``: the overrides that switch
    it to a spring-damper contact, if it has one, whose natural frequency (rad/s) is the settings
    field ``stiffness_setting`` (the stability study maps it). ``engine_defaults``: the
    engine's own out-of-the-box values of settings fields (what the README quotes), each read
    back from the engine (``Engine.read_back_defaults``) or, where the engine does not report
    it, measured: a test pins both.
    """

    name: str
    package: str
    import_name: str
    extra: str | None = None
    profiles: Mapping[str, Settings]
    color: str | None = None
    marker: str = "o"
    speed_accuracy: tuple[KnobFamily, ...] = ()
    integrators: tuple[Integrator, ...] = (Integrator(label="semi-implicit Euler"),)
    precision: str = "float64"
    converges_to: ContactReference = ContactReference.RIGID_IMPULSE
    restitution_rule: RestitutionRule = RestitutionRule.PRODUCT
    threshold_setting: str | None = None
    soft_contact: Mapping[str, Any] | None = None
    stiffness_setting: str | None = None
    engine_defaults: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        missing = [p for p in PROFILES if p not in self.profiles]
        if missing:
            raise ValueError(f"engine {self.name!r} has no {missing[0]!r} profile; allowed: "
                             f"profiles that include {', '.join(PROFILES)}")
        if self.precision not in ("float64", "float32"):
            raise ValueError(f"precision={self.precision!r} is unknown; allowed: float64, float32")
        object.__setattr__(self, "profiles", MappingProxyType(dict(self.profiles)))
        object.__setattr__(self, "engine_defaults", MappingProxyType(dict(self.engine_defaults)))
        if (self.soft_contact is None) != (self.stiffness_setting is None):
            raise ValueError(f"engine {self.name!r}: soft_contact and stiffness_setting go "
                             "together; allowed: both or neither")

    @property
    def eps(self) -> float:
        """Unit roundoff of the engine's float type (2.2e-16 for float64, 1.2e-7 for float32)."""
        return float(np.finfo(self.precision).eps)

    @property
    def install_hint(self) -> str:
        """What to run when the engine's package is missing."""
        target = f"'batsim[{self.extra}]'" if self.extra else self.package
        return (f"engine {self.name!r} needs the package {self.package!r}: pip install {target}  "
                "(or `make test`, which installs every engine)")

    def version(self) -> str:
        """The installed version of the engine's package."""
        return metadata.version(self.package)


def import_engine(record: EngineRecord) -> ModuleType:
    """Import the engine's module, or raise EngineNotInstalled with the install hint. Whatever
    the engine prints to the process's stdout while it loads (PyBullet's build-time banner) is
    dropped, so that it never mixes with a command's own output."""
    try:
        with _stdout_silenced():
            return importlib.import_module(record.import_name)
    except ModuleNotFoundError as err:
        if err.name is None or err.name.split(".")[0] != record.import_name.split(".")[0]:
            raise
        raise EngineNotInstalled(record.install_hint) from err


@contextlib.contextmanager
def _stdout_silenced() -> Iterator[None]:
    """Point file descriptors 1 and 2 at /dev/null for the block (C libraries print there
    directly); an import error still arrives as a Python exception."""
    streams = []
    for stream in (sys.stdout, sys.stderr):
        try:
            streams.append(stream.fileno())
            stream.flush()
        except (AttributeError, OSError, ValueError):  # no real stream (captured by pytest)
            continue
    saved = [os.dup(fd) for fd in streams]
    try:
        with open(os.devnull, "wb") as null:
            for fd in streams:
                os.dup2(null.fileno(), fd)
        yield
    finally:
        _flush_c_stdio()  # C's buffered output would otherwise reach the real streams later
        for fd, copy in zip(streams, saved):
            os.dup2(copy, fd)
            os.close(copy)


def _flush_c_stdio() -> None:
    import ctypes

    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):
        pass
