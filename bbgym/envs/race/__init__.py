"""BeachballRace: a fleet of dinghies on one course (PettingZoo; the ``race`` extra).

    import pettingzoo
    import bbgym  # registers bbgym/BeachballRace-v0 with PettingZoo
                  # and bbgym/BeachballRaceSolo-v0 with Gymnasium

    env = pettingzoo.make("parallel", "bbgym/BeachballRace-v0", num_boats=4)
    observations, infos = env.reset(seed=0)
    places = {}
    while env.agents:
        actions = {agent: env.action_space(agent).sample() for agent in env.agents}
        observations, rewards, terminations, truncations, infos = env.step(actions)
        places |= {agent: info["place"] for agent, info in infos.items()}  # each boat's last
    print(places)  # 0: did not finish (capsized or out of time; random actions seldom do)

``pettingzoo.make("aec", "bbgym/BeachballRace-v0")`` is the AEC form (boats act in turn);
:class:`BeachballRaceSoloEnv` a Gymnasium env of one boat against scripted racers
(``gym.make("bbgym/BeachballRaceSolo-v0")``);
:class:`BeachballRaceFleetEnv` many races at once as a Gymnasium vector env of every boat
(self-play with one shared policy); :class:`BeachballRaceMatchEnv` the learning boats of
many races against scripted racers, and :func:`play_matches` the pairings they win.
``parallel_env()`` and ``env()`` here make the same. The race's core
(:mod:`bbgym.envs.race.task`) and its course (:mod:`bbgym.envs.race.course`) need NumPy
alone.
"""

import importlib
from typing import Any

from bbgym.envs.race.spec import SPEC

_PLACES = {
    "ENV_ID": "parallel",
    "BeachballRaceEnv": "parallel",
    "env": "parallel",
    "parallel_env": "parallel",
    "BeachballRaceFleetEnv": "fleet",
    "BeachballRaceMatchEnv": "match",
    "play_matches": "match",
    "SOLO_ENV_ID": "solo",
    "BeachballRaceSoloEnv": "solo",
}
"""Where each public name lives. They load on first use (PEP 562): the spec, which
``import bbgym`` registers, needs no PettingZoo; the env modules import it first, so where
it is missing their ``ImportError`` names the extra's install."""


def __getattr__(name: str) -> Any:
    if name not in _PLACES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_PLACES[name]}"), name)


__all__ = ["SPEC", *_PLACES]
