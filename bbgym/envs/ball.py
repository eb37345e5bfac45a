"""What the ball tasks (throwing, curving, toppling) share: the accepted intervals of the
arguments every one of them takes (the ball, the throws, the wind, the launch, the step,
the reward weights), the gusts near the ground, and the fuzz samplers of those arguments.
"""

from __future__ import annotations

import math
from typing import Any

from bbgym.physics.ball import BallParams
from bbgym.physics.validation import interval
from bbgym.physics.wind import GustParams

BALL_GUSTS = GustParams(speed_std=0.25, shift_std_rad=math.radians(15.0), time_constant_s=10.0,
                        smoothing_s=2.0)  # fmt: skip
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


def sample_ball_kwargs(draw: Any) -> dict[str, Any]:
    """The arguments every ball task takes (the ball, the wind, the launch), drawn over
    their accepted intervals (``draw`` is a :data:`bbgym.fuzz.Draw`)."""
    from bbgym.fuzz import draw_flag, draw_pair, sample_params

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


def sample_wind_option(options: dict[str, Any], draw: Any) -> None:
    """The reset options every ball task takes: ``gusts`` and ``wind``, each or not."""
    from bbgym.fuzz import draw_flag, draw_vector

    if draw_flag(draw, "options.has_gusts"):
        options["gusts"] = draw_flag(draw, "options['gusts']")
    if draw_flag(draw, "options.has_wind"):
        options["wind"] = draw_vector(draw, "wind", WIND_SPEED_MPS)
