"""``python -m eigenupdate``: the same command line as the ``eigenupdate`` script."""

import sys

from eigenupdate.cli import main

if __name__ == "__main__":
    sys.argv[0] = "eigenupdate"
    sys.exit(main())
