"""What a run of the conformance checks says (``check.check_engine``): one result per check,
ok or FAILED and what it saw, as a report a plug-in author reads and a test asserts on."""

from __future__ import annotations

from dataclasses import dataclass


class CheckFailed(AssertionError):
    """A check found the engine off its bound; the message says where and by how much."""


@dataclass(frozen=True, kw_only=True)
class CheckResult:
    """One check's outcome: its name, whether it passed, what it saw, how long it took (s)."""

    name: str
    passed: bool
    detail: str
    seconds: float


@dataclass(frozen=True, kw_only=True)
class CheckReport:
    """Every check run on one engine."""

    engine: str
    results: tuple[CheckResult, ...]

    @property
    def passed(self) -> bool:
        return all(r.passed for r in self.results)

    @property
    def failures(self) -> tuple[CheckResult, ...]:
        return tuple(r for r in self.results if not r.passed)

    def raise_if_failed(self) -> None:
        if not self.passed:
            raise CheckFailed(str(self))

    def __str__(self) -> str:
        width = max(len(r.name) for r in self.results)
        lines = [
            f"check_engine({self.engine!r}): {sum(r.passed for r in self.results)} of "
            f"{len(self.results)} checks passed"
        ]
        lines += [
            f"  {'ok' if r.passed else 'FAILED':6} {r.name:{width}}  {r.detail}"
            for r in self.results
        ]
        return "\n".join(lines)
