"""Run the conformance checks (``experiments.core.check_engine``) on registered engines.

    python -m experiments.check_engine --engine myengine [--check NAME[,NAME...]]

Prints one report per engine (one line per check: ok or FAILED, and what it saw) and exits 1
if any check failed: what a plug-in author runs before trusting a sweep of a new engine.
Writes nothing.
"""

from __future__ import annotations

import argparse
import sys

import adapters

from .core import boundary, cli
from .core import check as check_


def checks_arg(value: str) -> tuple[str, ...]:
    picked = tuple(dict.fromkeys(v.strip() for v in value.split(",") if v.strip()))
    bad = [v for v in picked if v not in check_.CHECKS]
    if bad or not picked:
        raise argparse.ArgumentTypeError(
            f"{value!r}: {bad[0] if bad else 'nothing'} is not a check; allowed: a "
            f"comma-separated list of {', '.join(check_.CHECKS)}"
        )
    return picked


def build_parser() -> cli.Parser:
    p = cli.Parser(
        prog="python -m experiments.check_engine",
        description=cli.summary(__doc__),
        epilog="exit codes: 0 every check passed; 1 a check failed; 2 a bad option, "
        "refused before any work",
    )
    cli.add_engine(p)
    p.add_argument(
        "--check",
        type=checks_arg,
        default=None,
        metavar="NAME[,NAME...]",
        help="only these checks (default: every one that applies to the engine)",
    )
    return p


@boundary.entry
def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)

    def body() -> int:
        passed = True
        every = args.engine == adapters.available()
        for name, why in adapters.broken().items():  # checking all: it fails, as it cannot
            print(
                f"check_engine({name!r}): {'FAILED, ' if every else ''}a broken plug-in, not "
                f"checked: {why}"
            )
            passed &= not every
        for name in args.engine:
            wanted = tuple(
                c for c in args.check or check_.applicable(name) if c in check_.applicable(name)
            )
            if not wanted:
                print(f"check_engine({name!r}): none of {', '.join(args.check)} applies")
                continue
            report = check_.check_engine(name, wanted)
            print(report)
            passed &= report.passed
        return 0 if passed else 1

    return cli.main_guard(body)


if __name__ == "__main__":
    sys.exit(main())
