"""silokit analysis toolkit: readers for LIGGGHTS output and records,
statistics and plots for the silokit scenes (numpy/scipy/matplotlib only).

    common/           what every scene shares: the reader of '#'-header
                      tables (tables), dump readers (lammps_io), coarse
                      graining, STL meshes, LIGGGHTS input blocks, the
                      command-line conventions (cli)
    silo2d/           the clogging quasi-2D silo   python3 -m analysis.silo2d
    pile2d/           the open 2D pile             python3 -m analysis.pile2d
    silo3d_rotating/  the silo with a rotating bottom
                                                   python3 -m analysis.silo3d_rotating
    campaign/         carrying runs between machines, archives, checkpoints
    results_tables    the results tables of the pages, from doc/data
    testing           the pytest helper for decks (doc/testing.md)
"""
