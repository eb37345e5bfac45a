"""The toppling family's spec: BeachballTopple-v0 and -v1 (see :mod:`bbgym.spec`)."""

from __future__ import annotations

import math
from typing import Any

from bbgym.envs.throw.spec import ball_family_spec
from bbgym.envs.topple.task import ARGUMENT_TABLE
from bbgym.physics.ball import BallParams
from bbgym.physics.wall import WallParams
from bbgym.physics.wind import GustParams
from bbgym.spec import FuzzSpec, Version

# v1: the walls the planner can bring down: nearer, in an onshore breeze (from behind the
# thrower: pi/2 .. 3 pi/2 counterclockwise from +x).
ONSHORE = {"wall_distance_range": (3.0, 5.0), "wind_from_range": (0.5 * math.pi, 1.5 * math.pi)}
RK4_INTERVAL = {"interval_integrator": "rk4_events", "sim_dt": 0.05}
"""The interval of Topple-v2: RK4 steps of 0.05 s, the ball's bouncing touchdowns and its
hit on the wall located inside a step (:func:`bbgym.physics.toppling.event_bodies`)."""


def _scripted(env: Any) -> Any:
    from bbgym.agents.throw_agent import ToppleAgent

    return ToppleAgent()


def _planner(env: Any) -> Any:
    from bbgym.agents.planner import TopplePlanner

    return TopplePlanner(env)


def _outcome(env: Any, info: dict[str, Any], terminated: bool, truncated: bool) -> tuple:
    state = info.get("wall_state")
    if bool(info.get("is_success", False)):
        return "success: wall down" + (" (broke loose)" if state == "loose" else ""), True
    if terminated:
        if state == "fallen_toward":
            return "failed: wall fell toward you", False
        return "failed: out of throws, wall standing", False
    return "timed out", False


def _sample_kwargs(version: Version, draw: Any) -> dict[str, Any]:
    from bbgym.envs.ball import REWARD_WEIGHT, sample_ball_kwargs
    from bbgym.envs.topple import task
    from bbgym.fuzz.draws import COST_CAPS, draw_int, draw_pair, sample_params
    from bbgym.physics.validation import interval

    common = sample_ball_kwargs(draw)
    wall = sample_params(draw, WallParams, "wall")
    sim_dt = 0.01 * draw_int(draw, "sim_dt_centis", 1, 5)
    steps = COST_CAPS["topple_interval"]
    n_substeps = draw_int(
        draw, "interval_substeps", round(steps.low / sim_dt), round(steps.high / sim_dt)
    )
    gust_every = draw_int(draw, "gust_every", 1, n_substeps)
    distances = interval(
        0.5 * wall.get("base_depth_m", WallParams.base_depth_m) + 1.0, task.WALL_DISTANCE_MAX_M
    )
    max_speed = common["max_speed"]
    # A direction range spans at most one turn (2 pi), inside [-2 pi, 2 pi].
    from_low = draw("wind_from_range[0]", task.WIND_FROM_RAD, False)
    from_span = draw("wind_from_range span", interval(0.0, 2.0 * math.pi), False)
    return {
        **common,
        "wall": wall,
        "wind_from_range": (from_low, min(from_low + from_span, task.WIND_FROM_RAD.high)),
        "throws_per_episode": draw_int(draw, "throws_per_episode", 1, 10),
        "wall_distance_range": draw_pair(draw, "wall_distance_range", distances),
        "sim_dt": sim_dt,
        "interval_integrator": task.INTEGRATORS[
            draw_int(draw, "interval_integrator", 0, len(task.INTEGRATORS) - 1)
        ],
        "interval": n_substeps * sim_dt,
        "gust_dt": gust_every * sim_dt,
        "wait_speed": draw("wait_speed", interval(0.0, max_speed), False),
        **{
            name: draw(name, REWARD_WEIGHT, False)
            for name in ("success_bonus", "failure_penalty", "throw_cost", "lean_weight")
        },
    }


def _fit(kwargs: dict[str, Any]) -> dict[str, Any]:
    """A version's pinned step (Topple-v2's 0.05 s) dividing the drawn interval and gust
    step (each rounded to a whole number of steps, at least one), the wall's foot clear of
    the thrower at the pinned distances; then a ball heavy enough for RK4 steps."""
    from bbgym.envs.ball import fit_rk4_ball

    sim_dt = kwargs["sim_dt"]
    n_substeps = max(1, round(kwargs["interval"] / sim_dt))
    gust_every = min(n_substeps, max(1, round(kwargs["gust_dt"] / sim_dt)))
    wall = dict(kwargs["wall"])
    # The foot, half of base_depth_m, stands at least 1 m from the thrower.
    most_depth = 2.0 * (kwargs["wall_distance_range"][0] - 1.0)
    if wall.get("base_depth_m", WallParams.base_depth_m) > most_depth:
        wall["base_depth_m"] = most_depth
        wall["thickness_m"] = min(wall.get("thickness_m", WallParams.thickness_m), most_depth)
    kwargs = {
        **kwargs,
        "interval": n_substeps * sim_dt,
        "gust_dt": gust_every * sim_dt,
        "wall": wall,
    }
    return fit_rk4_ball(kwargs, "interval_integrator")


def _sample_options(topple_task: Any, draw: Any) -> dict[str, Any] | None:
    from bbgym.envs.ball import sample_wind_option
    from bbgym.fuzz.draws import draw_flag

    options: dict[str, Any] = {}
    sample_wind_option(options, draw, topple_task.wind_limit)
    if draw_flag(draw, "options.has_wall_distance"):
        options["wall_distance"] = draw(
            "options['wall_distance']", topple_task.wall_distance, False
        )
    return options or None


SPEC = ball_family_spec(
    "topple",
    (_scripted, _planner),
    summary="bring down a wall standing in gusty wind by throwing beach balls at it",
    versions=(
        Version(
            "BeachballTopple-v0",
            "the first version: walls 4-8 m away, wind from anywhere (half cannot be won)",
            preset="beachball_topple",
            base=True,
        ),
        Version(
            "BeachballTopple-v1",
            "walls 3-5 m away in an onshore breeze (the planner wins 100%)",
            kwargs=ONSHORE,
            preset="beachball_topple",
        ),
        Version(
            "BeachballTopple-v2",
            "Topple-v1 in RK4 steps of 0.05 s with the ball's bounces and hits located "
            "inside a step (faster, and closer to a fine integration)",
            kwargs={**ONSHORE, **RK4_INTERVAL},
            preset="beachball_topple",
        ),
    ),
    jax_params=("windsock_noise",),
    param_groups={"ball": BallParams, "wall": WallParams, "gust_params": GustParams},
    outcome=_outcome,
    argument_table=ARGUMENT_TABLE,
    fuzz=FuzzSpec(_sample_kwargs, _sample_options, step_share=0.2, episode_steps=8, fit=_fit),
)
