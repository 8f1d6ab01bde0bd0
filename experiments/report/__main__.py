"""python -m experiments.report"""

import sys

from . import main

sys.exit(main())
