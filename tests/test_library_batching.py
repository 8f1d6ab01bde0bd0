"""Each engine's record says what its library offers to step many worlds at once
(``EngineRecord.batching``), and each claim is read back from the installed library: the call
it names is there, so is every name it sets aside, the library's own public namespace holds no other
name that sounds like such a step, and the record says the harness uses the call exactly where
an adapter steps through it."""

from __future__ import annotations

import importlib
import re

import pytest

import adapters
from adapters.loading import import_engine

#: What a batched or threaded step's name would contain in a library's namespace.
SOUNDS_LIKE = re.compile(r"batch|rollout|thread|parallel|worker|vmap|pool|gpu", re.IGNORECASE)


def _resolve(target: str) -> object:
    """``module:attribute.path`` in the installed library (AttributeError if absent)."""
    module, _, path = target.partition(":")
    obj: object = importlib.import_module(module)
    for part in path.split("."):
        obj = getattr(obj, part)
    return obj


def _top_name(target: str, top: str) -> str | None:
    """The name ``target`` is reached by in the module ``top``'s own namespace."""
    module, _, path = target.partition(":")
    if module == top:
        return path.split(".")[0]
    if module.startswith(top + "."):
        return module[len(top) + 1 :].split(".")[0]
    return None


def _steps_through_its_library(name: str) -> bool:
    """Whether the harness steps the engine through its library's batched call: a batched
    adapter is built on it; a single-world engine's pool adapter, where that adapter times
    the call bare (``BatchedEngine.anchor_s``)."""
    rec = adapters.record(name)
    if rec.batched:
        return True
    pool = adapters.pool_class(name)
    return pool is not None and pool.anchor_s is not adapters.BatchedEngine.anchor_s


@pytest.mark.parametrize("name", adapters.names())
def test_the_record_says_what_batched_step_the_library_offers(name):
    rec = adapters.record(name)
    said = rec.batching
    assert said is not None, f"{name}: the record does not say (EngineRecord.batching)"
    top = import_engine(rec)
    named = [t for t in (said.call, *said.not_it) if t]
    for target in named:  # every name the record gives is in the installed library
        _resolve(target)
    accounted = {_top_name(t, top.__name__) for t in named}
    public = [n for n in dir(top) if not n.startswith("_")]
    unaccounted = sorted(n for n in public if SOUNDS_LIKE.search(n) and n not in accounted)
    assert not unaccounted, f"{name}: {top.__name__} has {unaccounted}: a step, or not_it?"
    # used exactly where an adapter steps through it; and only a call can be used
    assert said.used == _steps_through_its_library(name)
    assert said.call or not said.used
