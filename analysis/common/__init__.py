"""Pieces every scene shares: the reader of `#`-header tables (tables),
the dump readers (lammps_io), coarse graining (coarse_grain), STL meshes
(stl) and LIGGGHTS input blocks (deck_blocks)."""
