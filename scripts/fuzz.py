"""Developer tool: the same as ``bbgym fuzz`` (see bbgym.cli.fuzz), runnable from a checkout."""

import sys

from bbgym.cli import script_main

if __name__ == "__main__":
    sys.exit(script_main("fuzz"))
