"""bbgym: Gymnasium environments for sailing and beach-ball control on tested game physics.

Importing the package registers its environment ids with Gymnasium.
"""

import math

from gymnasium.envs.registration import register, registry

__version__ = "0.5.0"

SAIL_MAX_EPISODE_STEPS = 1200

if "BeachballSail-v0" not in registry:
    register(
        id="BeachballSail-v0",
        entry_point="bbgym.envs.sail:BeachballSailEnv",
        vector_entry_point="bbgym.envs.sail:BeachballSailVectorEnv",
        max_episode_steps=SAIL_MAX_EPISODE_STEPS,
    )

THROW_MAX_EPISODE_STEPS = 100

_CURVE = {"screen": True, "target_distance_range": (7.0, 10.0)}
# v1: the curves the planner can throw (bbgym.envs.throw, Version History): a mean wind of
# at most 2 m/s.
_CURVE_V1 = {**_CURVE, "wind_speed_range": (0.0, 2.0)}
for _id, _kwargs in (
    ("BeachballThrow-v0", {}),
    ("BeachballCurve-v0", _CURVE),
    ("BeachballCurve-v1", _CURVE_V1),
):
    if _id not in registry:
        register(
            id=_id,
            entry_point="bbgym.envs.throw:BeachballThrowEnv",
            vector_entry_point="bbgym.envs.throw:BeachballThrowVectorEnv",
            max_episode_steps=THROW_MAX_EPISODE_STEPS,
            kwargs=_kwargs,
        )

# v1: the walls the planner can bring down (bbgym.envs.topple, Version History): nearer, in
# an onshore breeze (from behind the thrower: pi/2 .. 3 pi/2 counterclockwise from +x).
_TOPPLE_V1 = {"wall_distance_range": (3.0, 5.0), "wind_from_range": (0.5 * math.pi, 1.5 * math.pi)}
for _id, _kwargs in (("BeachballTopple-v0", {}), ("BeachballTopple-v1", _TOPPLE_V1)):
    if _id not in registry:
        register(
            id=_id,
            entry_point="bbgym.envs.topple:BeachballToppleEnv",
            vector_entry_point="bbgym.envs.topple:BeachballToppleVectorEnv",
            max_episode_steps=100,
            kwargs=_kwargs,
        )

__all__ = ["__version__"]
