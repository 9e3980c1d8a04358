"""The cylindrical silo with a rotating bottom (Pongó, Börzsönyi and
Hidalgo 2022): records (reading a run directory), flow (flow rate, fits),
fields (coarse-grained fields), analyse (the scene's command line, run as
`python3 -m analysis.silo3d_rotating`), maps, acceleration and
orifice_plug (their own command lines) and results (the page's table)."""
