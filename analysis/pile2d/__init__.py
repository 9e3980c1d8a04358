"""The open 2D pile with rolling resistance (Magalhaes et al. 2014):
discharges (the statistics of h against the orifice width, the scene's
command line, run as `python3 -m analysis.pile2d`), driver (running an
ensemble of piles and discharges), repose (pile shapes and run-on) and
results (the page's table)."""
