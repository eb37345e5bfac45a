"""bbgym: Gymnasium environments for sailing and beach-ball control on tested game physics.

Importing the package registers its environment ids with Gymnasium.
"""

import math

from gymnasium.envs.registration import register, registry

__version__ = "0.8.0"

SAIL_MAX_EPISODE_STEPS = 1200
THROW_MAX_EPISODE_STEPS = 100
TOPPLE_MAX_EPISODE_STEPS = 100


def _register_versions(module: str, env_class: str, max_episode_steps: int,
                       versions: dict[str, dict]) -> None:  # fmt: skip
    """Register each ``id: kwargs`` of one env class (single and vector entry points)."""
    for env_id, kwargs in versions.items():
        if env_id not in registry:
            register(
                id=env_id,
                entry_point=f"bbgym.envs.{module}:{env_class}Env",
                vector_entry_point=f"bbgym.envs.{module}:{env_class}VectorEnv",
                max_episode_steps=max_episode_steps,
                kwargs=kwargs,
            )


# v1: time costs enough to race (bbgym.envs.sail, Version History): 0.1 a step, against 0.01,
# and a capsize 30, more than the discounted cost of the time left in any episode.
_SAIL_V1 = {"time_penalty": 0.1, "capsize_penalty": 30.0}
_register_versions("sail", "BeachballSail", SAIL_MAX_EPISODE_STEPS,
                   {"BeachballSail-v0": {}, "BeachballSail-v1": _SAIL_V1})  # fmt: skip

_CURVE = {"screen": True, "target_distance_range": (7.0, 10.0)}
# v1: the curves the planner can throw (bbgym.envs.throw, Version History): a mean wind of
# at most 2 m/s.
_CURVE_V1 = {**_CURVE, "wind_speed_range": (0.0, 2.0)}
_register_versions(
    "throw", "BeachballThrow", THROW_MAX_EPISODE_STEPS,
    {"BeachballThrow-v0": {}, "BeachballCurve-v0": _CURVE, "BeachballCurve-v1": _CURVE_V1},
)  # fmt: skip

# v1: the walls the planner can bring down (bbgym.envs.topple, Version History): nearer, in
# an onshore breeze (from behind the thrower: pi/2 .. 3 pi/2 counterclockwise from +x).
_TOPPLE_V1 = {"wall_distance_range": (3.0, 5.0), "wind_from_range": (0.5 * math.pi, 1.5 * math.pi)}
_register_versions("topple", "BeachballTopple", TOPPLE_MAX_EPISODE_STEPS,
                   {"BeachballTopple-v0": {}, "BeachballTopple-v1": _TOPPLE_V1})  # fmt: skip

__all__ = ["__version__"]
