#!/usr/bin/env bash
# From zero: installs what is needed, builds build/bin/liggghts and runs the
# demo deck (a disc held on another disc by rolling resistance).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install_deps.sh
bash tools/build.sh
cd examples/demo
../../build/bin/liggghts -in in.demo
