"""Fuzz every env through its public API for 10^6 steps (see :mod:`bbgym.fuzz`).

    python scripts/fuzz.py [--steps 1000000] [--seed 0] [--num-envs 32] [--minutes M]
                           [--out runs/fuzz]

Random valid constructor arguments (every physical constant over its whole accepted
interval), reset options and actions, on single and native vector envs; every
observation, reward and info float is checked, and every invalid number argument is
checked to raise the right error naming it. Writes ``fuzz.md`` and ``fuzz.json``; exits
with status 1 if anything failed, with what reproduces it.
"""

import sys

from bbgym.fuzz import main

if __name__ == "__main__":
    sys.exit(main())
