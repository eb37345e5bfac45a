"""BeachballSail: sail a dinghy to a mark (see :class:`BeachballSailEnv`).

``task`` is the functional core, ``env`` the Gymnasium adapters, ``scene`` and ``view`` the
drawing, ``spec`` what the family declares to the rest of the package.
"""

from bbgym.envs.sail.env import BeachballSailEnv, BeachballSailVectorEnv
from bbgym.envs.sail.spec import SPEC
from bbgym.envs.sail.task import ARGUMENT_TABLE, SailState, SailTask

__all__ = [
    "ARGUMENT_TABLE",
    "SPEC",
    "BeachballSailEnv",
    "BeachballSailVectorEnv",
    "SailState",
    "SailTask",
]
