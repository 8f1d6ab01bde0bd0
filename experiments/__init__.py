"""The harness core (``experiments.core``) and the commands, each run as
``python -m experiments.<name>``."""

import sys

if sys.argv[:1] == ["-m"]:  # a command is starting: its first failure, an import's too, in one line
    from . import errors

    sys.excepthook = errors.excepthook
