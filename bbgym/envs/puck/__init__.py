"""The puck: the template family (``docs/new-env.md``). ``task`` is the functional core,
``env`` the Gymnasium adapters, ``spec`` what it declares to the package."""

from bbgym.envs.puck.env import PuckEnv, PuckVectorEnv
from bbgym.envs.puck.spec import ENV_ID, SPEC
from bbgym.envs.puck.task import PuckParams, PuckState, PuckTask

__all__ = ["ENV_ID", "SPEC", "PuckEnv", "PuckParams", "PuckState", "PuckTask", "PuckVectorEnv"]
