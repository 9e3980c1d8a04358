#!/bin/bash
# Runs the quasi-2D clogging silo (inputs/silo2d/in.silo2d, the paper's
# geometry) at mu = 0.4 until NARCHES arches, then draws the eta and phi PDFs
# and the paper's other figures with analysis/silo2d/clogs.py.
#
#   bash examples/silo2d/run.sh [RUN_DIR] [extra -var options for the deck]
#
# Environment: NARCHES (default 60), DT (default 1e-5 s = t_c/24.5; the
# paper's 1e-6 costs ten times more, see doc/accuracy_cost_silo2d.md),
# NPROCS (default 1), SEED (default 32452843).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
RUN_DIR="${1:-$ROOT/examples/silo2d/run_mu0.4}"
shift || true
NARCHES="${NARCHES:-60}"
DT="${DT:-1e-5}"
NPROCS="${NPROCS:-1}"
SEED="${SEED:-32452843}"
LIGGGHTS="${SILOKIT_LIGGGHTS:-$ROOT/build/bin/liggghts}"
PYTHON="${PYTHON:-/usr/bin/python3}"

mkdir -p "$RUN_DIR"
cd "$RUN_DIR"
launcher=()
if [ "$NPROCS" -gt 1 ]; then
  launcher=(mpirun --allow-run-as-root --oversubscribe -np "$NPROCS")
fi
echo "silo2d example: $NARCHES arches, dt $DT, $NPROCS rank(s), in $RUN_DIR"
start=$(date +%s)
# stdbuf: an Error::one message is printed without a flush before MPI_Abort
# (doc/liggghts_quirks.md); line buffering keeps it and shows progress at once
"${launcher[@]}" stdbuf -oL "$LIGGGHTS" -in "$ROOT/inputs/silo2d/in.silo2d" -echo none \
  -var inputs "$ROOT/inputs" -var mu 0.4 -var dt "$DT" -var narches "$NARCHES" \
  -var seed "$SEED" "$@" | grep --line-buffered -E "^(silo2d|fix clog|ERROR|WARNING: [^N])"
end=$(date +%s)
echo "silo2d example: the run took $((end - start)) s of wall time on $NPROCS rank(s)" | tee run_time.txt
cd "$ROOT"
"$PYTHON" -m analysis.silo2d "$RUN_DIR" --out "$RUN_DIR/analysis"
