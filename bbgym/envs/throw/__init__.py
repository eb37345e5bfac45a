"""BeachballThrow and BeachballCurve: throw a beach ball into a target through the wind
(see :class:`BeachballThrowEnv`).

``task`` is the functional core, ``records`` the padded flight records, ``env`` the
Gymnasium adapters, ``scene`` and ``view`` the drawing, ``spec`` what the family declares
to the rest of the package.
"""

from bbgym.envs.throw.env import BeachballThrowEnv, BeachballThrowVectorEnv
from bbgym.envs.throw.spec import SPEC
from bbgym.envs.throw.task import ARGUMENT_TABLE, ThrowState, ThrowTask

__all__ = [
    "ARGUMENT_TABLE",
    "SPEC",
    "BeachballThrowEnv",
    "BeachballThrowVectorEnv",
    "ThrowState",
    "ThrowTask",
]
