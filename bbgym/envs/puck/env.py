"""The puck's Gymnasium adapters: everything but the docstring comes from :mod:`bbgym.envs.core`."""

from __future__ import annotations

from bbgym.envs.core import CoreEnv, CoreVectorEnv
from bbgym.envs.puck.task import PuckTask


class PuckEnv(CoreEnv):
    """Blow a puck on an air table into a target circle with an air jet.

    The template family of ``docs/new-env.md``: a task core, these two adapters and a spec.

    ## Action Space

    ``Box(-1, 1, (2,), float32)``: the jet's velocity, x and y, as fractions of
    ``max_jet_speed_mps``.

    ## Observation Space

    ``Box(-1, 1, (4,), float32)``, clipped:

    | index | observation | scale |
    |---|---|---|
    | 0 | puck x, m (target at 0) | / 10 |
    | 1 | puck y, m | / 10 |
    | 2 | puck velocity x, m/s | / `max_jet_speed_mps` |
    | 3 | puck velocity y, m/s | / `max_jet_speed_mps` |

    ## Rewards

    +1 on the step the puck's centre enters the target circle, -0.01 on every other step.

    ## Starting State

    At rest, 2-4 m from the target in a uniformly drawn direction (``options['distance']``,
    1-10 m, pins the distance).

    ## Episode End

    Terminated when the puck is in the target circle; truncated after 200 steps.

    ## Arguments

    The fields of :class:`~bbgym.envs.puck.task.PuckParams`, each with its accepted interval
    (the table on the Validation page is generated from them).

    ## Info

    ``is_success`` (the puck is in the circle), ``distance_m`` (from the target).

    ## Version History

    - v0: the first version.
    """

    metadata = {"render_modes": [], "render_fps": 10}
    task_class = PuckTask


class PuckVectorEnv(CoreVectorEnv):
    """The native vector version of :class:`PuckEnv` (NumPy or compiled torch)."""

    metadata = {**CoreVectorEnv.metadata, "render_modes": []}
    task_class = PuckTask
