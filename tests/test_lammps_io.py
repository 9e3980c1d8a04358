"""analysis.common.lammps_io.thermo_rows on hand-written screen output."""

from analysis.common.lammps_io import thermo_rows

OUTPUT = """\
Setting up run ...
Step Atoms f_a[1] f_a[2]
       0       10 0 0.5
fix a: a message inside the table
     100       12 1 0.25
WARNING: something
Loop time of 0.1 on 1 procs for 100 steps with 12 atoms
     150       99 9 9
Step Atoms f_a[1] f_a[2]
     100       12 1 0.25
     200       11 2 0.125 7
     300       11 3 0.0625
Loop time of 0.1 on 1 procs for 200 steps with 11 atoms
"""


def test_rows_of_every_table_message_lines_skipped_and_nothing_after_loop_time():
    rows = thermo_rows(OUTPUT, 4)
    assert rows == {0: [10, 0, 0.5], 100: [12, 1, 0.25], 300: [11, 3, 0.0625]}
