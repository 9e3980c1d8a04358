"""`python3 -m analysis.silo3d_rotating`: the scene's analysis of run
directories (analysis.silo3d_rotating.analyse)."""

import sys

from analysis.silo3d_rotating.analyse import main

sys.exit(main())
