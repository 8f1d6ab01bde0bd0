"""Input checks shared by the analytic records: each failure names the field, the value and the
allowed range, so a user sees at once what to fix."""

from __future__ import annotations

import math
import numbers


def finite(name: str, value: float) -> float:
    """Return ``value`` as a float, or raise ValueError if it is not a finite real number (a
    string such as '0.5' is refused: it would fail later, far from here)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(
            f"{name}={value!r} is not a number ({type(value).__name__}); allowed: "
            "a finite real number"
        )
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name}={value!r} is not finite; allowed: a finite real number")
    return x


def instance(name: str, value: object, kind: type) -> object:
    """Return ``value`` if it is a ``kind``, else raise (a Bat passed as the ball would fail
    far from here, or worse, give a number)."""
    if not isinstance(value, kind):
        shown = repr(value) if len(repr(value)) <= 40 else f"{repr(value)[:37]}..."
        raise ValueError(f"{name}={shown} is a {type(value).__name__}; allowed: a {kind.__name__}")
    return value


def choice(name: str, value: object, allowed) -> object:
    """Return ``value`` if it is one of ``allowed``, else raise naming them."""
    if not isinstance(value, str | int | float) or value not in allowed:
        raise ValueError(f"{name}={value!r} is unknown; allowed: {', '.join(map(str, allowed))}")
    return value


def in_range(
    name: str,
    value: float,
    lo: float = -math.inf,
    hi: float = math.inf,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
) -> float:
    """Return ``value`` if it is finite and within [lo, hi] (ends open where asked), else raise."""
    x = finite(name, value)
    below = x <= lo if lo_open else x < lo
    above = x >= hi if hi_open else x > hi
    if below or above:
        left = "<" if lo_open else "<="
        right = "<" if hi_open else "<="
        raise ValueError(
            f"{name}={x!r} is out of range; allowed: {lo:g} {left} {name} {right} {hi:g}"
        )
    return x


def integer(name: str, value: int, lo: int, hi: int) -> int:
    """Return ``value`` if it is an integer within [lo, hi], else raise."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(
            f"{name}={value!r} is not an integer ({type(value).__name__}); allowed: "
            f"an integer {lo} <= {name} <= {hi}"
        )
    in_range(name, value, lo, hi)
    return int(value)


def positive(name: str, value: float) -> float:
    """Return ``value`` if it is finite and > 0, else raise."""
    return in_range(name, value, 0.0, math.inf, lo_open=True)


def non_negative(name: str, value: float) -> float:
    """Return ``value`` if it is finite and >= 0, else raise."""
    return in_range(name, value, 0.0, math.inf)


def array_in_range(name: str, values, lo: float = -math.inf, hi: float = math.inf):
    """Return ``values`` as a float array if every element is finite and within [lo, hi]; else
    raise, naming the first offending element."""
    import numpy as np

    a = np.asarray(values, dtype=float)
    bad = ~np.isfinite(a) | (a < lo) | (a > hi)
    if np.any(bad):
        x = a[bad].flat[0]
        raise ValueError(
            f"{name} contains {x!r}; allowed: finite values with {lo:g} <= {name} <= {hi:g}"
        )
    return a
