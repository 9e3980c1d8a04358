#!/bin/bash
# A small ensemble of the open 2D pile (inputs/pile2d, Magalhaes et al.
# 2014): piles of L = 20 d for the four contact models (none, overlap,
# depth, fixed), each discharged at several widths, then h(w), w_t and the
# paper's Figs. 4-6 with analysis/pile2d/discharges.py. About 4 min of CPU on one core.
#
#   bash examples/pile2d/run.sh [RUN_DIR]
#
# Environment: SEEDS (piles per model, default 6), L (default "20"; e.g.
# "20 30" gives w_c from a fit in 1/L too), JOBS (runs at once, default 1).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
RUN_DIR="${1:-$ROOT/examples/pile2d/runs}"
SEEDS="${SEEDS:-6}"
L="${L:-20}"
JOBS="${JOBS:-1}"
PYTHON="${PYTHON:-/usr/bin/python3}"

cd "$ROOT"
"$PYTHON" -m analysis.pile2d.driver --campaign "$RUN_DIR" --L $L --seeds "$SEEDS" \
  --widths 1.0 1.4 1.8 2.2 2.6 3.0 3.4 3.8 4.2 5.0 -j "$JOBS"
"$PYTHON" -m analysis.pile2d "$RUN_DIR/discharges.txt" --out "$RUN_DIR/analysis" --bootstrap 500
