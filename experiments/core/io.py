"""Atomic result files and their provenance.

A result is written to a temporary file beside its target and renamed over it, so a failed or
interrupted run leaves the previous file intact.
"""

from __future__ import annotations

import datetime as _dt
import io
import json
import os
import platform
import subprocess
import sys
import tempfile
from collections.abc import Callable
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

import adapters

ROOT = Path(__file__).resolve().parents[2]  #: the project root


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


UMASK = _umask()


def make_public(path: Path, directory: bool = False) -> None:
    """Give a file made by mkstemp (0600) or a directory made by mkdtemp (0700), and every file
    in it, the mode the user's umask asks for."""
    path = Path(path)
    if directory:
        for child in path.iterdir():
            make_public(child)
        os.chmod(path, 0o777 & ~UMASK)
    else:
        os.chmod(path, 0o666 & ~UMASK)


#: Libraries every result depends on; each engine's package comes from its record.
PACKAGES = ("numpy", "scipy", "pandas", "matplotlib")


def atomic_write_bytes(path: Path | str, data: bytes) -> Path:
    """Write ``data`` to ``path`` via a temporary file and a rename (atomic on POSIX)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        make_public(Path(tmp))
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def atomic_write_many(files: dict[Path, bytes]) -> list[Path]:
    """Write several files so that an interruption leaves all of the old ones: every temporary
    file is complete before the first rename, and the renames follow back to back."""
    staged = []
    try:
        for path, data in files.items():
            path = Path(path)
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
            with os.fdopen(fd, "wb") as f:
                f.write(data)
                f.flush()
                os.fsync(f.fileno())
            make_public(Path(tmp))
            staged.append((tmp, path))
        for tmp, path in staged:
            os.replace(tmp, path)
    finally:
        for tmp, _ in staged:
            Path(tmp).unlink(missing_ok=True)
    return [path for _, path in staged]


def figure_png(fig, dpi: int = 120) -> bytes:
    """A matplotlib figure as PNG bytes without timestamp metadata (same chart, same bytes)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})
    return buf.getvalue()


def md_table(df, fmt: Callable[[float], str]) -> str:
    """A pandas frame as a GitHub markdown table, floats through ``fmt``."""

    def cell(v: object) -> str:
        if isinstance(v, float | np.floating):
            return fmt(float(v))
        return str(v).replace("|", "\\|")

    lines = ["| " + " | ".join(map(str, df.columns)) + " |", "|" + "---|" * len(df.columns)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in df.itertuples(index=False)]
    return "\n".join(lines)


def json_bytes(obj: Any) -> bytes:
    """Indented, key-sorted JSON."""
    return (json.dumps(obj, indent=2, sort_keys=True, default=str) + "\n").encode("utf-8")


def _git(*args: str) -> str:
    try:
        return subprocess.run(
            ["git", *args], cwd=ROOT, capture_output=True, text=True, timeout=10, check=True
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


def versions() -> dict[str, str]:
    """Installed versions of the libraries whose behaviour the results depend on: the
    scientific stack and every registered engine's package (read from the installed metadata,
    no engine imported: the engines may have run in worker processes)."""
    engines = sorted({adapters.record(n).install.package for n in adapters.names()})
    out = {"python": platform.python_version()}
    for name in (*PACKAGES, *engines):
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def _command_line() -> str:
    main = sys.modules.get("__main__")
    spec = getattr(main, "__spec__", None)
    prog = f"python -m {spec.name}" if spec is not None else " ".join(sys.argv[:1])
    return " ".join([prog, *sys.argv[1:]])


def provenance(**extra: Any) -> dict[str, Any]:
    """Who made a result and how: commit (and dirty flag), versions, machine, date, command line."""
    return {
        "commit": _git("rev-parse", "HEAD") or "unknown",
        # results/ is what a run rewrites; dirty means the code differs from the commit
        "dirty": bool(
            _git("status", "--porcelain", "--untracked-files=no", "--", ".", ":!results")
        ),
        "command": _command_line(),
        "date_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "machine": {
            "platform": platform.platform(),
            "processor": platform.machine(),
            "cpus": os.cpu_count(),
        },
        "versions": versions(),
        "broken_plugins": dict(adapters.broken()),
        **extra,
    }
