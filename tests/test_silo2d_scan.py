"""analysis.silo2d.scan on hand-made records of two friction coefficients;
the expected numbers are worked out here by hand."""

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from analysis.silo2d import scan as silo2d_scan
from analysis.common.tables import read_table
from test_silo2d_analysis import write_feet, write_records, write_table

ROOT = Path(__file__).resolve().parent.parent


def test_paper_ratio_propagates_table1():
    # mu = 0.4: 35/20 = 1.75, relative errors 3/35 and 1/20 in quadrature
    ratio, error = silo2d_scan.paper_ratio(0.4)
    assert ratio == pytest.approx(1.75)
    assert error == pytest.approx(1.75 * ((3 / 35) ** 2 + (1 / 20) ** 2) ** 0.5)
    assert silo2d_scan.paper_ratio(0.3) is None


def test_phi_peak_is_the_centre_of_the_fullest_bin():
    assert silo2d_scan.phi_peak([151.0, 152.0, 159.9, 181.0]) == 155.0


def test_scan_table_of_two_runs(tmp_path):
    """Each run: one arch of 3 members (fn 300, 400, 500 N) with feet
    (200, 600 N), bulk contacts 100 and 300 N, m g = 10 N (write_records).
    members: eta 3, <f_n,a> 40 m g, <f_n,b> 20 m g, ratio 2.0, 1 defect of 3;
    outlet (the right foot, on its outlet grain alone): eta 4, <f_n,a>
    (300 + 400 + 500 + 600)/4 = 450 N = 45 m g, ratio 2.25, 2 defects of 4;
    feet: eta 5, <f_n,a> 40 m g, ratio 2.0, 2 defects of 5."""
    runs = []
    for mu in (0.4, 0.2):
        directory = tmp_path / f"mu{mu}"
        directory.mkdir()
        write_records(directory)
        write_feet(directory)
        silo = (directory / "silo.txt").read_text().replace("mu 0.4", f"mu {mu}")
        (directory / "silo.txt").write_text(silo)
        runs.append(directory)
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, "-m", "analysis.silo2d.scan", *map(str, runs),
                             "--out", str(out)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    lines = [line for line in (out / "scan_table.md").read_text().splitlines() if line.startswith("| 0.")]
    assert [line.split("|")[1:3] for line in lines] == \
        [[f" {mu} ", f" {reading} "] for mu in ("0.2", "0.4") for reading in ("members", "outlet", "feet")]
    members, outlet, feet = ([""] + line.split("|")[1:4] + line.split("|")[5:] for line in lines[3:])
    # surface: the 99th percentile of the heights of the C and I contacts,
    # 1.3 27 30 40 48 (x = 13 is W): 40 + 0.96 * (48 - 40) = 47.68, one clog
    assert lines[3].split("|")[4].strip() == "47.7 ± nan"
    assert members[3].strip() == "1" and members[5].strip().startswith("3 ")
    assert outlet[5].strip().startswith("4 ") and feet[5].strip().startswith("5 ")
    assert members[8].strip().startswith("0.333 ") and outlet[8].strip().startswith("0.500 ")
    assert feet[8].strip().startswith("0.400 ")
    assert members[9].strip().startswith("20.0 ") and members[10].strip().startswith("40.0 ")
    assert outlet[10].strip().startswith("45.0 ")
    assert members[11].strip().startswith("2.00 ") and outlet[11].strip().startswith("2.25 ")
    assert feet[11].strip().startswith("2.00 ")
    assert "20 ± 1, 35 ± 3, 1.75 ± 0.17" in lines[3]
    for name in ("eta_pdf", "phi_pdf", "force_vs_phi", "fn_profiles", "fn_pdf", "ft_pdf",
                 "mobilized_friction"):
        png = out / f"scan_{name}.png"
        assert png.exists() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name


def test_profile_sums_by_hand():
    """d = 1: contacts at (x, h) = (0, 0.5) 10 N, (0, 0.7) 30 N (C, bin 0-1),
    (5, 1.5) 20 N (I, bin 1-2), (13, 0.2) 40 N (W, bin 0-1)."""
    from analysis.silo2d import clogs as silo2d
    rows = silo2d.profile_sums([0.0, 0.0, 5.0, 13.0], [0.5, 0.7, 1.5, 0.2], [10.0, 30.0, 20.0, 40.0], 1.0)
    # (region, h_low, h_high, n, mean, sum of squared deviations): C 10, 30 -> 20, 200
    assert sorted(rows) == sorted([(0, 0.0, 1.0, 1, 40.0, 0.0), (1, 1.0, 2.0, 1, 20.0, 0.0),
                                   (2, 0.0, 1.0, 2, 20.0, 200.0)])
    table = {name: np.array([row[k] for row in rows]) for k, name in enumerate(silo2d.PROFILE_COLUMNS)}
    profiles = silo2d.profiles_from_sums(table)
    centres, mean, sem, count = profiles["C"]
    # C: 10 and 30 N -> mean 20, std (ddof 1) 14.142, sem 10
    assert centres.tolist() == [0.5] and mean.tolist() == [20.0] and count.tolist() == [2]
    assert sem[0] == pytest.approx(10.0)
    assert math.isnan(profiles["W"][2][0])          # one contact: no scatter


def test_an_archive_gives_the_scan_of_its_run(tmp_path):
    """A run of two clogs with contacts inside and outside the bulk window:
    its archive keeps only the bulk rows (compressed) and the profiles as
    sums, and the scan table and Fig. 4 data come out the same."""
    from analysis.silo2d import clogs as silo2d
    from analysis.campaign import silo2d_archive
    run = tmp_path / "run"
    run.mkdir()
    write_records(run)
    write_feet(run)
    rng = np.random.default_rng(3)
    rows = []
    for clog in (1,):
        for k in range(300):
            x, h = rng.uniform(-16, 16), rng.uniform(0, 80)
            rows.append((clog, k, k + 1000, x, h, rng.exponential(200.0), rng.exponential(30.0), 0))
    contacts = read_table(run / "contacts.txt")
    old = [tuple(contacts[c][k] for c in ("clog", "id1", "id2", "x", "z", "fn", "ft", "arch"))
           for k in range(contacts["clog"].size)]
    write_table(run / "contacts.txt", "clog id1 id2 x z fn ft arch", old + rows)
    total, kept = silo2d_archive.archive(run, tmp_path / "archive")
    all_contacts = read_table(run / "contacts.txt")
    in_bulk = silo2d.bulk_mask(all_contacts["x"], all_contacts["z"], 1.0)
    # and the contacts along the arches' walks (test_walk_contact_forces_by_hand)
    walks = silo2d.walk_pairs(read_table(run / "arches.txt"), read_table(run / "feet.txt"))
    on_walk = silo2d.walk_contact_mask(walks, all_contacts)
    keep = in_bulk | on_walk
    assert on_walk.sum() >= 1 and not np.any(in_bulk & on_walk)
    assert (total, kept) == (306, int(keep.sum())) and 0 < kept < total
    assert not (tmp_path / "archive" / "contacts.txt").exists()
    packed = read_table(tmp_path / "archive" / "contacts.txt.xz")
    np.testing.assert_allclose(packed["fn"], all_contacts["fn"][keep], rtol=5e-6)   # 6 digits
    np.testing.assert_allclose(packed["x"], all_contacts["x"][keep], rtol=5e-7)

    raw, archived = (silo2d_scan.load_run(path) for path in (run, tmp_path / "archive"))
    for reading in silo2d.READINGS:
        a = silo2d_scan.summarize(raw, reading, np.random.default_rng(5))
        b = silo2d_scan.summarize(archived, reading, np.random.default_rng(5))
        assert silo2d_scan.format_table([a]) == silo2d_scan.format_table([b])
    direct = silo2d.force_profiles(all_contacts["x"], all_contacts["z"], all_contacts["fn"], 1.0)
    summed = silo2d.profiles_from_sums(archived["profile_sums"])
    for region in ("W", "I", "C"):
        filled = direct[region][3] > 0
        np.testing.assert_allclose(summed[region][0], direct[region][0][filled])
        np.testing.assert_allclose(summed[region][1], direct[region][1][filled], rtol=1e-9)
        np.testing.assert_allclose(summed[region][2], direct[region][2][filled], rtol=1e-9)
        np.testing.assert_array_equal(summed[region][3], direct[region][3][filled])


def test_walk_contact_forces_by_hand():
    """One clog: feet 5 (on base grain 100) and 6 (on 101), members 10 and
    11 between them. The walk is 100-5-10-11-6-101; each grain's force is
    the mean of its two walk contacts, whatever its other contacts carry."""
    from analysis.silo2d import clogs as silo2d
    arches = {"clog": np.array([1, 1]), "order": np.array([1, 2]), "id": np.array([10, 11])}
    feet = {"clog": np.array([1, 1]), "order": np.array([0, 3]), "id": np.array([5, 6]),
            "base": np.array([100, 101])}
    contacts = {"clog": np.array([1, 1, 1, 1, 1, 1, 2]),
                "id1": np.array([5, 5, 10, 6, 6, 10, 10]),
                "id2": np.array([100, 10, 11, 11, 101, 12, 11]),
                "fn": np.array([10.0, 20.0, 30.0, 40.0, 50.0, 999.0, 777.0])}
    walks = silo2d.walk_pairs(arches, feet)
    assert walks == {1: {5: ((5, 100), (5, 10)), 10: ((5, 10), (10, 11)), 11: ((10, 11), (6, 11)),
                         6: ((6, 11), (6, 101))}}
    # the five contacts of the walk of clog 1, not 10-12 nor clog 2's 10-11
    np.testing.assert_array_equal(silo2d.walk_contact_mask(walks, contacts),
                                  [True, True, True, True, True, False, False])
    grains = {"clog": np.array([1, 1, 1, 1]), "id": np.array([5, 10, 11, 6])}
    np.testing.assert_allclose(silo2d.walk_contact_forces(grains, walks, contacts), [15, 25, 35, 45])
    # a clog without its walk, or a missing contact: NaN, not a wrong number
    missing = {k: np.delete(v, 2) for k, v in contacts.items()}      # 10-11 gone
    forces = silo2d.walk_contact_forces({"clog": np.array([1, 2]), "id": np.array([10, 10])}, walks, missing)
    assert np.isnan(forces).all()
