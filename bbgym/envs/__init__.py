"""Gymnasium environments: one module per task, each with its single and vector env."""

from bbgym.envs.sail import BeachballSailEnv, BeachballSailVectorEnv

__all__ = ["BeachballSailEnv", "BeachballSailVectorEnv"]
