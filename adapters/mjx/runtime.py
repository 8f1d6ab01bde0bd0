"""MJX and JAX, imported and set up once for the adapter and its derivative: the install
check, XLA's flags and caches read when JAX starts, and the world-count buckets both pad to."""

from __future__ import annotations

import math
import os
from pathlib import Path

from ..loading import import_engine
from . import RECORD

# XLA's CPU runtime, with its concurrency-optimised scheduler, never returned from the second
# step of 512 or more worlds on a 2-core machine (jaxlib 0.10.2: every thread idle, the caller
# waiting on the step's completion event; 256 worlds ran). Without it, 1024 worlds step in
# 8 ms and 256 as fast as before. Read when JAX starts its CPU backend, after this import.
_NO_HANG = "--xla_cpu_enable_concurrency_optimized_scheduler=false"
if "concurrency_optimized_scheduler" not in os.environ.get("XLA_FLAGS", ""):
    os.environ["XLA_FLAGS"] = f"{os.environ.get('XLA_FLAGS', '')} {_NO_HANG}".strip()

mjx = import_engine(RECORD)
import jax  # noqa: E402  (mujoco.mjx brings JAX; imported after the install check)
import jax.numpy as jnp  # noqa: E402

__all__ = ["BUCKET", "bucket", "jax", "jnp", "mjx"]

# Compiled steps are kept on disk (JAX's persistent cache): a new process, a worker, a test's
# subprocess, a rerun, loads them instead of compiling again (6-9 s each on a CPU; the model
# and data helpers each take under a second, but a worker process needs a dozen of them).
if not jax.config.jax_compilation_cache_dir:
    jax.config.update(
        "jax_compilation_cache_dir",
        os.environ.get("BATSIM_JAX_CACHE", str(Path.home() / ".cache" / "batsim" / "jax")),
    )
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)

# On a CPU, JAX's asynchronous dispatch deadlocked here (every thread waiting on a futex, at
# 1e4 worlds; and with 100 steps queued at 1e3), before _NO_HANG was found: each step runs
# to its end before the next.
jax.config.update("jax_cpu_enable_async_dispatch", False)

#: Bucket sizes: powers of two up to this, then multiples of it.
BUCKET = 4096


def bucket(n: int) -> int:
    """The padded world count for ``n`` worlds (the adapter's module docstring)."""
    return 1 << max(0, n - 1).bit_length() if n <= BUCKET else BUCKET * math.ceil(n / BUCKET)
