"""The throwing family's spec: BeachballThrow-v0 and BeachballCurve-v0/-v1 (see
:mod:`bbgym.spec`)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from bbgym.envs.ball import sample_ball_kwargs, sample_wind_option
from bbgym.envs.throw.task import ARGUMENT_TABLE
from bbgym.physics.ball import BallParams
from bbgym.physics.wind import GustParams
from bbgym.spec import EnvSpec, FuzzSpec, PolicyFactory, Version

MAX_EPISODE_STEPS = 100
CURVE = {"screen": True, "target_distance_range": (7.0, 10.0)}
"""BeachballCurve: a screen in the way and far targets, so only a curving throw scores."""
RK4_FLIGHT = {"flight_integrator": "rk4_events", "sim_dt": 0.05}
"""The flight of Throw-v1 and Curve-v2: RK4 steps of 0.05 s with the touchdown and the
screen hits located inside a step (:mod:`bbgym.physics.flight_events`)."""


def _scripted(env: Any) -> Any:
    from bbgym.agents.throw_agent import ThrowSolverAgent

    return ThrowSolverAgent(env.unwrapped.task)


def _planner(env: Any) -> Any:
    from bbgym.agents.planner import ThrowPlanner

    return ThrowPlanner(env)


def miss_direction(env: Any, info: dict[str, Any]) -> str:
    """Where the last throw missed its target: ``screen`` (it hit the screen), else the
    larger of its along-line error (``long`` / ``short``, along the line from the thrower
    to the target) and its cross-line error (``left`` / ``right``, seen from the thrower).
    Reads the target from the env's state (a report, not a policy input)."""
    if bool(info.get("hit_screen", False)):
        return "screen"
    k = int(info.get("trajectory_length", 0))
    if k == 0:
        return "no throw"
    land_x, land_y = (float(v) for v in np.asarray(info["trajectory"])[k - 1, :2])
    scenario = env.unwrapped.state.scenario
    target_x, target_y = float(scenario.target_x), float(scenario.target_y)
    distance = math.hypot(target_x, target_y)
    along_x, along_y = target_x / distance, target_y / distance
    long_error = land_x * along_x + land_y * along_y - distance
    left_error = along_x * land_y - along_y * land_x  # counterclockwise of the line
    if abs(long_error) >= abs(left_error):
        return "long" if long_error > 0 else "short"
    return "left" if left_error > 0 else "right"


def _outcome(env: Any, info: dict[str, Any], terminated: bool, truncated: bool) -> tuple:
    if bool(info.get("is_success", False)):
        return "success: hit", True
    if terminated:
        return f"missed {miss_direction(env, info)}", False
    return "timed out", False


def _keyboard(env: Any, seed: int | None) -> Any:
    from bbgym.envs.ball_keys import ThrowKeys

    return ThrowKeys(env, seed)


def ball_family_spec(
    family: str, policies: tuple[PolicyFactory, PolicyFactory], **fields: Any
) -> EnvSpec:
    """The spec of a beach-ball family (throw, topple): what both declare alike, their
    envs ``Beachball<Family>Env`` and ``Beachball<Family>VectorEnv``, a step a throw
    (launch velocity and spin), :data:`MAX_EPISODE_STEPS` of them, played by
    :class:`~bbgym.envs.ball_keys.ThrowKeys`.

    Args:
        family: The folder's name under ``bbgym/envs/`` (``"throw"``).
        policies: The family's scripted agent and planner.
        **fields: The family's own :class:`~bbgym.spec.EnvSpec` fields.

    Returns:
        The family's spec.
    """
    name = family.capitalize()
    scripted, planner = policies
    return EnvSpec(
        family=family,
        env_class=f"Beachball{name}Env",
        vector_env_class=f"Beachball{name}VectorEnv",
        max_episode_steps=MAX_EPISODE_STEPS,
        actions="launch velocity, spin",
        integer_arguments=("throws_per_episode",),
        policies={"scripted": scripted, "planner": planner},
        keyboard=_keyboard,
        step_unit="throws",
        **fields,
    )


def _sample_kwargs(version: Version, draw: Any) -> dict[str, Any]:
    from bbgym.envs.throw import task
    from bbgym.fuzz.draws import COST_CAPS, draw_flag, draw_int, draw_pair
    from bbgym.physics.validation import interval

    common = sample_ball_kwargs(draw)
    sim_dt = draw("sim_dt", COST_CAPS["ball_sim_dt"], True)
    target_radius = draw("target_radius", task.TARGET_RADIUS_M, True)
    field_radius = draw(
        "field_radius", interval(2.5 * target_radius, task.FIELD_RADIUS_M.high), True
    )
    targets = interval(target_radius, field_radius - target_radius, low_open=True, high_open=True)
    flight = COST_CAPS["max_flight_time"]
    return {
        **common,
        "throws_per_episode": draw_int(draw, "throws_per_episode", 1, 10),
        "target_radius": target_radius,
        "field_radius": field_radius,
        "target_distance_range": draw_pair(draw, "target_distance_range", targets, True),
        "target_bearing_range": draw_pair(draw, "target_bearing_range", task.BEARING_RAD),
        "throw_interval": draw("throw_interval", task.THROW_INTERVAL_S, True),
        # A version with the screen keeps it; the others draw it.
        "screen": bool(version.kwargs.get("screen")) or draw_flag(draw, "screen"),
        "screen_height": draw("screen_height", task.SCREEN_SIZE_M, True),
        "screen_half_width": draw("screen_half_width", task.SCREEN_SIZE_M, True),
        "screen_position": draw(
            "screen_position", interval(0.0, 1.0, low_open=True, high_open=True), False
        ),
        "flight_integrator": task.FLIGHT_INTEGRATORS[
            draw_int(draw, "flight_integrator", 0, len(task.FLIGHT_INTEGRATORS) - 1)
        ],
        "sim_dt": sim_dt,
        "max_flight_time": draw(
            "max_flight_time", interval(max(flight.low, 10 * sim_dt), flight.high), True
        ),
        "max_roll_time": draw("max_roll_time", flight, True),
        "miss_scale": draw("miss_scale", task.MISS_SCALE_M, True),
        "hit_bonus": draw("hit_bonus", task.REWARD_WEIGHT, False),
    }


def _fit(kwargs: dict[str, Any]) -> dict[str, Any]:
    """A version's pinned targets (Curve's 7-10 m) inside the drawn ring: the target no
    wider than the nearest target's distance allows, the field wide enough for the
    farthest; then a ball heavy enough for RK4 steps."""
    from bbgym.envs.ball import fit_rk4_ball

    near, far = kwargs["target_distance_range"]
    target_radius = kwargs["target_radius"]
    target_radius = target_radius if target_radius < near else 0.5 * near
    field_radius = kwargs["field_radius"]
    field_radius = field_radius if far < field_radius - target_radius else far + 2 * target_radius
    kwargs = {**kwargs, "target_radius": target_radius, "field_radius": field_radius}
    return fit_rk4_ball(kwargs, "flight_integrator")


def _sample_options(throw_task: Any, draw: Any) -> dict[str, Any] | None:
    from bbgym.fuzz.draws import draw_flag, draw_vector

    options: dict[str, Any] = {}
    sample_wind_option(options, draw, throw_task.wind_limit)
    if draw_flag(draw, "options.has_target"):
        options["target"] = draw_vector(draw, "target", throw_task.target_distance)
    if draw_flag(draw, "options.has_screen"):
        options["screen"] = draw_flag(draw, "options['screen']")
    return options or None


SPEC = ball_family_spec(
    "throw",
    (_scripted, _planner),
    summary="throw a beach ball through the wind into a target, several throws an episode "
    "(Curve: round a screen, so only a spinning throw scores)",
    versions=(
        Version(
            "BeachballThrow-v0",
            "the first version: a ring 3-10 m away",
            preset="beachball_throw",
            base=True,
        ),
        Version(
            "BeachballCurve-v0",
            "Throw-v0 with a screen in the way and targets 7-10 m out (5% cannot be won)",
            kwargs=CURVE,
            preset="beachball_throw",
            base=True,
        ),
        # v1: the curves the planner can throw: a mean wind of at most 2 m/s.
        Version(
            "BeachballCurve-v1",
            "Curve-v0 in a mean wind of at most 2 m/s (the planner wins 100%)",
            kwargs={**CURVE, "wind_speed_range": (0.0, 2.0)},
            preset="beachball_curve",
        ),
        Version(
            "BeachballThrow-v1",
            "Throw-v0 flown in RK4 steps of 0.05 s with the touchdown and screen hits "
            "located inside a step, to the first touchdown (several times faster)",
            kwargs=RK4_FLIGHT,
            preset="beachball_throw",
        ),
        Version(
            "BeachballCurve-v2",
            "Curve-v1 flown as Throw-v1",
            kwargs={**CURVE, "wind_speed_range": (0.0, 2.0), **RK4_FLIGHT},
            preset="beachball_curve_v2",
        ),
    ),
    jax_params=("gust_params.shift_std_rad", "windsock_noise"),
    param_groups={"ball": BallParams, "gust_params": GustParams},
    outcome=_outcome,
    argument_table=ARGUMENT_TABLE,
    fuzz=FuzzSpec(_sample_kwargs, _sample_options, step_share=0.2, episode_steps=12, fit=_fit),
)
