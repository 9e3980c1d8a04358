"""`python3 -m analysis.silo2d`: the analysis of one run's clog records
(analysis.silo2d.clogs)."""

import sys

from analysis.silo2d.clogs import main

sys.exit(main())
