#!/usr/bin/env bash
# The whole test suite from a fresh clone: installs what is missing, builds
# build/bin/liggghts, runs pytest with Debian's Python. Extra arguments go to
# pytest (e.g. tools/test.sh -k jiang -x).
#
#   bash tools/test.sh --fast [pytest arguments]
#       only the tests that need no LIGGGHTS binary (the host-free core's
#       drivers, the analysis, the records and pages): no build, about two
#       minutes. For a change to analysis/, doc/ or a core header; the full
#       suite (CI's) for anything that reaches the engine. It runs on two
#       pytest-xdist workers, one test file each at a time (a file's
#       session fixtures, e.g. a compiled driver, are made once); `-n 0`
#       among the arguments runs it in one process.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install_deps.sh
if [ "${1:-}" = --fast ]; then
  shift
  # a test that runs the engine without its `engine` mark fails here, loudly
  export SILOKIT_LIGGGHTS=/nonexistent/tools-test-fast-runs-no-liggghts
  exec /usr/bin/python3 -m pytest tests --fast -n 2 --dist loadfile "$@"
fi
bash tools/build.sh
exec /usr/bin/python3 -m pytest tests "$@"
