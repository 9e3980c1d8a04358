"""analysis.silo2d_scan on hand-made records of two friction coefficients;
the expected numbers are worked out here by hand."""

import subprocess
import sys
from pathlib import Path

import pytest

from analysis import silo2d_scan
from test_silo2d_analysis import write_feet, write_records

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
    result = subprocess.run([sys.executable, "-m", "analysis.silo2d_scan", *map(str, runs),
                             "--out", str(out)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    lines = [line for line in (out / "scan_table.md").read_text().splitlines() if line.startswith("| 0.")]
    assert [line.split("|")[1:3] for line in lines] == \
        [[f" {mu} ", f" {reading} "] for mu in ("0.2", "0.4") for reading in ("members", "outlet", "feet")]
    members, outlet, feet = (line.split("|") for line in lines[3:])
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
