"""BeachballTopple: bring down a wall in gusty wind with beach balls (see
:class:`BeachballToppleEnv`).

``task`` is the functional core, ``records`` the padded samples of a step, ``env`` the
Gymnasium adapters, ``scene`` and ``view`` the drawing, ``spec`` what the family declares
to the rest of the package.
"""

from bbgym.envs.topple.env import BeachballToppleEnv, BeachballToppleVectorEnv
from bbgym.envs.topple.spec import SPEC
from bbgym.envs.topple.task import ARGUMENT_TABLE, ToppleState, ToppleTask

__all__ = [
    "ARGUMENT_TABLE",
    "SPEC",
    "BeachballToppleEnv",
    "BeachballToppleVectorEnv",
    "ToppleState",
    "ToppleTask",
]
