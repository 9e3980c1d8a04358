"""The two engines a campaign driver can run a deck in (DESIGN.md, "Two
hosts: one physics core"): LIGGGHTS ($SILOKIT_LIGGGHTS, default
build/bin/liggghts) with a scene's deck, or LAMMPS ($SILOKIT_LMP, default
build/bin/lmp) with the deck's twin `<deck>.lammps`, which loads our plugin
with `plugin load ${plugin}` ($SILOKIT_LAMMPS_PLUGIN when that is set,
else the deck's default). The decks of a scene take the same -var names and
write the same records, so a driver differs between hosts only in the
command line it builds; and a campaign holds one host's runs, since each
host reads only its own restart files (claim_host).

Used by analysis.pile2d.driver and analysis.silo2d.driver (--host).
"""

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HOSTS = ("liggghts", "lammps")
LIGGGHTS_BINARY = Path(os.environ.get("SILOKIT_LIGGGHTS", ROOT / "build" / "bin" / "liggghts"))
LAMMPS_BINARY = Path(os.environ.get("SILOKIT_LMP", ROOT / "build" / "bin" / "lmp"))


def deck_name(host, deck):
    """The deck file of a step ("in.build", "in.silo2d") in a host."""
    return deck + ".lammps" if host == "lammps" else deck


def engine_binary(host):
    """The engine a host runs (read at call time, so that a test can point
    the module's LIGGGHTS_BINARY / LAMMPS_BINARY elsewhere)."""
    return LAMMPS_BINARY if host == "lammps" else LIGGGHTS_BINARY


def engine_command(host, deck_path, variables, mpi=1, nice=0, binary=None, options=()):
    """The command line of one run of a deck in a host: `binary` (default
    engine_binary(host)), `-in deck -log none`, any further engine
    `options` (e.g. "-echo", "none"), then the variables; in LAMMPS the
    plugin from $SILOKIT_LAMMPS_PLUGIN unless a variable names it."""
    variables = dict(variables)
    if host == "lammps":
        plugin = os.environ.get("SILOKIT_LAMMPS_PLUGIN")
        if plugin and "plugin" not in variables:
            variables["plugin"] = plugin
    binary = engine_binary(host) if binary is None else binary
    # stdbuf: LIGGGHTS' Error::one prints without a flush before
    # MPI_Abort (doc/liggghts_quirks.md); line buffering keeps the message
    command = ["stdbuf", "-oL", str(binary), "-in", str(deck_path), "-log", "none", *options]
    for name, value in variables.items():
        command += ["-var", name, str(value)]
    if mpi > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(mpi)] + command
    if nice:
        command = ["nice", "-n", str(nice)] + command
    return command


def claim_host(out, host, has_runs=False):
    """Writes the campaign's host to OUT/host.txt, or raises ValueError
    when the campaign was run with the other host (its restart files are
    that host's, and its records would mix the two). has_runs: the
    campaign already holds runs; without host.txt they were made before
    --host existed, by LIGGGHTS, whose host is written first."""
    path = Path(out) / "host.txt"
    if has_runs and not path.exists():
        path.write_text("liggghts\n")
    if path.exists():
        recorded = path.read_text().strip()
        if recorded != host:
            raise ValueError(f"{out} is a {recorded} campaign (host.txt): run --host {recorded} "
                             f"there, or --host {host} in another --campaign")
    else:
        path.write_text(host + "\n")
