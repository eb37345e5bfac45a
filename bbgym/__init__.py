"""bbgym: Gymnasium environments for sailing and beach-ball control on tested game physics.

Importing the package registers its environment ids with Gymnasium: each env family's
spec (:mod:`bbgym.spec`) registers its own.
"""

__version__ = "0.8.0"

import bbgym.envs  # noqa: E402, F401  (registers every family's ids)

__all__ = ["__version__"]
