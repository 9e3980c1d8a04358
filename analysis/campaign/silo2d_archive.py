"""A compact copy of a clogging-silo run's records, for doc/data: everything
analysis.silo2d.scan needs, in a few per cent of the space.

contacts.txt holds every grain-grain contact of the silo at every clog
(about 4500 per clog in the paper's silo, 300 kB of text); of those the
analysis needs, per contact, only the contacts of the bulk window (Table 1,
the force PDFs, the mobilized friction: regions C and I, 27 < h/d < 48),
and for the normal-force profiles of Fig. 4 only sums per region and bin
of height. The archive keeps:

- clogs.txt, arches.txt, feet.txt, silo.txt, parameters.txt, segments.txt
  as they are (small);
- contacts.txt.xz: the rows of contacts.txt in the bulk window and the
  contacts along each arch's walk (silo2d.walk_pairs: feet, members and
  the feet's base grains; `silo2d_scan --arch-force walk`), with
  positions rounded to 7 significant digits and forces to 6, compressed
  with xz;
- surfaces.txt: per clog, the height of the free surface in d
  (analysis.silo2d.clogs.surface_heights, from all contacts);
- profiles.txt: per region and bin of h/d (width 1), the number of contacts,
  their mean f_n and the sum of squared deviations from it, over all clogs
  (analysis.silo2d.clogs.profile_sums).

analysis.silo2d.scan reads an archive as it reads a run directory and
gives the same table and figures (tests/test_silo2d_scan.py checks it).
The run's dumps and restart files (the driver's state<k>.restart) are not
kept: an archive is what doc/data holds of a finished run
(doc/data/README.md).

CLI:  python3 -m analysis.campaign.silo2d_archive RUN_DIR ARCHIVE_DIR
"""

import lzma
import shutil
import sys
from pathlib import Path

import numpy as np

from analysis.silo2d import clogs as silo2d
from analysis.common.tables import read_table
from analysis.common.cli import command_line

# contacts.txt's columns (clog id1 id2 x z fn ft arch), positions to 7
# significant digits (0.1 um in the paper's silo), forces to 6
CONTACT_ROW = "{:.0f} {:.0f} {:.0f} {:.7g} {:.7g} {:.6g} {:.6g} {:.0f}\n"
KEPT_AS_THEY_ARE = ("clogs.txt", "arches.txt", "feet.txt", "silo.txt", "parameters.txt",
                    "segments.txt")


def archive(run_dir, archive_dir, d=None):
    """Writes the archive of run_dir into archive_dir; returns
    (contacts in the run, contacts kept)."""
    run_dir, archive_dir = Path(run_dir), Path(archive_dir)
    archive_dir.mkdir(parents=True, exist_ok=True)
    for name in KEPT_AS_THEY_ARE:
        if (run_dir / name).exists():
            shutil.copyfile(run_dir / name, archive_dir / name)
    if d is None:
        silo = run_dir / "silo.txt"
        d = silo2d.read_silo(silo)["d"] if silo.exists() else 1.0 / 32
    contacts = read_table(run_dir / "contacts.txt")
    bulk = silo2d.bulk_mask(contacts["x"], contacts["z"], d)
    keep = bulk.copy()
    feet = silo2d.read_feet(run_dir)
    if feet is not None:
        walks = silo2d.walk_pairs(read_table(run_dir / "arches.txt"), feet)
        keep |= silo2d.walk_contact_mask(walks, contacts)
    columns = silo2d.REQUIRED_COLUMNS["contacts.txt"]
    with lzma.open(archive_dir / "contacts.txt.xz", "wt", preset=9) as packed:
        packed.write("# " + " ".join(columns) + "\n")
        for k in np.flatnonzero(keep):
            packed.write(CONTACT_ROW.format(*(contacts[c][k] for c in columns)))
    clogs, heights = silo2d.surface_heights(contacts["clog"], contacts["x"], contacts["z"], d)
    with open(archive_dir / "surfaces.txt", "w") as surfaces:
        surfaces.write("# clog surface\n")
        surfaces.writelines(f"{c:.0f} {h:.4f}\n" for c, h in zip(clogs, heights))
    sums = silo2d.profile_sums(contacts["x"], contacts["z"], contacts["fn"], d)
    with open(archive_dir / "profiles.txt", "w") as profiles:
        # region: 0 W, 1 I, 2 C; h in d; forces in N (the header line must come last)
        profiles.write("# " + " ".join(silo2d.PROFILE_COLUMNS) + "\n")
        for code, low, high, n, mean, deviations in sums:
            profiles.write(f"{code} {low:g} {high:g} {n} {mean:.12g} {deviations:.12g}\n")
    return int(np.size(contacts["fn"])), int(np.sum(keep))


def main(argv=None):
    parser = command_line("analysis.campaign.silo2d_archive", __doc__,
                          "/usr/bin/python3 -m analysis.campaign.silo2d_archive runs/silo2d_scan/mu0.4 "
                          "doc/data/silo2d_scan/mu0.4")
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("archive_dir", type=Path)
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    total, kept = archive(args.run_dir, args.archive_dir)
    print(f"silo2d_archive: {args.run_dir} -> {args.archive_dir}: {kept} of {total} contacts "
          f"kept (the bulk window and the arches' walks), profiles as sums", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
