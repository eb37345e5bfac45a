"""An error about a constraint between two arguments names the one the user passed.

A derived limit (``gust_dt`` at most ``interval``, a mark beyond ``mark_radius``) used to be
reported in terms of the other argument alone: ``gym.make("BeachballTopple-v0",
interval=0.015)`` raised "gust_dt must be in (0, 0.015], got 0.25" though the user never
passed ``gust_dt``. Each message now names both arguments and the value of the one the
limit comes from.
"""

from __future__ import annotations

import gymnasium as gym
import pytest

import bbgym  # noqa: F401  (registers the ids)


@pytest.mark.parametrize(
    ("env_id", "kwargs", "named"),
    [
        ("BeachballTopple-v0", {"interval": 0.015}, ("interval = 0.015", "gust_dt")),
        (
            "BeachballTopple-v0",
            {"max_speed": 1.0, "wait_speed": 2.0},
            ("max_speed = 1", "wait_speed"),
        ),
        (
            "BeachballTopple-v1",
            {"wall": {"base_depth_m": 5.0}},
            ("wall.base_depth_m = 5", "wall_distance_range"),
        ),
        ("BeachballTopple-v0", {"ball": {"radius_m": 2.0}}, ("ball.radius_m = 2", "launch_height")),
        ("BeachballThrow-v0", {"ball": {"radius_m": 2.0}}, ("ball.radius_m = 2", "launch_height")),
        ("BeachballSail-v0", {"mark_radius": 50.0}, ("mark_radius = 50", "mark_distance_range")),
        ("BeachballThrow-v0", {"target_radius": 5.0}, ("target_radius = 5", "field_radius")),
        ("BeachballThrow-v0", {"field_radius": 6.0}, ("field_radius = 6", "target_radius")),
    ],
)
def test_a_derived_limit_names_the_argument_passed(env_id, kwargs, named):
    with pytest.raises(ValueError) as raised:
        gym.make(env_id, **kwargs)
    message = str(raised.value)
    for text in named:
        assert text in message, message
