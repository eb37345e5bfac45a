"""The race's spec: its PettingZoo and one-boat ids, classes, bench and recording (see
:class:`bbgym.spec.MultiAgentSpec`). Importing it imports neither PettingZoo nor the race's
modules: ``import bbgym`` registers the race through it."""

from __future__ import annotations

from bbgym.envs.race.task import ARGUMENT_TABLE
from bbgym.physics.shadow import ShadowParams
from bbgym.spec import MultiAgentSpec

SPEC = MultiAgentSpec(
    family="race",
    env_id="bbgym/BeachballRace-v0",
    summary="a fleet of dinghies racing round a course, with right of way (PettingZoo)",
    extra="race",
    one_agent_env_id="bbgym/BeachballRaceSolo-v0",
    one_agent_env_class="BeachballRaceSoloEnv",
    vector_env_classes=("BeachballRaceFleetEnv", "BeachballRaceMatchEnv"),
    agents=4,
    agents_argument="num_boats",
    agent_name="boat",
    episode_name="race",
    policies=("scripted", "random", "ppo"),
    argument_table=ARGUMENT_TABLE,
    param_groups={"shadow_params": ShadowParams},
    fuzz="fuzz:FUZZ",
    record="recording:recorded_race",
)
"""``pettingzoo.make("parallel", SPEC.env_id)``; ``gym.make(SPEC.one_agent_env_id)``."""
