"""Gymnasium environments: one folder per env family, each with its spec.

Importing this package imports every family of :data:`FAMILY_NAMES` and registers its
``SPEC`` (:func:`bbgym.spec.register_spec`). A new family is a new folder here and its
name in that tuple (``docs/new-env.md``); the template family, :mod:`bbgym.envs.puck`, is
in no tuple: it is the example, registered only by those who check it.

The race (:mod:`bbgym.envs.race`, PettingZoo's: the ``race`` extra) is no spec'd family;
its ids register here by module path (the race's modules load at ``make``), so that
``gym.make("bbgym/BeachballRaceSolo-v0")`` and ``pettingzoo.make("parallel",
"bbgym/BeachballRace-v0")`` work after ``import bbgym``.
"""

import importlib

import gymnasium as gym

from bbgym.envs.video import RecordFlightVideo
from bbgym.spec import register_spec

FAMILY_NAMES = ("sail", "throw", "topple")
"""The shipped families, in the order the command and the docs list them: a new family
is its folder and its name here (``docs/new-env.md``)."""
FAMILIES = tuple(importlib.import_module(f"bbgym.envs.{name}") for name in FAMILY_NAMES)
"""Their packages, each with its ``SPEC``."""
for _family in FAMILIES:
    register_spec(_family.SPEC)

RACE_ENV_ID = "bbgym/BeachballRace-v0"
"""The race's id in PettingZoo's registries (:data:`bbgym.envs.race.env.ENV_ID`)."""
RACE_SOLO_ENV_ID = "bbgym/BeachballRaceSolo-v0"
"""The race's one-boat Gymnasium id (:data:`bbgym.envs.race.solo.SOLO_ENV_ID`)."""


def register_race_pettingzoo() -> None:
    """Register the race (not a spec'd family: PettingZoo's, the ``race`` extra) in
    PettingZoo's parallel and AEC registries, once, by module path: PettingZoo imports
    :mod:`bbgym.envs.race` at ``pettingzoo.make``. Call it only where PettingZoo is
    importable."""
    import pettingzoo

    if RACE_ENV_ID not in pettingzoo.parallel_registry:
        pettingzoo.register("parallel", RACE_ENV_ID, entry_point="bbgym.envs.race:parallel_env")
    if RACE_ENV_ID not in pettingzoo.aec_registry:
        pettingzoo.register("aec", RACE_ENV_ID, entry_point="bbgym.envs.race:env")


def _register_race() -> None:
    """The race's ids at ``import bbgym``: the one-boat Gymnasium id by module path
    (``gym.make`` imports :mod:`bbgym.envs.race`, which raises an ``ImportError`` naming
    the ``race`` extra's install command where PettingZoo is missing) and, where PettingZoo
    is installed, its parallel and AEC ids (importing it takes about 40 ms after
    Gymnasium)."""
    if RACE_SOLO_ENV_ID not in gym.registry:
        gym.register(RACE_SOLO_ENV_ID, entry_point="bbgym.envs.race.solo:BeachballRaceSoloEnv")
    try:
        import pettingzoo  # noqa: F401  (the race extra)
    except ImportError:
        return
    register_race_pettingzoo()


_register_race()

__all__ = [
    "FAMILIES",
    "FAMILY_NAMES",
    "RACE_ENV_ID",
    "RACE_SOLO_ENV_ID",
    "RecordFlightVideo",
    "register_race_pettingzoo",
]
