"""The house rules a reader relies on, read from the source itself: a module reads in one
sitting (about 400 lines) and a function on one screen (about 60), a guide and not a cap (a
module is split by responsibility, not at a count: the test fails only half as long again
past it), imports in one direction only (none of the project's inside a function): theory
(``analytic``) <- engines (``adapters``) <- harness core (``experiments.core``) <- the
commands' parts (``experiments.parts``: no command among them) <- commands
(``experiments.*``); and a row's status is named through ``experiments.core.judge.Status``
outside the judge, not spelled."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from experiments.core.judge import Status

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("analytic", "adapters", "experiments")
SOURCES = sorted(p for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py")) + sorted(
    (ROOT / "tests").rglob("*.py")
)
#: The guide's sizes, and how far past them the test lets a module or function go.
MODULE_LINES, FUNCTION_LINES, PAST_GUIDE = 400, 60, 1.5
MAX_MODULE_LINES = int(MODULE_LINES * PAST_GUIDE)
MAX_FUNCTION_LINES = int(FUNCTION_LINES * PAST_GUIDE)
#: What each layer may import from the project (the layer names, by module prefix).
ALLOWED = {
    "analytic": ("analytic",),
    "adapters": ("analytic", "adapters"),
    "experiments.errors": (),  # the failures a command expects: installed before any import
    "experiments.core": ("analytic", "adapters", "experiments.core", "experiments.errors"),
    "experiments.parts": (
        "analytic",
        "adapters",
        "experiments.core",
        "experiments.errors",
        "experiments.parts",
    ),
}

#: The modules outside the judge that may still spell a status, each with why (at most 2).
#: None do: an episode's ending, whose 'non_finite' was the one word shared with a status,
#: is an ``endings.Ending`` code, its label spelt from the enum's name.
STATUS_WORDS_KEPT: dict[str, str] = {}


def _name(path: Path) -> str:
    return ".".join(path.relative_to(ROOT).with_suffix("").parts)


def _layer(module: str) -> str | None:
    for layer in sorted(ALLOWED, key=len, reverse=True):
        if module == layer or module.startswith(layer + "."):
            return layer
    return None


def _project_imports(path: Path) -> set[str]:
    """Every project module ``path`` imports, relative imports resolved."""
    module = _name(path)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = package.split(".")
            base = base[: len(base) - node.level + 1] if node.level else []
            target = ".".join(base + ([node.module] if node.module else []))
            out |= {target} | {f"{target}.{a.name}" for a in node.names}
    return {m for m in out if m.split(".")[0] in PACKAGES}


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_module_and_function_sizes(path):
    lines = path.read_text().count("\n")
    assert lines <= MAX_MODULE_LINES, f"{lines} lines"
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            length = node.end_lineno - node.lineno + 1
            assert length <= MAX_FUNCTION_LINES, f"{node.name}: {length} lines"


@pytest.mark.parametrize(
    "path", [p for p in SOURCES if _layer(_name(p))], ids=lambda p: str(p.relative_to(ROOT))
)
def test_no_project_module_is_imported_inside_a_function(path):
    # an import circle is resolved by moving what both sides need, not hidden by importing
    # late; third-party modules may still load late (matplotlib, Dask: a cost, not a circle)
    late = [
        node.lineno
        for fn in ast.walk(ast.parse(path.read_text()))
        if isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef)
        for node in ast.walk(fn)
        if isinstance(node, ast.ImportFrom | ast.Import) and _names_the_project(node)
    ]
    assert not late, f"{_name(path)}: project imports inside a function at lines {late}"


def _names_the_project(node: ast.Import | ast.ImportFrom) -> bool:
    if isinstance(node, ast.ImportFrom):
        return node.level > 0 or (node.module or "").split(".")[0] in PACKAGES
    return any(a.name.split(".")[0] in PACKAGES for a in node.names)


@pytest.mark.parametrize(
    "path", [p for p in SOURCES if _layer(_name(p))], ids=lambda p: str(p.relative_to(ROOT))
)
def test_imports_point_one_way(path):
    allowed = ALLOWED[_layer(_name(path))]
    wrong = sorted(
        m
        for m in _project_imports(path)
        if not any(m == a or m.startswith(a + ".") for a in allowed)
    )
    assert not wrong, f"{_name(path)} imports {wrong}: allowed {allowed}"


def _status_words(path: Path) -> list[tuple[int, str]]:
    """Each string constant equal to a status and used as one: compared, a ``.get`` key, or in
    a dict's keys or a tuple, list or set whose strings are all statuses (a row of columns
    such as ``{"engine": ..., "ok": ...}`` names a column, not a status)."""
    words = {s.value for s in Status}
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Compare):
            used = [node.left, *node.comparators]
        elif isinstance(node, ast.Dict | ast.Tuple | ast.List | ast.Set):
            strings = [
                n
                for n in (node.keys if isinstance(node, ast.Dict) else node.elts)
                if isinstance(n, ast.Constant) and isinstance(n.value, str)
            ]
            used = strings if all(n.value in words for n in strings) else []
        elif (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "get"
            and node.args
        ):
            used = node.args[:1]
        else:
            continue
        found += [
            (n.lineno, n.value) for n in used if isinstance(n, ast.Constant) and n.value in words
        ]
    return found


def test_statuses_only_through_the_enum():
    judge = ROOT / "experiments" / "core" / "judge.py"
    found = {
        str(p.relative_to(ROOT)): words
        for p in SOURCES
        if p.relative_to(ROOT).parts[0] in PACKAGES and p != judge and (words := _status_words(p))
    }
    assert len(STATUS_WORDS_KEPT) <= 2
    assert set(found) == set(STATUS_WORDS_KEPT), {
        m: w for m, w in found.items() if m not in STATUS_WORDS_KEPT
    }


def test_nothing_points_outside_the_project():
    """The project stands alone: no file names the design notes it grew from."""
    texts = [
        p
        for p in ROOT.rglob("*")
        if p.suffix in {".py", ".md", ".toml", ".txt", ".cfg"}
        and not any(part.startswith((".", "runs")) for part in p.relative_to(ROOT).parts)
        and p != Path(__file__).resolve()
    ]
    hits = [
        str(p.relative_to(ROOT))
        for p in texts
        if "../shared" in p.read_text(errors="ignore")
        or "ENGINE_NOTES" in p.read_text(errors="ignore")
    ]
    assert not hits, hits
