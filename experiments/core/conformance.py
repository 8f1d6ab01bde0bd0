"""The conformance suite as pytest cases, for a plug-in author's own tests (scikit-learn's
``parametrize_with_checks``): one case per check that applies, for an engine's record or its
adapter class, registered or not yet.

    from experiments.core.conformance import parametrize_with_checks
    from mypackage import MyAdapter

    @parametrize_with_checks([MyAdapter], expected_failures={"oblique": "no friction yet"})
    def test_my_engine(engine, check):
        check(engine)

A record not registered is registered for the check's while (``adapters.register``) and then
forgotten; a check named in ``expected_failures`` is expected to fail, for the reason given
(pytest's strict xfail: one that passes fails the test, so that the declaration is removed).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping

import pytest

import adapters

from .check import applicable, run_check
from .check_report import CheckFailed


def record_of(target) -> adapters.EngineRecord:
    """The record of a target: an ``EngineRecord``, an adapter class (its ``record``), or a
    registered engine's name; TypeError for anything else, naming it."""
    if isinstance(target, adapters.EngineRecord):
        return target
    if isinstance(target, str):
        return adapters.record(target)
    rec = getattr(target, "record", None)
    if isinstance(target, type) and isinstance(rec, adapters.EngineRecord):
        return rec
    raise TypeError(
        f"{target!r} is not an engine; allowed: an adapters.EngineRecord, an "
        "adapter class with its record, or a registered engine's name"
    )


def checker(name: str) -> Callable[[adapters.EngineRecord], None]:
    """The check ``name`` as a callable on a record: CheckFailed (its report's line) if the
    engine fails it."""

    def check(rec: adapters.EngineRecord) -> None:
        registered = rec.name in adapters.names()
        if not registered:
            adapters.register(rec)
        try:
            result = run_check(rec.name, name)
        finally:
            if not registered:
                adapters.unregister(rec.name)
        if not result.passed:
            raise CheckFailed(f"{rec.name} {name}: {result.detail}")

    check.__name__ = name
    return check


def parametrize_with_checks(targets: Iterable, expected_failures: Mapping[str, str] | None = None):
    """A ``pytest.mark.parametrize("engine, check", ...)`` over every check that applies to
    each target (ids ``<engine>-<check>``), those in ``expected_failures`` (check -> reason)
    marked as expected to fail."""
    expected = dict(expected_failures or {})
    params = []
    for target in targets:
        rec = record_of(target)
        for name in _applicable(rec):
            marks = (
                [pytest.mark.xfail(reason=expected[name], strict=True, raises=CheckFailed)]
                if name in expected
                else []
            )
            params.append(pytest.param(rec, checker(name), id=f"{rec.name}-{name}", marks=marks))
    return pytest.mark.parametrize("engine, check", params)


def _applicable(rec: adapters.EngineRecord) -> tuple[str, ...]:
    """The checks that apply to a record, registered or not."""
    if rec.name in adapters.names():
        return applicable(rec.name)
    adapters.register(rec)
    try:
        return applicable(rec.name)
    finally:
        adapters.unregister(rec.name)
