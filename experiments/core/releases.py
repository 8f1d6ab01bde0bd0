"""One isolated Python environment per engine release, made by uv and cached.

An environment holds the harness's own dependencies at the versions ``constraints.txt`` pins and
one release of one engine (``package==version``, or a local wheel), resolved by uv together:
whatever else the release asks for is not pinned. It is made once, under
``<cache>/py<X.Y>/<package>-<version>-<hash of the pins>``, and reused: a ``ready.json``
written last (what uv installed) marks it complete, so an install that was interrupted is made
again, as is one damaged since (``fault``: its python or a distribution gone), and a lock file
keeps two processes (two Dask workers) from making the same one at once.
The harness's code is not installed there: it runs from this checkout (``PYTHONPATH``), so that
every release is judged by the same code.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tomllib
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

from filelock import FileLock

import adapters

from .io import ROOT, atomic_write_bytes

#: Where environments live unless --cache says otherwise: XDG_CACHE_HOME's, where it is set to
#: an absolute path (the XDG spec ignores any other), else ~/.cache's.
_XDG = os.environ.get("XDG_CACHE_HOME", "")
DEFAULT_CACHE = (Path(_XDG) if Path(_XDG).is_absolute() else Path.home() / ".cache") / "batsim"
#: uv's resolve and install of one release, downloads included (a cold cache: about 60 MB).
INSTALL_TIMEOUT_S = 900
READY = "ready.json"


class NotInstallable(RuntimeError):
    """uv could not install the release: it does not exist, or has no wheel for this Python."""


class IndexUnreachable(NotInstallable):
    """uv could not reach the package index (no network, a proxy, DNS, UV_OFFLINE with an
    empty cache): nothing is known of the release."""


#: What uv says when the index cannot be reached (as opposed to a release it does not have).
UNREACHABLE = re.compile(
    r"Failed to fetch|Request failed after|network was disabled|"
    r"dns error|Connection refused|tcp connect error",
    re.I,
)


@dataclass(frozen=True, kw_only=True)
class Release:
    """One engine release to judge: ``version`` as the package index spells it, or the path of
    a local wheel (a candidate before it is published)."""

    engine: str
    version: str
    #: requirements the release needs beyond its own (``numpy<2`` for a build against NumPy 1,
    #: ``setuptools`` for one that imports pkg_resources without saying so)
    extras: tuple[str, ...] = ()

    @property
    def package(self) -> str:
        return adapters.record(self.engine).install.package

    @property
    def wheel(self) -> Path | None:
        return Path(self.version) if self.version.endswith(".whl") else None

    @property
    def requirements(self) -> list[str]:
        """The release, what is released in step with it (``Install.released_with``), and its
        extras."""
        if self.wheel:
            return [str(self.wheel.resolve()), *self.extras]
        beside = adapters.record(self.engine).install.released_with
        return [f"{p}=={self.version}" for p in (self.package, *beside)] + list(self.extras)

    @property
    def key(self) -> str:
        """The environment's folder name: the release, or the wheel's name and content hash."""
        extras = "".join(f"+{re.sub(r'[^A-Za-z0-9.]', '', e)}" for e in self.extras)
        if self.wheel is None:
            return f"{self.package}-{self.version}{extras}"
        digest = hashlib.sha256(self.wheel.read_bytes()).hexdigest()[:12]
        return f"{self.wheel.stem}-{digest}{extras}"


def python_tag() -> str:
    return f"py{sys.version_info.major}.{sys.version_info.minor}"


def _name(requirement: str) -> str:
    """A requirement's distribution name, normalised (PEP 503)."""
    bare = re.split(r"[<>=!~\[; ]", requirement.strip(), maxsplit=1)[0]
    return re.sub(r"[-_.]+", "-", bare).lower()


def harness_requirements() -> list[str]:
    """The project's own dependencies without the engines (each environment brings one) and
    uv (the environments are made from outside)."""
    engines = {_name(adapters.record(n).install.package) for n in adapters.names()} | {"uv"}
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    return [r for r in project["dependencies"] if _name(r) not in engines]


def harness_closure() -> set[str]:
    """The distributions the harness's own dependencies pull in, as installed here (an extra
    they ask for included: dask[distributed])."""
    todo = [
        (_name(r), set(re.findall(r"\[(.*?)\]", r)[0].split(",")) if "[" in r else set())
        for r in harness_requirements()
    ]
    seen: set[str] = set()
    while todo:
        name, extras = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        try:
            requires = metadata.requires(name) or []
        except metadata.PackageNotFoundError:
            continue
        for r in requires:
            wanted = re.search(r"extra\s*==\s*['\"]([^'\"]+)", r)
            if wanted is None or wanted.group(1) in extras:
                todo.append((_name(r), set()))
    return seen


def constraints(release: Release) -> str:
    """The pins of constraints.txt for the harness's own libraries (``harness_closure``): an
    engine's release brings whatever else it asks for (its own dependencies, at the versions
    it needs), and what it needs beyond them (``extras``) is not pinned either. A build against
    NumPy 1 gets no pins at all: the harness's libraries resolve afresh within pyproject's
    ranges (today's need NumPy 2)."""
    if "numpy" in {_name(r) for r in release.extras}:
        return "\n"
    keep = harness_closure() - {_name(r) for r in release.extras}
    lines = (ROOT / "constraints.txt").read_text().splitlines()
    kept = [ln for ln in lines if ln.strip() and not ln.startswith("#") and _name(ln) in keep]
    return "\n".join(kept) + "\n"


def uv() -> str:
    """The uv executable that the project's dependencies installed."""
    from uv import find_uv_bin

    return find_uv_bin()


def _uv(args: list[str]) -> None:
    try:
        done = subprocess.run(
            [uv(), *args], capture_output=True, text=True, timeout=INSTALL_TIMEOUT_S
        )
    except subprocess.TimeoutExpired:
        raise NotInstallable(
            f"uv did not finish within {INSTALL_TIMEOUT_S} s (a slow network or index?)"
        ) from None
    if done.returncode and UNREACHABLE.search(done.stderr):
        fetch = re.search(r"Failed to fetch:?\s*(\S+)", done.stderr)
        where = f" at {fetch.group(1).strip('`')}" if fetch else ""
        raise IndexUnreachable(
            f"the package index could not be reached{where} ({_why(done.stderr)})"
        )
    if done.returncode:
        raise NotInstallable(_why(done.stderr))


def _why(stderr: str) -> str:
    """uv's reason, in a line: the lines that say what was not found, or its last line."""
    lines = [
        re.sub(r"^(cause|hint|error):\s*", "", ln.strip(" ×╰─▶|"))
        for ln in stderr.splitlines()
        if ln.strip()
    ]
    said = [
        ln
        for ln in lines
        if re.search(
            r"no version|not found|no wheels|unsatisf|cannot "
            r"be used|not exist|No such file",
            ln,
            re.I,
        )
    ]
    return " ".join(said or lines[-1:])[:300] or "uv failed"


def install(release: Release, target: Path) -> dict:
    """Make the environment at ``target``; return what uv installed (distribution -> version)."""
    _uv(["venv", "--quiet", "--python", sys.executable, str(target)])
    pins = target / "constraints.txt"
    pins.write_text(constraints(release))
    python = str(target / "bin" / "python")
    _uv(
        [
            "pip",
            "install",
            "--quiet",
            "--no-build",
            "--python",
            python,
            "-c",
            str(pins),
            *harness_requirements(),
            *release.requirements,
        ]
    )
    frozen = subprocess.run(
        [uv(), "pip", "freeze", "--python", python], capture_output=True, text=True, check=True
    ).stdout
    return dict(ln.split("==", 1) for ln in frozen.splitlines() if "==" in ln)


def place(release: Release, cache: Path = DEFAULT_CACHE) -> Path:
    """The folder of the release's environment in ``cache``, made or not."""
    pins = hashlib.sha256("\n".join([*harness_requirements(), constraints(release)]).encode())
    return cache / python_tag() / f"{release.key}-{pins.hexdigest()[:8]}"


def environment(release: Release, cache: Path = DEFAULT_CACHE, installer=install) -> Path:
    """The Python of the release's environment, made now if the cache has none complete;
    NotInstallable (uv's reason) if the release cannot be installed for this Python."""
    folder = place(release, cache)
    if (folder.exists() or folder.is_symlink()) and not folder.is_dir():  # not the harness's
        raise NotInstallable(
            f"{folder} is a file (or a link to none), not an environment: "
            "move it away to have the environment made there"
        )
    folder.parent.mkdir(parents=True, exist_ok=True)
    with FileLock(str(folder) + ".lock"):
        if (why := fault(folder)) is not None:
            if (folder / READY).exists():  # made once, since damaged: a cache, made again
                print(
                    f"history: the environment {folder} is broken ({why}): made again",
                    file=sys.stderr,
                )
            shutil.rmtree(folder, ignore_errors=True)
            try:
                installed = installer(release, folder)
            except BaseException:
                shutil.rmtree(folder, ignore_errors=True)
                raise
            atomic_write_bytes(folder / READY, json.dumps(installed, indent=1).encode())
    return folder / "bin" / "python"


def fault(folder: Path) -> str | None:
    """Why the environment at ``folder`` cannot be used as it is (None if it can): not made
    to the end (no ready.json), or damaged since (its ready.json, python or pyvenv.cfg gone
    or garbled, a distribution that ready.json lists gone from its site-packages)."""
    try:
        listed = json.loads((folder / READY).read_text())
    except FileNotFoundError:
        return f"no {READY}: its install did not finish"
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        return f"its {READY} cannot be read ({type(err).__name__})"
    python = folder / "bin" / "python"
    if not isinstance(listed, dict):
        return f"its {READY} is not an object"
    if not (python.is_file() and os.access(python, os.X_OK)):  # a link to a python gone too
        return "its bin/python is missing"
    if not (folder / "pyvenv.cfg").is_file():
        return "its pyvenv.cfg is missing"
    site = folder / "lib" / f"python{sys.version_info.major}.{sys.version_info.minor}"
    held = {_name(p.stem.split("-", 1)[0]) for p in site.glob("site-packages/*.dist-info")}
    lost = sorted(n for n in map(_name, listed) if n not in held)
    return f"{len(lost)} of its distributions are missing ({', '.join(lost[:3])})" if lost else None


def installed(python: Path) -> dict:
    """What the environment of ``python`` holds (its ready.json)."""
    return json.loads((python.parent.parent / READY).read_text())
