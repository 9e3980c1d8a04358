#!/usr/bin/env bash
# The whole test suite from a fresh clone: installs what is missing, builds
# build/bin/liggghts, runs pytest with Debian's Python. Extra arguments go to
# pytest (e.g. tools/test.sh -k jiang -x).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install_deps.sh
bash tools/build.sh
exec /usr/bin/python3 -m pytest tests "$@"
