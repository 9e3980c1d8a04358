"""Every ERROR reaches a user whose output goes to a file, as in a cluster
job: `liggghts -in deck > out.txt`, with and without `-log log.txt`, no
stdbuf (conftest.run_liggghts with batch=True).

LIGGGHTS' Error::all prints on rank 0, closes the log and exits: its
message always reaches the files. Error::one (an error that one rank
meets alone) printed to the screen and called MPI_Abort, which ends the
process without flushing stdio: a screen that is a file lost the message,
and Open MPI's "MPI_ABORT was invoked" was all that remained. Our patch of
Error::one (cmake/liggghts-3.8.0-error-one-flush.patch,
doc/liggghts_quirks.md) writes the message to the log too (rank 0), to
stderr on a rank without a screen, and flushes before it aborts.

Cases: a data file that gives a rod a zero quaternion (error->one in
atom_style spherocylinder, on the rank that owns the rod); a
rollingContactLength larger than a grain (error->one in the force loop,
mid-run); set_spherocylinder's 'axis random 1' (LIGGGHTS' seed check on
rank 0 was an error->one; our own check now makes it an error->all); a rod
shorter than its diameter (error->all, the control).
"""

import pytest

from analysis.common.deck_blocks import per_pair
from analysis.testing import LiggghtsError
from conftest import has_mpirun, run_liggghts
from test_jiang_errors import deck as jiang_deck
from test_spherocylinder import rod_contacts, rod_system

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

ROD_DECK = """{head}
{system}
{contacts}
fix move all nve/spherocylinder
run 1
"""

DATA_FILE = """rods with a bad quaternion

1 atoms
1 atom types

-0.1 0.1 xlo xhi
-0.1 0.1 ylo yhi
-0.1 0.1 zlo zhi

Atoms

1 1 0.01 0.03 1000 0.0 0.0 {z} 0 0 0 0
"""

CREATED_ROD = """region box block -0.1 0.1 -0.1 0.1 -0.1 0.1 units box
create_box 1 box
create_atoms 1 single 0.05 0.0 0.0 units box
{line}"""


def zero_quaternion(workdir, z=-0.05):
    (workdir / "rods.data").write_text(DATA_FILE.format(z=z))
    return ROD_DECK.format(head=rod_system(), system="read_data rods.data",
                           contacts=rod_contacts(1e-6))


def set_spherocylinder(line):
    return ROD_DECK.format(head=rod_system(), system=CREATED_ROD.format(line=line),
                           contacts=rod_contacts(1e-6))


CASES = {
    "zero quaternion (error->one)":
        (lambda workdir: zero_quaternion(workdir),
         "Atoms section has a zero quaternion"),
    "contact length (error->one, mid-run)":
        (lambda workdir: jiang_deck("pair", properties=per_pair("rollingContactLength", 0.05)),
         "is larger than the diameter"),
    "axis random 1 (seed check, now error->all)":
        (lambda workdir: set_spherocylinder("set_spherocylinder all axis random 1"),
         "seed of 'axis random' must be a prime number > 10000"),
    "length < diameter (error->all)":
        (lambda workdir: set_spherocylinder("set_spherocylinder all diameter 0.01 length 0.005"),
         "'length' must be >= 'diameter'"),
}


@pytest.mark.parametrize("log_file", ["log.txt", None], ids=["with -log", "without -log"])
@pytest.mark.parametrize("case", sorted(CASES))
def test_the_error_reaches_the_output_file(tmp_path, liggghts_binary, case, log_file):
    make_deck, message = CASES[case]
    with pytest.raises(LiggghtsError):
        run_liggghts(make_deck(tmp_path), tmp_path, batch=True, log_file=log_file, timeout=120)
    out = (tmp_path / "out.txt").read_text(errors="replace")
    assert message in out, f"out.txt:\n{out}\nerr.txt:\n{(tmp_path / 'err.txt').read_text()}"
    log = tmp_path / (log_file or "log.liggghts")
    assert message in log.read_text(errors="replace")


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
@pytest.mark.parametrize("log_file", ["log.txt", None], ids=["with -log", "without -log"])
def test_an_error_on_another_rank_reaches_the_output_file(tmp_path, liggghts_binary, log_file):
    """Rank 1 owns the rod of z = 0.05 (2 ranks split the box along z);
    every rank's screen is stdout, so its message goes to out.txt."""
    with pytest.raises(LiggghtsError):
        run_liggghts(zero_quaternion(tmp_path, z=0.05), tmp_path, nprocs=2, batch=True,
                     log_file=log_file, timeout=120)
    out = (tmp_path / "out.txt").read_text(errors="replace")
    assert "ERROR on proc 1: atom_style spherocylinder: Atoms section has a zero quaternion" in out, out
