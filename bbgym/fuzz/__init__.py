"""Fuzzing the envs through their public API: random valid arguments, options and actions.

Every accepted input must run finite, stay inside the observation space and raise nothing;
every rejected one must raise ``TypeError`` or ``ValueError`` naming the argument. One
sampler serves both the property-based tests (``tests/test_fuzz.py``, where hypothesis
draws each number, so a failure shrinks to a small example) and the long run of
``bbgym fuzz`` (a NumPy generator draws them):

* :func:`sample_kwargs` draws constructor arguments: every field of the physics parameter
  dataclasses over its whole accepted interval (log-uniform where the interval is
  positive, ends included), and the task's arguments within their intervals;
* :func:`sample_options` draws ``reset`` options within the same intervals;
* :func:`check_episode` steps a single env or a native vector env with random actions and
  checks every output; :func:`check_rejections` passes invalid values and checks the
  errors;
* a family of many agents (the PettingZoo race) brings its own sampler and checks, a
  :class:`bbgym.spec.MultiAgentFuzz` its spec names (the race's:
  :mod:`bbgym.envs.race.fuzz`, its parallel and AEC forms and its invalid numbers), built
  from the tools here (:func:`check_step`, :func:`bad_action`, :func:`finite_floats`);
* :func:`sample_scene_params` and :func:`check_scene` for the course's scenes
  (``bbgym.scenes``), on NumPy and torch.

The package's modules: :mod:`~bbgym.fuzz.draws` (the draw tools every family's sampler
uses; it imports no env), :mod:`~bbgym.fuzz.envs`, :mod:`~bbgym.fuzz.scenes` and
:mod:`~bbgym.fuzz.long_run`; their public names are here.

Step sizes and time limits are drawn from the slow end of their intervals only (a sim_dt
of 1e-4 s is accepted, but a fuzz run of a million steps at it would take days): the
:data:`COST_CAPS` say where; :data:`SCENE_MOST_BODIES` caps the scenes' counts alike.
:func:`run` is the long run, :func:`format_report` its tables.
"""

from __future__ import annotations

from bbgym.fuzz.draws import (  # noqa: F401
    COST_CAPS,
    Draw,
    draw_flag,
    draw_int,
    draw_pair,
    draw_vector,
    log_floor,
    numpy_draw,
    sample_params,
)
from bbgym.fuzz.envs import (  # noqa: F401
    BACKENDS,
    BAD_ACTION_RATE,
    BAD_ACTIONS,
    BAD_NUMBERS,
    bad_action,
    check_episode,
    check_refusals,
    check_rejections,
    check_step,
    finite_floats,
    numeric_arguments,
    pin_version,
    sample_kwargs,
    sample_options,
)
from bbgym.fuzz.long_run import (  # noqa: F401
    MULTI_AGENT_SHARE,
    SCENE_SHARE,
    format_report,
    installed_backends,
    run,
)
from bbgym.fuzz.scenes import (  # noqa: F401
    SCENE_BACKENDS,
    SCENE_GRID_SIDES,
    SCENE_MOST_BODIES,
    SCENE_NOT_COUNTS,
    SCENE_ORDERED,
    SCENE_SHARES,
    SCENE_STEPS,
    check_scene,
    installed_scene_backends,
    sample_scene_params,
    scene_count_caps,
)
