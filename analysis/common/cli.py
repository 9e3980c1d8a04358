"""The conventions of our command lines, in one place: the usage line is
a command that runs as written (`/usr/bin/python3 -m <module>`, the
Python that has numpy), and `--help` ends with an example.

Options across the command lines: `--out DIR` is always the directory a
command writes its tables and figures into; `--figure PNG` a single
figure; `--campaign DIR` the directory a driver keeps a campaign in (its
records, restarts and logs; a later call goes on from it). A length
carries its unit in its name (`--z-max-m`, `--z-max-D`) or in its help."""

import argparse

PYTHON = "/usr/bin/python3"


def command_line(module, description, example):
    """The argument parser of `python3 -m <module>`: its description
    printed as written, and `example` (a whole command) at the end of
    --help."""
    return argparse.ArgumentParser(prog=f"{PYTHON} -m {module}", description=description,
                                   epilog=f"example:\n  {example}",
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
