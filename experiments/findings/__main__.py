"""``python -m experiments.findings``: run the findings command."""

import sys

from . import main

if __name__ == "__main__":
    sys.exit(main())
