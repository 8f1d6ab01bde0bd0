"""What a file handed to a command must be, checked before any work.

Each kind of file a command reads (a sweep table, a throughput table, a run's ``run.json``, a
folder it writes into) has a function here that reads it and returns what it holds, or raises
``BadInput`` with one line: ``'<path>' <what is wrong>; allowed: <what it must be>``. A command
calls them in its check phase and refuses with ``parser.error(str(err))`` (exit 2): a file that
is missing, a directory, empty, binary, cut mid-line, of another kind (its columns), or holding
text where numbers belong is refused there, never read as data nor met later as a traceback.
"""

from __future__ import annotations

import csv
import datetime
import errno
import io
import json
import re
import shutil
import tempfile
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

import adapters

from ..errors import BadInput


@dataclass(frozen=True, kw_only=True)
class Schema:
    """The columns a kind of CSV table must have (others may follow), by what they hold."""

    #: what the table must be, as the error's "allowed:" says it
    kind: str
    #: text on every row (an engine's, a profile's name): never blank, never all numbers
    names: tuple[str, ...] = ()
    #: a number on every row
    numbers: tuple[str, ...] = ()
    #: a number or blank
    maybe_numbers: tuple[str, ...] = ()
    #: present, whatever they hold
    others: tuple[str, ...] = ()
    #: the column whose values must be registered engines (``adapters.names()``), if any
    engines: str | None = None
    #: the column whose values must name a kind of device the harness knows (``device_kind``)
    devices: str | None = None
    #: the columns that name a row: no two rows alike on them
    unique: tuple[str, ...] = ()

    @property
    def columns(self) -> tuple[str, ...]:
        return (*self.names, *self.numbers, *self.maybe_numbers, *self.others)


#: Rows are matched on these in a comparison: a sweep names them on every row.
SWEEP_KEYS = (
    "engine",
    "profile",
    "bat",
    "s_m",
    "v0_mps",
    "u0_mps",
    "omega0_radps",
    "e",
    "theta_rad",
)
SWEEP = Schema(
    kind="a sweep table (sweep.csv of a run)",
    names=SWEEP_KEYS[:3],
    numbers=SWEEP_KEYS[3:],
    maybe_numbers=("v1_abs_err_mps",),
    others=("status",),
)
#: The table ``experiments.parts.throughput.measure`` writes (bench_batches.csv), every column.
THROUGHPUT = Schema(
    kind="a throughput table (bench_batches.csv of a bench_engines run)",
    names=("engine", "precision", "device"),
    numbers=(
        "batch",
        "impacts_per_s",
        "wall_s",
        "us_per_impact",
        "bare_us_per_impact",
        "harness_us_per_impact",
        "max_abs_err_mps",
    ),
    maybe_numbers=(
        "step_us_per_impact",
        "read_us_per_impact",
        "steps_median",
        "repeats",
        "ok",
        "judged",
    ),
    others=("batched",),
    engines="engine",
    devices="device",
    unique=("engine", "batch", "device"),
)
#: A twins run's table (twins.csv); on a GPU machine it adds the device.
TWINS = Schema(
    kind="a twins table (twins.csv of a twins run)",
    names=("engine", "step"),
    maybe_numbers=("max_abs_diff_mps", "median_abs_diff_mps"),
    others=("statuses",),
)
TWINS_ON_DEVICE = Schema(
    kind=TWINS.kind,
    names=(*TWINS.names, "device"),
    maybe_numbers=TWINS.maybe_numbers,
    others=TWINS.others,
    devices="device",
)
#: The kind of device a row's ``device`` names, by its platform (the text before its first
#: colon): what adapters' ``device()`` write (Warp's ``cpu``, ``cuda:N: name``; JAX's
#: ``cpu: cpu``, ``gpu: name``, ``rocm`` for AMD). The benchmarks' charts and the GPU runs'
#: gathering sort rows into these two kinds; a row of another (a TPU's) belongs to neither.
DEVICE_KINDS = {"cpu": "CPU", "cuda": "GPU", "gpu": "GPU", "rocm": "GPU"}
#: A stability run's tables: every impact, and the map's cells.
STABILITY = Schema(
    kind="a stability table (stability.csv of a stability run)", names=("map",), others=("status",)
)
STABILITY_CELLS = Schema(
    kind="a stability map's cells (stability_cells.csv of a stability run)",
    names=("map",),
    numbers=("dt_s",),
    maybe_numbers=("v0_mps", "soft_omega_radps", "fraction_ok"),
    others=("failure",),
)


def device_kind(device: str) -> str | None:
    """'CPU' or 'GPU': the kind of device ``device`` names (``DEVICE_KINDS``), None if it
    names none the harness knows."""
    return DEVICE_KINDS.get(str(device).split(":", 1)[0].strip().lower())


def bad(path: Path, wrong: str, allowed: str) -> BadInput:
    """The one line refusing ``path``: what is wrong with it and what is allowed."""
    return BadInput(f"{str(path)!r} {wrong}; allowed: {allowed}".replace("\n", " "))


def _exists(path: Path, allowed: str) -> bool:
    """Whether ``path`` exists; BadInput where even that cannot be told (a name too long)."""
    try:
        return path.exists()
    except OSError as err:
        raise bad(
            path, f"cannot be looked up ({err.strerror or type(err).__name__})", allowed
        ) from None


def existing_file(path: Path, allowed: str) -> bytes:
    """The bytes of ``path``: a regular file, not empty."""
    path = Path(path)
    if not _exists(path, allowed):
        raise bad(path, f"is not a file: {_absent(path)}", allowed)
    if path.is_dir():
        raise bad(path, "is not a file: it is a directory", allowed)
    if not path.is_file():
        raise bad(path, "is not a regular file (a device, a pipe?)", allowed)
    try:
        data = path.read_bytes()
    except OSError as err:
        raise bad(path, f"cannot be read ({err.strerror or type(err).__name__})", allowed) from None
    if not data.strip():
        raise bad(path, "is empty", allowed)
    return data


def _absent(path: Path) -> str:
    """Why a path that does not exist as a file does not: a link to nothing, a loop of
    links, or nothing there at all."""
    if not path.is_symlink():
        return "it does not exist"
    try:
        path.stat()
    except OSError as err:
        if err.errno == errno.ELOOP:
            return "it is a symbolic link loop (a link that leads back to itself)"
    return f"it is a symbolic link to {str(path.readlink())!r}, which does not exist"


def text_file(path: Path, allowed: str) -> str:
    """The text of ``path``: UTF-8 (a leading byte-order mark dropped), no NUL."""
    data = existing_file(path, allowed)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise bad(
            path,
            f"is not a text file (byte 0x{data[err.start]:02x} at offset "
            f"{err.start} is not UTF-8: a binary file?)",
            allowed,
        ) from None
    if "\0" in text:
        raise bad(
            path, f"holds a NUL byte at offset {text.index(chr(0))} (a binary file?)", allowed
        )
    return text


def _rows(path: Path, text: str, allowed: str) -> None:
    """Every row as wide as the header, whose names are given once each. A last line without
    its newline (the harness ends every table with one) is a cut file where it is narrower or
    wider than the header or holds text where its column's other rows hold numbers; else a
    complete table written by another hand."""
    try:
        rows = list(csv.reader(io.StringIO(text, newline=""), strict=True))
    except csv.Error as err:
        raise bad(path, f"is not a CSV table ({err})", allowed) from None
    header = rows[0]
    if not text.endswith(("\n", "\r")) and len(rows) > 1:
        _last_row(path, rows, allowed)
    for n, row in enumerate(rows[1:], start=2):
        if row and len(row) != len(header):  # (pandas skips blank lines too)
            raise bad(
                path,
                f"is not a CSV table: line {n} has {len(row)} fields, its "
                f"header {len(header)} (a damaged or cut file?)",
                allowed,
            )
    blank = [i for i, name in enumerate(header, start=1) if not name.strip()]
    if blank:
        raise bad(path, f"has a header without a name in column {blank[0]}", allowed)
    twice = sorted({name for name in header if header.count(name) > 1})
    if twice:
        raise bad(path, f"names column {twice[0]!r} twice in its header", allowed)


def _last_row(path: Path, rows: list[list[str]], allowed: str) -> None:
    """A last line left without its newline: as wide as the header, and a number (or blank)
    in every column whose other rows all hold numbers; else the file was cut short."""
    header, last, above = rows[0], rows[-1], [r for r in rows[1:-1] if len(r) == len(rows[0])]
    if len(last) != len(header):
        raise bad(
            path,
            f"ends mid-line: its last line has {len(last)} fields, its header "
            f"{len(header)} (the file was cut short?)",
            allowed,
        )
    for i, value in enumerate(last):
        numeric = above and all(_number(r[i]) for r in above if r[i].strip())
        if numeric and value.strip() and not _number(value):
            raise bad(
                path,
                f"ends mid-line: its last line's {header[i]!r} is {value!r}, not a "
                "number as above it (the file was cut short?)",
                allowed,
            )


def _plain(value):
    """A table's value as Python holds it (1, not np.int64(1)), for a message."""
    return value.item() if hasattr(value, "item") else value


def _number(value: str) -> bool:
    try:
        float(value)
    except ValueError:
        return False
    return True


def table(path: Path, schema: Schema) -> pd.DataFrame:
    """The table at ``path``, checked against ``schema``."""
    path = Path(path)
    text = text_file(path, schema.kind)
    _rows(path, text, schema.kind)
    try:
        df = pd.read_csv(io.StringIO(text), on_bad_lines="error")
    except (pd.errors.ParserError, pd.errors.EmptyDataError, ValueError) as err:
        raise bad(path, f"is not a CSV table ({err})", schema.kind) from None
    if df.empty:
        raise bad(path, "has a header but no rows", schema.kind)
    missing = [c for c in schema.columns if c not in df.columns]
    if missing:
        raise bad(
            path,
            f"is not {schema.kind.split(' (')[0]}: no column {missing[0]!r} "
            f"({len(df.columns)} columns: {_listed(df.columns)})",
            schema.kind,
        )
    for col in schema.names:
        _names(path, df[col], schema.kind)
    for col in (*schema.numbers, *schema.maybe_numbers):
        _numbers(path, df[col], schema.kind, blank=col in schema.maybe_numbers)
    if schema.engines:
        unknown = sorted(set(df[schema.engines]) - set(adapters.names()))
        if unknown:
            raise bad(
                path,
                f"names engine {unknown[0]!r}, which is not registered",
                f"{schema.kind}, of the engines {', '.join(adapters.names())}",
            )
    _devices_and_keys(path, df, schema)
    return df


def _devices_and_keys(path: Path, df: pd.DataFrame, schema: Schema) -> None:
    """Each device of a kind the harness knows; no two rows alike on ``schema.unique``."""
    if schema.devices:
        unknown = [device_kind(d) is None for d in df[schema.devices]]
        if any(unknown):
            at = unknown.index(True)
            raise bad(
                path,
                f"has device {df[schema.devices].iloc[at]!r} on row {at + 1}, a "
                "kind of device the harness does not know",
                f"{schema.kind}, its devices a CPU (cpu) or a GPU (cuda:N, gpu, rocm)",
            )
    if schema.unique:
        twice = df.duplicated(list(schema.unique))
        if twice.any():
            at = int(twice.argmax())
            first = int(
                (df[list(schema.unique)] == df[list(schema.unique)].iloc[at]).all(axis=1).argmax()
            )
            said = ", ".join(f"{c} {_plain(df[c].iloc[at])!r}" for c in schema.unique)
            raise bad(
                path,
                f"has row {at + 1} the same as row {first + 1} ({said})",
                f"{schema.kind}, one row per {', '.join(schema.unique)}",
            )


def _listed(names: Sequence[str], most: int = 6) -> str:
    shown = ", ".join(map(str, list(names)[:most]))
    return shown + (", ..." if len(names) > most else "")


def _names(path: Path, col: pd.Series, allowed: str) -> None:
    """A column of names: text on every row."""
    if col.isna().all():
        raise bad(path, f"has column {col.name!r} blank on every row", allowed)
    if pd.api.types.is_numeric_dtype(col) or pd.api.types.is_bool_dtype(col):
        raise bad(
            path,
            f"has numbers in column {col.name!r} (row 1: {str(col.iloc[0])!r}), not names",
            allowed,
        )
    if col.isna().any():
        raise bad(path, f"has row {int(col.isna().argmax()) + 1} without its {col.name!r}", allowed)


def _numbers(path: Path, col: pd.Series, allowed: str, *, blank: bool) -> None:
    """A column of numbers (blanks allowed with ``blank``)."""
    if pd.api.types.is_bool_dtype(col) or not pd.api.types.is_numeric_dtype(col):
        values = pd.to_numeric(col, errors="coerce")
        at = int((values.isna() & col.notna()).argmax())
        raise bad(
            path,
            f"has text in column {col.name!r} (row {at + 1}: "
            f"{str(col.iloc[at])!r}), where numbers belong",
            allowed,
        )
    if not blank and col.isna().any():
        raise bad(path, f"has row {int(col.isna().argmax()) + 1} without its {col.name!r}", allowed)


def json_object(path: Path, allowed: str, keys: dict[str, type | tuple[type, ...]]) -> dict:
    """The JSON object at ``path``, with each of ``keys`` of its type."""
    path = Path(path)
    text = text_file(path, allowed)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as err:
        raise bad(path, f"is not JSON ({err})", allowed) from None
    if not isinstance(data, dict):
        raise bad(path, f"holds a JSON {type(data).__name__}, not an object", allowed)
    for key, kind in keys.items():
        if key not in data:
            raise bad(path, f"has no {key!r}", allowed)
        value = data[key]
        if not isinstance(value, kind) or (isinstance(value, bool) and bool not in _tuple(kind)):
            raise bad(path, f"has {key!r} = {value!r}, not a {_kinds(kind)}", allowed)
    return data


def _tuple(kind: type | tuple[type, ...]) -> tuple[type, ...]:
    return kind if isinstance(kind, tuple) else (kind,)


def _kinds(kind: type | tuple[type, ...]) -> str:
    names = {
        "str": "text",
        "dict": "JSON object",
        "list": "JSON list",
        "bool": "true/false",
        "int": "number",
        "float": "number",
    }
    return " or ".join(dict.fromkeys(names.get(k.__name__, k.__name__) for k in _tuple(kind)))


RUN_JSON = "a run's run.json (a JSON object with its ISO date_utc, as every command writes)"


def run_date(path: Path) -> datetime.datetime:
    """When the run whose ``run.json`` is at ``path`` was made (UTC)."""
    data = json_object(path, RUN_JSON, {"date_utc": str})
    try:
        date = datetime.datetime.fromisoformat(data["date_utc"])
    except ValueError:
        raise bad(path, f"has date_utc = {data['date_utc']!r}, not an ISO date", RUN_JSON) from None
    return date if date.tzinfo else date.replace(tzinfo=datetime.UTC)


def directory(path: Path, allowed: str) -> Path:
    """``path``: a directory that exists."""
    path = Path(path)
    if not _exists(path, allowed):
        raise bad(
            path,
            f"is not a directory: {_absent(path)}" if path.is_symlink() else "does not exist",
            allowed,
        )
    if not path.is_dir():
        raise bad(path, "is not a directory", allowed)
    return path


def writable_directory(path: Path, allowed: str) -> Path:
    """``path``: a directory that exists or can be made, where files can be made (tried, not
    assumed: a root user's os.access says yes to /proc)."""
    path = Path(path).expanduser()
    probe = path
    while not _exists(probe, allowed) and probe != probe.parent:
        probe = probe.parent
    if not probe.is_dir():
        said = "is a file" if probe == path else f"lies under {str(probe)!r}, a file"
        raise bad(path, said, allowed)
    try:
        shutil.rmtree(tempfile.mkdtemp(dir=probe, prefix=".batsim-probe-"))
    except OSError as err:
        raise bad(
            path,
            f"cannot hold new files ({err.strerror or type(err).__name__} in {probe})",
            allowed,
        ) from None
    return path


WHEEL = "the path of a wheel (a .whl file, as pip download or a build makes)"


def wheel(path: Path) -> str:
    """The distribution a wheel at ``path`` holds (its file name's first part, normalised as
    PEP 503 does): a zip archive with a .dist-info/METADATA."""
    path = Path(path)
    existing_file(path, WHEEL)
    try:
        with zipfile.ZipFile(path) as archive:
            names = archive.namelist()
    except (zipfile.BadZipFile, OSError) as err:
        raise bad(path, f"is not a zip archive ({err})", WHEEL) from None
    if not any(re.fullmatch(r"[^/]+\.dist-info/METADATA", n) for n in names):
        raise bad(path, "holds no .dist-info/METADATA (not a wheel)", WHEEL)
    return distribution(path.name.split("-", 1)[0])


def distribution(name: str) -> str:
    """A distribution's name normalised (PEP 503): ``Foo_Bar`` -> ``foo-bar``."""
    return re.sub(r"[-_.]+", "-", name).lower()
