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

from bbgym.envs import register_race_pettingzoo
from bbgym.envs.race.env import ENV_ID, BeachballRaceEnv, env, parallel_env
from bbgym.envs.race.fleet import BeachballRaceFleetEnv
from bbgym.envs.race.match import BeachballRaceMatchEnv, play_matches
from bbgym.envs.race.solo import SOLO_ENV_ID, BeachballRaceSoloEnv

# ``import bbgym`` registered the ids (bbgym.envs) where PettingZoo is installed; env.py
# imports PettingZoo first, so where it is not, its ImportError names the extra's install.
register_race_pettingzoo()

__all__ = [
    "ENV_ID",
    "SOLO_ENV_ID",
    "BeachballRaceEnv",
    "BeachballRaceFleetEnv",
    "BeachballRaceMatchEnv",
    "BeachballRaceSoloEnv",
    "env",
    "parallel_env",
    "play_matches",
]
