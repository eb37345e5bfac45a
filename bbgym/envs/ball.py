"""What the ball tasks (throwing, curving, toppling) share: the accepted intervals of the
arguments every one of them takes (the ball, the throws, the wind, the launch, the step,
the reward weights), the gusts near the ground, and the fuzz samplers of those arguments.
"""

from __future__ import annotations

import math
from typing import Any

from bbgym.physics.ball import BallParams
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.validation import interval
from bbgym.physics.wind import GustParams

BALL_GUSTS = GustParams(
    speed_std=0.25, shift_std_rad=math.radians(15.0), time_constant_s=10.0, smoothing_s=2.0
)
"""Gusts near the ground: stronger and quicker than on open water."""

# Accepted intervals of the arguments and reset options every ball task takes.
THROWS_PER_EPISODE = interval(1, 100)
WIND_SPEED_MPS = interval(0.0, 20.0)
"""Mean wind near the ground: calm to a gale (beyond it nobody throws beach balls)."""
WINDSOCK_NOISE_MPS = interval(0.0, 10.0)
LAUNCH_SPEED_MPS = interval(0.0, 60.0, low_open=True)
"""Up to a hard-hit football; a beach ball's drag takes most of it within metres."""
LAUNCH_SPIN_RPS = interval(0.0, 500.0, low_open=True)
LAUNCH_HEIGHT_MAX_M = 20.0
BALL_SIM_DT_S = interval(1e-4, 0.05)
REWARD_WEIGHT = interval(0.0, 1000.0)


GUST_HEADROOM_STDS = 3.0
"""How many standard deviations of the gusts' speed the RK4 check allows above the mean
wind (the gusts are a smoothed Gaussian process: beyond 3 stds about 1 launch in 700)."""


def rk4_fastest_air_speed_mps(
    ball: BallParams,
    max_speed: float,
    max_spin: float,
    launch_height: float,
    wind_mps: float,
    gust_params: GustParams,
) -> float:
    """The fastest a thrown ball can meet the air: thrown at ``max_speed`` straight into
    the wind gusting :data:`GUST_HEADROOM_STDS` above ``wind_mps``, plus what a fall from
    ``launch_height`` adds, ``sqrt(2 g h)`` (gravity's work; drag only slows the ball
    against the air, the Magnus force turns it, a bounce gives back at most what it took),
    plus what its spin gives when friction on the ground makes it roll, ``k / (1 + k) r w``
    with ``k = I / (m r^2)`` (a shell's 2/3: 0.4 of ``r w``; seed §5, §6)."""
    gusting = 1.0 + GUST_HEADROOM_STDS * gust_params.speed_std
    k = ball.inertia_kgm2 / (ball.mass_kg * ball.radius_m**2)
    rolled = k / (1.0 + k) * ball.radius_m * max_spin
    fall = math.sqrt(2.0 * GRAVITY_MPS2 * launch_height)
    return max_speed + fall + rolled + wind_mps * gusting


def rk4_wind_limit_mps(
    ball: BallParams,
    sim_dt: float,
    max_speed: float,
    max_spin: float,
    launch_height: float,
    gust_params: GustParams,
) -> float:
    """The strongest mean wind a ball task flown in RK4 steps of ``sim_dt``
    (``rk4_events``) accepts: the fastest air speed of :func:`rk4_fastest_air_speed_mps`
    stays within the step's stable air speed
    (:func:`~bbgym.physics.flight_events.rk4_stable_air_speed_mps`). Negative where even a
    throw in calm air is too fast for the step; ``inf`` without drag or Magnus force."""
    from bbgym.physics.flight_events import rk4_stable_air_speed_mps

    stable = rk4_stable_air_speed_mps(ball, sim_dt)
    calm = rk4_fastest_air_speed_mps(ball, max_speed, max_spin, launch_height, 0.0, gust_params)
    return (stable - calm) / (1.0 + GUST_HEADROOM_STDS * gust_params.speed_std)


def check_rk4_ball(
    ball: BallParams,
    sim_dt: float,
    max_speed: float,
    max_spin: float,
    launch_height: float,
    wind_speed_range: tuple[float, float],
    gust_params: GustParams,
    integrator_arg: str,
) -> float:
    """Refuse a ball too light for RK4 steps of ``sim_dt`` at the task's fastest throw
    into its strongest wind (RK4 then overshoots the drag or the Magnus turn and the flight
    runs to NaN; :data:`~bbgym.physics.flight_events.RK4_AIR_LIMIT`). The error names the
    ball's mass field and ``sim_dt`` and says what each would have to be. Returns the
    strongest mean wind a ``reset`` option may pin (:func:`rk4_wind_limit_mps`)."""
    from bbgym.physics.flight_events import rk4_stable_air_speed_mps

    limit = rk4_wind_limit_mps(ball, sim_dt, max_speed, max_spin, launch_height, gust_params)
    wind_hi = wind_speed_range[1]
    if limit >= wind_hi:
        return limit
    mass_field = "ball.density_kgm3" if ball.solid else "ball.shell_areal_density_kgm2"
    mass_value = ball.density_kgm3 if ball.solid else ball.shell_areal_density_kgm2
    needed = rk4_fastest_air_speed_mps(
        ball, max_speed, max_spin, launch_height, wind_hi, gust_params
    )
    stable = rk4_stable_air_speed_mps(ball, sim_dt)
    # The stable speed scales as 1 / sim_dt and with the ball's mass (its density's field).
    scale = needed / stable
    raise ValueError(
        f"{mass_field}={mass_value:g} is too light for {integrator_arg}'s RK4 steps of "
        f"sim_dt={sim_dt:g} s: thrown at max_speed={max_speed:g} m/s with "
        f"max_spin={max_spin:g} rad/s from launch_height={launch_height:g} m into "
        f"wind_speed_range's {wind_hi:g} m/s "
        f"(gusts included) it may meet the air at {needed:.3g} m/s, and the step is stable "
        f"against this ball's drag and Magnus force only to {stable:.3g} m/s. Pass "
        f"sim_dt <= {_rounded(sim_dt / scale, math.floor)}, or {mass_field} >= "
        f"{_rounded(mass_value * scale, math.ceil)}, or a lower max_speed or "
        "wind_speed_range"
    )


def _rounded(value: float, direction: Any, digits: int = 3) -> str:
    """``value`` to ``digits`` significant digits, rounded by ``direction`` (``math.floor``
    for an upper bound, ``math.ceil`` for a lower one), so the bound an error quotes is
    itself accepted."""
    scale = 10.0 ** (digits - 1 - math.floor(math.log10(value)))
    return f"{direction(value * scale) / scale:.{digits}g}"


def rk4_task_wind_limit(task: Any, integrator_arg: str) -> float:
    """A ball task's ``wind_limit``: ``inf`` unless ``getattr(task, integrator_arg)`` is
    ``"rk4_events"``, else :func:`check_rk4_ball` of its checked ball, step, fastest throw,
    wind range and gusts (which refuses a ball too light for the step)."""
    if getattr(task, integrator_arg) != "rk4_events":
        return math.inf
    return check_rk4_ball(
        task.ball,
        task.sim_dt,
        task.max_speed,
        task.max_spin,
        task.launch_height,
        task.wind_speed_range,
        task.gust_params,
        f'{integrator_arg}="rk4_events"',
    )


def check_wind_option(path: str, value: Any, wind_limit: float) -> tuple[float, float]:
    """A ``reset`` option's wind vector: a pair whose length lies in
    :data:`WIND_SPEED_MPS` and, for RK4 flights, at most ``wind_limit``
    (:func:`check_rk4_ball`)."""
    from bbgym.physics.validation import check_norm, check_pair

    accepted = WIND_SPEED_MPS
    why = ""
    if wind_limit < accepted.high:
        accepted = interval(0.0, wind_limit)
        why = "the most this ball's RK4 steps are stable for, at the task's max_speed"
    return check_norm(path, check_pair(path, value), accepted, why=why)


def fit_rk4_ball(kwargs: dict[str, Any], integrator_arg: str) -> dict[str, Any]:
    """Drawn arguments of a ball task (the fuzzer's, every one present), with the ball made
    heavy enough for RK4 steps where ``kwargs[integrator_arg]`` is ``"rk4_events"``: its
    mass field raised a hair past the bound :func:`check_rk4_ball` sets, the rest kept."""
    from bbgym.physics.flight_events import rk4_stable_air_speed_mps

    if kwargs[integrator_arg] != "rk4_events":
        return kwargs
    ball = dict(kwargs["ball"])
    params = BallParams(**ball)
    gusts = GustParams(**kwargs["gust_params"])
    winds = kwargs["wind_speed_range"][1]
    speed, spin, height = kwargs["max_speed"], kwargs["max_spin"], kwargs["launch_height"]
    needed = rk4_fastest_air_speed_mps(params, speed, spin, height, winds, gusts)
    # The stable speed grows with the mass (the rest does not): past the bound, a hair.
    scale = needed / rk4_stable_air_speed_mps(params, kwargs["sim_dt"])
    if scale <= 1.0:
        return kwargs
    field = "density_kgm3" if params.solid else "shell_areal_density_kgm2"
    accepted = BallParams.__dataclass_fields__[field].metadata["interval"]
    ball[field] = min(getattr(params, field) * scale * 1.001, accepted.high)
    params = BallParams(**ball)
    # The heaviest ball still too light (a 4 m ball spun at 500 rad/s): less spin, then a
    # slower throw, for what the step takes.
    room = rk4_stable_air_speed_mps(params, kwargs["sim_dt"]) / 1.001 - needed
    if room < 0.0:
        rolled = rk4_fastest_air_speed_mps(params, 0.0, spin, 0.0, 0.0, gusts)
        spin *= max(rolled + room, 0.0) / rolled if rolled > 0.0 else 1.0
        room = min(0.0, rolled + room)
        speed = max(speed + room, 1e-3)
    fitted = {**kwargs, "ball": ball, "max_spin": max(spin, 1e-3), "max_speed": speed}
    if "wait_speed" in kwargs:  # Topple's: at most max_speed
        fitted["wait_speed"] = min(kwargs["wait_speed"], speed)
    return fitted


def sample_ball_kwargs(draw: Any) -> dict[str, Any]:
    """The arguments every ball task takes (the ball, the wind, the launch), drawn over
    their accepted intervals (``draw`` is a :data:`bbgym.fuzz.Draw`)."""
    from bbgym.fuzz.draws import draw_flag, draw_pair, sample_params

    ball = sample_params(draw, BallParams, "ball")
    radius = ball.get("radius_m", BallParams.radius_m)
    return {
        "ball": ball,
        "wind_speed_range": draw_pair(draw, "wind_speed_range", WIND_SPEED_MPS),
        "gusts": draw_flag(draw, "gusts"),
        "gust_params": sample_params(draw, GustParams, "gust_params"),
        "windsock_noise": draw("windsock_noise", WINDSOCK_NOISE_MPS, False),
        "max_speed": draw("max_speed", LAUNCH_SPEED_MPS, True),
        "max_spin": draw("max_spin", LAUNCH_SPIN_RPS, True),
        "launch_height": draw("launch_height", interval(radius, LAUNCH_HEIGHT_MAX_M), True),
    }


def sample_wind_option(options: dict[str, Any], draw: Any, wind_limit: float) -> None:
    """The reset options every ball task takes: ``gusts`` and ``wind``, each or not (a
    wind no stronger than the task's ``wind_limit``, :func:`check_wind_option`)."""
    from bbgym.fuzz.draws import draw_flag, draw_vector

    if draw_flag(draw, "options.has_gusts"):
        options["gusts"] = draw_flag(draw, "options['gusts']")
    if draw_flag(draw, "options.has_wind"):
        winds = interval(0.0, min(WIND_SPEED_MPS.high, wind_limit))
        options["wind"] = draw_vector(draw, "wind", winds)
