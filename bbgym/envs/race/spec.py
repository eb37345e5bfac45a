"""The race's spec: its PettingZoo and one-boat ids, classes, bench and recording (see
:class:`bbgym.spec.MultiAgentSpec`). Importing it imports neither PettingZoo nor the race's
modules: ``import bbgym`` registers the race through it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from bbgym.spec import AgentsEpisode, MultiAgentSpec


def _record(
    policy_name: str,
    *,
    seed: int,
    max_steps: int | None,
    model: Path | None,
    load_policy: Any,
) -> AgentsEpisode:
    from bbgym.envs.race.recording import recorded_race

    return recorded_race(
        policy_name, seed=seed, max_steps=max_steps, model=model, load_policy=load_policy
    )


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
    record=_record,
)
"""``pettingzoo.make("parallel", SPEC.env_id)``; ``gym.make(SPEC.one_agent_env_id)``."""
