"""The puck's spec: what the family declares to the rest of the package (see
:mod:`bbgym.spec`). Registering it (``register_spec(SPEC)``, which ``bbgym.envs`` does for
each shipped family) is all it takes for ``gym.make``, the vector envs, ``bbgym``'s
commands, the fuzzer and :mod:`bbgym.testing` to serve it."""

from __future__ import annotations

from typing import Any

import numpy as np

from bbgym.envs.puck.task import START_DISTANCE_M, PuckParams
from bbgym.physics.validation import accepted_interval
from bbgym.spec import EnvSpec, FuzzSpec, Version

ENV_ID = "BeachballPuck-v0"


def _scripted(env: Any) -> Any:
    """Aim the jet at the target, easing off as the puck nears it (a PD law on the
    observation)."""

    def policy(obs: np.ndarray) -> np.ndarray:
        aim = -(3.0 * obs[..., :2] + 0.5 * obs[..., 2:])
        return np.clip(aim, -1.0, 1.0).astype(np.float32)

    return policy


def _sample_kwargs(version: Version, draw: Any) -> dict[str, Any]:
    return {name: draw(name, accepted_interval(PuckParams, name), True) for name in FIELDS}


def _sample_options(task: Any, draw: Any) -> dict[str, Any] | None:
    return {"distance": draw("options['distance']", START_DISTANCE_M, False)}


FIELDS = tuple(PuckParams.__dataclass_fields__)

SPEC = EnvSpec(
    family="puck",
    env_class="PuckEnv",
    vector_env_class="PuckVectorEnv",
    max_episode_steps=200,
    summary="blow a puck into a target circle with an air jet (the template family)",
    actions="jet velocity x, y",
    versions=(Version(ENV_ID, "the first version", base=True),),
    policies={"scripted": _scripted},
    fuzz=FuzzSpec(_sample_kwargs, _sample_options, episode_steps=30),
)
