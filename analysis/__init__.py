"""silokit analysis toolkit: readers for LIGGGHTS output and records,
statistics and plots for the silokit scenes (numpy/scipy/matplotlib only)."""
