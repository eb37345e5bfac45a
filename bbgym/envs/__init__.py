"""Gymnasium environments: one folder per env family, each with its spec.

Importing this package imports the spec of every family of :data:`FAMILY_NAMES` and
registers it (:func:`bbgym.spec.register_spec`): a Gymnasium family's ids with their single
and vector entry points, and a family of many agents' (the race, PettingZoo's: the ``race``
extra) one-agent Gymnasium id and, where PettingZoo is installed, its parallel and AEC ids.
Entry points are module paths: a family's env modules load at ``make``. A new family is a
new folder here and its name in that tuple (``docs/new-env.md``); the template family,
:mod:`bbgym.envs.puck`, is in no tuple: it is the example, registered only by those who
check it.
"""

import importlib

from bbgym.envs.video import RecordFlightVideo
from bbgym.spec import register_spec

FAMILY_NAMES = ("sail", "throw", "topple", "race")
"""The shipped families, in the order the command and the docs list them: a new family
is its folder and its name here (``docs/new-env.md``)."""
SPECS = tuple(importlib.import_module(f"bbgym.envs.{name}.spec").SPEC for name in FAMILY_NAMES)
"""Their specs (:class:`bbgym.spec.EnvSpec`, or :class:`bbgym.spec.MultiAgentSpec` for
the race), each from its folder's ``spec.py``."""
for _spec in SPECS:
    register_spec(_spec)

__all__ = ["FAMILY_NAMES", "SPECS", "RecordFlightVideo"]
