"""Gymnasium environments: one module per task, each with its single and vector env."""

from bbgym.envs.sail import BeachballSailEnv, BeachballSailVectorEnv
from bbgym.envs.throw import BeachballThrowEnv, BeachballThrowVectorEnv
from bbgym.envs.video import RecordFlightVideo

__all__ = [
    "BeachballSailEnv",
    "BeachballSailVectorEnv",
    "BeachballThrowEnv",
    "BeachballThrowVectorEnv",
    "RecordFlightVideo",
]
