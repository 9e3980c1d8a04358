#!/usr/bin/env bash
# Configures and builds build/bin/liggghts (incremental; extra arguments go
# to the cmake configure step, e.g. -DLIGGGHTS_SOURCE_DIR=/path/to/LIGGGHTS).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build "$@"
cmake --build build -j "$(nproc)"
