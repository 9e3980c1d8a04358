"""`python3 -m analysis.pile2d`: the statistics of a discharge record
(analysis.pile2d.discharges)."""

import sys

from analysis.pile2d.discharges import main

sys.exit(main())
