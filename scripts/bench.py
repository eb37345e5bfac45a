"""Developer tool: the same as ``bbgym bench`` (see bbgym.cli.bench), runnable from a checkout."""

import sys

from bbgym.cli import script_main

if __name__ == "__main__":
    sys.exit(script_main("bench"))
