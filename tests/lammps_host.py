"""What the LAMMPS tests (tests/test_lammps_*.py) share: where LAMMPS and our
plugin are, a skip when they are not built, and a runner.

LAMMPS is build/bin/lmp and the plugin build/lib/silokit_lammps.so, or
$SILOKIT_LMP and $SILOKIT_LAMMPS_PLUGIN (doc/testing.md). A build configured
with -DSILOKIT_LAMMPS=OFF has neither: the tests are then skipped, saying so.
"""

import os
import shutil
from pathlib import Path

import pytest

from analysis.testing import run_deck

ROOT = Path(__file__).resolve().parent.parent
LMP = Path(os.environ.get("SILOKIT_LMP", ROOT / "build" / "bin" / "lmp"))
PLUGIN = Path(os.environ.get("SILOKIT_LAMMPS_PLUGIN", ROOT / "build" / "lib" / "silokit_lammps.so"))


def missing_reason():
    for path, variable in ((LMP, "SILOKIT_LMP"), (PLUGIN, "SILOKIT_LAMMPS_PLUGIN")):
        if not path.exists():
            return (f"{path} is missing (a build with -DSILOKIT_LAMMPS=OFF has no LAMMPS): "
                    f"build it with tools/build.sh, or point {variable} at it")
    return None


# every LAMMPS test: the `engine` mark (tools/test.sh --fast leaves it out)
# and a skip when LAMMPS or the plugin is not built
needs_lammps = [pytest.mark.engine,
                pytest.mark.skipif(missing_reason() is not None, reason=str(missing_reason()))]


def has_mpirun():
    return shutil.which("mpirun") is not None


def run_lammps(deck, workdir, nprocs=1, variables=None, timeout=600):
    """Runs a deck (its text) with our lmp in workdir; the deck loads the
    plugin with `plugin load ${plugin}`. Returns analysis.testing's Run;
    raises LiggghtsError carrying LAMMPS' first ERROR line when it fails."""
    variables = dict(variables or {})
    variables.setdefault("plugin", str(PLUGIN))
    return run_deck(deck, workdir, nprocs=nprocs, variables=variables, binary=LMP,
                    timeout=timeout, log_file="log.lammps")
