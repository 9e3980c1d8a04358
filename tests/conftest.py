"""Shared fixtures: run the built LIGGGHTS on a small deck in a temporary
directory and hand back its output."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

LIGGGHTS = Path(os.environ.get("SILOKIT_LIGGGHTS", ROOT / "build" / "bin" / "liggghts"))


class LiggghtsError(RuntimeError):
    """LIGGGHTS stopped with an error; .message holds its ERROR line."""

    def __init__(self, message, output):
        super().__init__(message)
        self.message = message
        self.output = output


def run_liggghts(deck, workdir, nprocs=1, variables=None, timeout=600):
    """Writes `deck` to workdir/in.deck, runs it (under mpirun when
    nprocs > 1) and returns the screen output. Raises LiggghtsError carrying
    the ERROR line when LIGGGHTS fails; a hang ends in TimeoutExpired."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(deck)
    # stdbuf: LIGGGHTS' Error::one prints its message without a flush
    # before MPI_Abort (doc/liggghts_quirks.md); line buffering keeps it
    command = ["stdbuf", "-oL", str(LIGGGHTS), "-in", "in.deck", "-echo", "screen", "-log", "log.liggghts"]
    for name, value in (variables or {}).items():
        command += ["-var", name, str(value)]
    if nprocs > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(nprocs)] + command
    # errors="replace": on some errors stock LIGGGHTS (error_special.h)
    # prints a line of garbage bytes after the message
    result = subprocess.run(command, cwd=workdir, capture_output=True, text=True,
                            errors="replace", timeout=timeout)
    output = result.stdout + result.stderr
    # lines that start with ERROR: Open MPI's own ORTE_ERROR_LOG lines do not
    errors = [line for line in output.splitlines() if line.startswith("ERROR")]
    if result.returncode != 0 or errors:
        raise LiggghtsError(errors[0] if errors else f"exit code {result.returncode}", output)
    return output


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
