"""Shared fixtures: run the built LIGGGHTS on a small deck in a temporary
directory and hand back its output."""

import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from analysis.testing import liggghts_binary as _binary, run_deck  # noqa: E402

# our tests run the documented helper (analysis/testing.py, doc/testing.md),
# so that it stays right; $SILOKIT_LIGGGHTS or build/bin/liggghts
LIGGGHTS = _binary()


def run_liggghts(deck, workdir, nprocs=1, variables=None, timeout=600, batch=False,
                 log_file="log.liggghts"):
    """analysis.testing.run_deck with a deck's text, returning its screen
    output; raises LiggghtsError carrying the ERROR line when LIGGGHTS fails."""
    return run_deck(deck, workdir, nprocs=nprocs, variables=variables, binary=LIGGGHTS,
                    timeout=timeout, batch=batch, log_file=log_file).output


@pytest.fixture(scope="session")
def liggghts_binary():
    if not LIGGGHTS.exists():
        pytest.fail(f"{LIGGGHTS} is missing: build it with tools/build.sh")
    return LIGGGHTS


@pytest.fixture
def run(liggghts_binary, tmp_path):
    """run(deck, nprocs=1, variables=None, subdir='.') -> screen output."""
    def runner(deck, nprocs=1, variables=None, subdir="."):
        return run_liggghts(deck, tmp_path / subdir, nprocs=nprocs, variables=variables)
    return runner


def has_mpirun():
    return shutil.which("mpirun") is not None


# ---- the fast tier: tools/test.sh --fast ---------------------------------

def pytest_addoption(parser):
    parser.addoption("--fast", action="store_true",
                     help="only the tests that need no LIGGGHTS binary (no `engine` mark, no liggghts_binary)")


def pytest_configure(config):
    config.addinivalue_line("markers", "engine: runs the built LIGGGHTS (tools/test.sh --fast leaves it out)")


def needs_engine(item):
    return item.get_closest_marker("engine") is not None or "liggghts_binary" in getattr(item, "fixturenames", ())


def pytest_collection_modifyitems(config, items):
    if not config.getoption("--fast"):
        return
    engine = [item for item in items if needs_engine(item)]
    if engine:
        config.hook.pytest_deselected(items=engine)
        items[:] = [item for item in items if not needs_engine(item)]
