"""BeachballRace: a fleet of dinghies on one course (PettingZoo; the ``race`` extra).

    import pettingzoo
    import bbgym.envs.race  # registers bbgym/BeachballRace-v0 with PettingZoo (and
                            # bbgym/BeachballRaceSolo-v0 with Gymnasium)

    env = pettingzoo.make("parallel", "bbgym/BeachballRace-v0", num_boats=4)
    observations, infos = env.reset(seed=0)
    while env.agents:
        actions = {agent: env.action_space(agent).sample() for agent in env.agents}
        observations, rewards, terminations, truncations, infos = env.step(actions)

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

import gymnasium as gym
import pettingzoo

from bbgym.envs.race.env import ENV_ID, BeachballRaceEnv, env, parallel_env
from bbgym.envs.race.fleet import BeachballRaceFleetEnv
from bbgym.envs.race.match import BeachballRaceMatchEnv, play_matches
from bbgym.envs.race.solo import SOLO_ENV_ID, BeachballRaceSoloEnv

# Once per process (PettingZoo warns when an id is registered again).
if ENV_ID not in pettingzoo.parallel_registry:
    pettingzoo.register("parallel", ENV_ID, entry_point=parallel_env)
if ENV_ID not in pettingzoo.aec_registry:
    pettingzoo.register("aec", ENV_ID, entry_point=env)
if SOLO_ENV_ID not in gym.registry:
    gym.register(SOLO_ENV_ID, entry_point=BeachballRaceSoloEnv)

__all__ = [
    "ENV_ID", "SOLO_ENV_ID", "BeachballRaceEnv", "BeachballRaceFleetEnv", "BeachballRaceMatchEnv",
    "BeachballRaceSoloEnv", "env", "parallel_env", "play_matches",
]  # fmt: skip
