"""``python -m bbgym``: the same as the ``bbgym`` command."""

import sys

from bbgym.cli import main

if __name__ == "__main__":
    sys.exit(main())
