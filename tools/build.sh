#!/usr/bin/env bash
# Configures and builds build/bin/liggghts (incremental; extra arguments go
# to the cmake configure step, e.g. -DLIGGGHTS_SOURCE_DIR=/path/to/LIGGGHTS).
# SILOKIT_BUILD_JOBS=N: parallel compile jobs (default: all cores), e.g. 1
# when another job holds a core.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build "$@"
cmake --build build -j "${SILOKIT_BUILD_JOBS:-$(nproc)}"
