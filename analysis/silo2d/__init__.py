"""The quasi-2D silo that clogs (Hidalgo et al. 2013): clogs (the analysis
of one run's clog records, the scene's command line, run as
`python3 -m analysis.silo2d`), scan (the friction scan), driver (running a
campaign in segments), picture (one arch drawn) and results (the page's
table)."""
