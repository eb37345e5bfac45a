"""Gymnasium environments: one folder per env family, each with its spec.

Importing this package imports every family, and each family's ``spec`` module registers
its ids (:func:`bbgym.spec.register_spec`). A new family is a new folder here and one
name in the import below (``docs/new-env.md``).
"""

from bbgym.envs import sail, throw, topple
from bbgym.envs.video import RecordFlightVideo

FAMILIES = (sail, throw, topple)
"""The shipped families, in the order the command and the docs list them."""

__all__ = ["FAMILIES", "RecordFlightVideo"]
