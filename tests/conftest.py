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


def run_liggghts(deck, workdir, nprocs=1, variables=None, timeout=600, batch=False,
                 log_file="log.liggghts"):
    """Writes `deck` to workdir/in.deck, runs it (under mpirun when
    nprocs > 1) and returns the screen output. Raises LiggghtsError carrying
    the ERROR line when LIGGGHTS fails; a hang ends in TimeoutExpired.
    batch=True runs it as a cluster job does: no stdbuf, stdout and stderr
    into the files out.txt and err.txt of workdir (the output returned is
    theirs). log_file=None leaves out -log (LIGGGHTS' default log file)."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(deck)
    command = [str(LIGGGHTS), "-in", "in.deck", "-echo", "screen"]
    if log_file:
        command += ["-log", log_file]
    if not batch:
        # line buffering: the output of a run that hangs or is killed
        command = ["stdbuf", "-oL"] + command
    for name, value in (variables or {}).items():
        command += ["-var", name, str(value)]
    if nprocs > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(nprocs)] + command
    if batch:
        with open(workdir / "out.txt", "w") as out, open(workdir / "err.txt", "w") as err:
            result = subprocess.run(command, cwd=workdir, stdout=out, stderr=err, timeout=timeout)
        output = ((workdir / "out.txt").read_text(errors="replace")
                  + (workdir / "err.txt").read_text(errors="replace"))
    else:
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
