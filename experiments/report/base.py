"""What every section of the report uses: the results directory, number formats, tables.

Every number the report prints goes through one of the formats here, from a value read out of
a file in results/ (or from the model inputs in ``analytic.presets``), never typed into a string.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterable, Iterator
from functools import cache
from pathlib import Path

import pandas as pd

import adapters

from ..core.io import md_table as plain_md_table


class Damaged(Exception):
    """A results file that cannot be read as what it should be (its name and why)."""


class Missing(Exception):
    """A file a section needs is not in the results directory."""


class Infinite(ValueError):
    """A JSON Infinity: the commands write NaN for what was not measured, never infinity."""


def _finite_or_nan(constant: str) -> float:
    if constant != "NaN":
        raise Infinite(constant)
    return math.nan


class Results:
    """The files of one results directory, each read once; charts checked to exist."""

    def __init__(self, root: Path):
        self.root = Path(root)
        self._cache: dict[str, object] = {}

    def path(self, name: str) -> Path:
        path = self.root / name
        if not path.is_file():
            raise Missing(name)
        return path

    def csv(self, name: str) -> pd.DataFrame:
        if name not in self._cache:
            try:
                self._cache[name] = pd.read_csv(self.path(name))
            except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as err:
                raise Damaged(f"{name} ({type(err).__name__})") from None
        return self._cache[name].copy()

    def json(self, name: str) -> dict:
        if name not in self._cache:
            try:
                self._cache[name] = json.loads(
                    self.path(name).read_text(), parse_constant=_finite_or_nan
                )
            except (json.JSONDecodeError, UnicodeDecodeError) as err:
                raise Damaged(f"{name} ({type(err).__name__})") from None
            except Infinite as err:
                raise Damaged(f"{name} (a value {err}, which no command writes)") from None
        return self._cache[name]

    def text(self, name: str) -> str:
        return self.path(name).read_text()

    def chart(self, name: str, alt: str) -> str:
        """A markdown image of a chart beside the report (the file must exist)."""
        self.path(name)
        return f"![{alt}]({name})"

    def glob(self, pattern: str) -> list[str]:
        return sorted(p.name for p in self.root.glob(pattern))

    def memo(self, key: str, make: Callable[[], object]):
        """``make()``, computed once per results directory."""
        if key not in self._cache:
            self._cache[key] = make()
        return self._cache[key]


# -- numbers ----------------------------------------------------------------------------------


def num(x: float, sig: int = 2) -> str:
    """``sig`` significant digits: plain from 0.01 to 10^4, else 1.2e-5 (no exponent padding)."""
    if x is None or not math.isfinite(x):
        return "n/a"
    if x == 0:
        return "0"
    mantissa, exponent = f"{x:.{sig - 1}e}".split("e")
    exp = int(exponent)
    if -2 <= exp < 4:
        return f"{float(f'{x:.{sig - 1}e}'):.{max(0, sig - 1 - exp)}f}"
    return f"{mantissa}e{exp}"


def gnum(x: float) -> str:
    """Python's shortest form without exponent padding: 1e-06 -> '1e-6', 0.3 -> '0.3'."""
    text = f"{x:g}"
    if "e" in text:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}e{int(exponent)}"
    return text


def pct(fraction: float, sig: int = 2) -> str:
    """A fraction as a percentage: 0.054 -> '5.4%'."""
    return "n/a" if not math.isfinite(fraction) else f"{num(100 * fraction, sig)}%"


def times(ratio: float, digits: int = 2) -> str:
    """A ratio as '1.81x'."""
    return f"{ratio:.{digits}f}x"


def secs(t_s: float, sig: int = 2) -> str:
    """A duration with its unit: '13 us', '1.2 ms', '0.27 s'."""
    for scale, unit in ((1e-6, "us"), (1e-3, "ms")):
        if abs(t_s) < 999.5 * scale:
            return f"{whole(t_s / scale, sig)} {unit}"
    return f"{whole(t_s, sig)} s"


def whole(x: float, sig: int = 2) -> str:
    """``sig`` significant digits without trailing zeros, never rounding an integer part away:
    19299 -> '19299', 1.0 -> '1', 0.844 -> '0.84'."""
    return f"{x:.0f}" if abs(x) >= 10**sig else f"{float(f'{x:.{sig}g}'):g}"


def dist(x_m: float, sig: int = 2) -> str:
    """A length with its unit: '11 nm', '0.44 mm', '66.6 mm'."""
    for scale, unit in ((1e-9, "nm"), (1e-6, "um"), (1e-3, "mm")):
        if abs(x_m) < 999.5 * scale:
            return f"{whole(x_m / scale, sig)} {unit}"
    return f"{whole(x_m, sig)} m"


def step(dt_s: float) -> str:
    """A time step as the prose writes it: '1/60 s', '10 us', '2 ms'."""
    for n in (60, 240):
        if math.isclose(dt_s, 1 / n, rel_tol=1e-5):
            return f"1/{n} s"
    for scale, unit in ((1e-6, "us"), (1e-3, "ms"), (1.0, "s")):
        if abs(dt_s) < 999.5 * scale or unit == "s":
            return f"{dt_s / scale:.3g} {unit}"
    raise AssertionError


def sci(x: float, sig: int = 2) -> str:
    """Always scientific: 0.012 -> '1.2e-2'."""
    if not math.isfinite(x):
        return "n/a"
    mantissa, exponent = f"{x:.{sig - 1}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def span(lo: float, hi: float, fmt: Callable[[float], str] = num, sep: str = "-") -> str:
    """'lo-hi', or one value where both print alike; with ``num``, both alike in style."""
    a, b = fmt(lo), fmt(hi)
    if fmt is num and ("e" in a) != ("e" in b):
        a, b = sci(lo), sci(hi)
    if a == b:
        return a
    unit_a, unit_b = a.rpartition(" ")[2], b.rpartition(" ")[2]
    if " " in a and " " in b and unit_a == unit_b:  # '435 um', '463 um' -> '435-463 um'
        return f"{a.rpartition(' ')[0]}{sep}{b}"
    return f"{a}{sep}{b}"


WORDS = ("no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten")


def count(n: int, capital: bool = False) -> str:
    """Small counts in words, as prose writes them: 3 -> 'three'."""
    word = WORDS[n] if 0 <= n < len(WORDS) else str(n)
    return word.capitalize() if capital else word


def orders(big: float, small: float) -> int:
    """How many orders of magnitude ``big`` is above ``small`` (rounded)."""
    return round(math.log10(big / small))


# -- words ------------------------------------------------------------------------------------


def label(engine: str) -> str:
    """The engine's name as prose spells it (its record's ``label``)."""
    try:
        return adapters.record(engine).look.label or engine
    except ValueError:  # no longer registered
        return engine


def names(items: Iterable[str], conj: str = "and") -> str:
    """'a', 'a and b', 'a, b and c'."""
    items = list(items)
    if len(items) <= 1:
        return "".join(items)
    return f"{', '.join(items[:-1])} {conj} {items[-1]}"


def engines_text(engines: Iterable[str]) -> str:
    return names(label(e) for e in engines)


def method(name: str) -> str:
    """A swing-study method ('mujoco Euler') with its engine's name as prose spells it."""
    engine, _, rest = name.partition(" ")
    return f"{label(engine)} {rest}".strip()


def methods(items: Iterable[str]) -> str:
    return names(method(m) for m in items)


@cache
def precision(engine: str) -> str:
    """The engine's float precision from its record ('unknown' for an unregistered one)."""
    try:
        return adapters.record(engine).errors.precision
    except (KeyError, ValueError):
        return "unknown"


# -- tables -----------------------------------------------------------------------------------


def md_table(df: pd.DataFrame, fmt: Callable[[object], str] | None = None) -> str:
    """A frame as a GitHub markdown table; floats through ``fmt`` (default ``num``)."""
    return plain_md_table(df, fmt or num)


def bullets(items: Iterable[str]) -> str:
    """Markdown bullets; an item may span lines (continuations indented), empty ones dropped."""
    return "\n".join("- " + item.strip().replace("\n", "\n  ") for item in items if item)


def lead(head: str, facts: Iterable[str]) -> str:
    """A conclusion over its facts, one indented sub-bullet each (empty facts dropped): an item
    for ``bullets``, or a paragraph and its list on its own."""
    return "\n".join(part for part in (head.strip(), bullets(facts)) if part)


def alike(pairs: Iterable[tuple[str, str]]) -> list[tuple[list[str], str]]:
    """(engine, text) pairs with the same text merged: [(engines, text)], in first-seen order."""
    merged: dict[str, list[str]] = {}
    for engine, text in pairs:
        merged.setdefault(text, []).append(engine)
    return [(engines, text) for text, engines in merged.items()]


def _top_level(text: str) -> Iterator[int]:
    """The indices of ``text``'s characters outside brackets and backticks."""
    depth, code = 0, False
    for i, ch in enumerate(text):
        if ch == "`":
            code = not code
        elif not code and ch in "([":
            depth += 1
        elif not code and ch in ")]":
            depth -= 1
        elif not code and depth == 0:
            yield i


def clauses(text: str) -> list[str]:
    """Prose cut into its clauses, at each semicolon and sentence end outside brackets and
    backticks (a record's text, listed a clause a line); each keeps its case."""
    out, start = [], 0
    for i in _top_level(text):
        if text[i] == ";" or (
            text[i] == "." and text[i + 1 : i + 2] == " " and text[i + 2 : i + 3].isupper()
        ):
            out.append(text[start:i].strip())
            start = i + 1
    out.append(text[start:].strip().rstrip("."))
    return [c for c in out if c]


def claim(text: str) -> list[str]:
    """A record's prose as a claim and its facts: its first clause cut at its first colon
    outside brackets (the claim before it, the reason after), then the other clauses."""
    first, *rest = clauses(text)
    cut = next((i for i in _top_level(first) if first[i : i + 2] == ": "), None)
    return ([first] if cut is None else [first[:cut], first[cut + 2 :]]) + rest
