"""A ball too light for the RK4 flights of Throw-v1, Curve-v2 and Topple-v2 (issue 51).

RK4 in steps of 0.05 s overshoots a light ball's quadratic drag: Topple-v2 with a
0.02 kg/m^2 shell ran to NaN (observations, rewards, ``wall_angle``), Throw-v1 threw the
same ball forward and had it land behind the thrower. Those versions keep their bits and
refuse such a ball, naming it and ``sim_dt``; at the bounds the error quotes, the worst
throw (the fastest, straight into the strongest wind) flies finite and slows down.
"""

from __future__ import annotations

import math
import re

import gymnasium as gym
import numpy as np
import pytest

import bbgym  # noqa: F401  (registers the ids)
from bbgym.envs.ball import GUST_HEADROOM_STDS, rk4_wind_limit_mps
from bbgym.physics.ball import BallParams, BallState
from bbgym.physics.flight_events import RK4_AIR_LIMIT, rk4_cubics, rk4_stable_air_speed_mps
from bbgym.physics.wind import GustParams

RK4_IDS = ["BeachballThrow-v1", "BeachballCurve-v2", "BeachballTopple-v2"]
LIGHT = {"shell_areal_density_kgm2": 0.02}


def quoted(message: str, name: str) -> float:
    """The bound an error message quotes for ``name`` (``name <= x`` or ``name >= x``)."""
    match = re.search(re.escape(name) + r" [<>]= ([0-9.e+-]+)", message)
    assert match, message
    return float(match.group(1))


def test_stable_air_speed_is_the_rk4_limit_of_drag_and_magnus_rates() -> None:
    ball = BallParams()
    speed = rk4_stable_air_speed_mps(ball, 0.05)
    # 2 h (c + w) at that speed is the limit: rho A (C_d + C_L,max) u / (2 m).
    coefficients = ball.drag_coefficient + ball.lift_coefficient_max
    rate = 1.2 * coefficients * ball.area_m2 * speed / (2 * ball.mass_kg)
    assert 2 * 0.05 * rate == pytest.approx(RK4_AIR_LIMIT, rel=1e-12)
    assert speed == pytest.approx(101.6, abs=0.1)  # the default ball: never near it
    vacuum = BallParams(drag_coefficient=0.0, lift_coefficient_max=0.0)
    assert rk4_stable_air_speed_mps(vacuum, 0.05) == math.inf
    # Half the step, twice the speed; a quarter of the mass, a quarter of it.
    assert rk4_stable_air_speed_mps(ball, 0.025) == pytest.approx(2 * speed, rel=1e-12)
    light = BallParams(shell_areal_density_kgm2=0.125)
    assert rk4_stable_air_speed_mps(light, 0.05) == pytest.approx(speed / 4, rel=1e-12)


def _one_step_speed(ball: BallParams, speed: float, spin: float = 0.0) -> float:
    """A ball moving horizontally at ``speed`` through still air, spinning about the
    vertical at ``spin``: its speed after one RK4 step of 0.05 s, gravity's part aside."""
    s = BallState(*([0.0] * 13))._replace(z=10.0, vx=speed, wz=spin, qw=1.0)
    cubics = rk4_cubics(ball, s, 0.0, 0.0, 0.05, np)
    vx, vy = sum(cubics[3]), sum(cubics[4])  # the cubics at theta = 1: the RK4 step
    return math.hypot(vx, vy)


def test_one_rk4_step_past_the_limit_overshoots_the_drag() -> None:
    """The reason for the limit: within it the drag slows the ball, forward; at twice the
    speed the step reverses it and speeds it up (no lift here: drag alone)."""
    ball = BallParams(shell_areal_density_kgm2=0.02, lift_coefficient_max=0.0)
    stable = rk4_stable_air_speed_mps(ball, 0.05)
    assert 0.0 < _one_step_speed(ball, stable) < stable
    assert _one_step_speed(ball, 2.0 * stable) > 2.0 * stable


def test_one_rk4_step_past_the_limit_overshoots_the_magnus_turn() -> None:
    """No drag, a saturated Magnus force (fast spin): within the limit the step turns the
    ball without speeding it up; at three times the speed it turns too far and speeds up
    (the 20 m/s winds that ran Topple-v1's and v2's light, high-lift balls to NaN)."""
    ball = BallParams(shell_areal_density_kgm2=0.02, drag_coefficient=0.0)
    stable = rk4_stable_air_speed_mps(ball, 0.05)
    spin = 500.0  # rad/s: r w / v of 2 to 6, where C_L has saturated
    assert _one_step_speed(ball, stable, spin) <= stable * (1 + 1e-9)
    assert _one_step_speed(ball, 3.0 * stable, spin) > 3.0 * stable * 1.5


@pytest.mark.parametrize("env_id", RK4_IDS)
def test_a_ball_too_light_for_the_step_is_refused_naming_it(env_id: str) -> None:
    with pytest.raises(ValueError, match=r"ball\.shell_areal_density_kgm2=0\.02 .*sim_dt"):
        gym.make(env_id, ball=LIGHT)
    with pytest.raises(ValueError, match=r"ball\.density_kgm3=10 "):
        solid = {"solid": True, "density_kgm3": 10.0, "radius_m": 0.02, "drag_coefficient": 2.0}
        gym.make(env_id, ball=solid)
    # The semi-implicit versions take it: their drag is implicit, stable at any rate.
    family_v0 = env_id.split("-")[0] + "-v0"
    gym.make(family_v0, ball=LIGHT).close()


@pytest.mark.parametrize("env_id", RK4_IDS)
@pytest.mark.parametrize("bound", ["sim_dt", "ball.shell_areal_density_kgm2"])
def test_at_the_quoted_bound_the_worst_throw_runs_finite_and_slows(env_id: str, bound: str) -> None:
    with pytest.raises(ValueError) as refused:
        gym.make(env_id, ball=LIGHT)
    value = quoted(str(refused.value), bound)
    if bound == "sim_dt":
        # Topple needs a step that divides its 0.25 s gust_dt: the next one below the bound.
        value = 0.25 / math.ceil(0.25 / value) if "Topple" in env_id else value
        kwargs = {"ball": LIGHT, "sim_dt": value}
        if "Throw" in env_id or "Curve" in env_id:
            kwargs["max_flight_time"] = 6.0
    else:
        kwargs = {"ball": {"shell_areal_density_kgm2": value * (1 + 1e-9)}}
    env = gym.make_vec(env_id, num_envs=2, **kwargs)
    task = env.unwrapped.task if hasattr(env, "unwrapped") else env.task
    # The strongest wind the range allows, blowing at the thrower (air moving to -x), and
    # the fastest throw straight into it, flat.
    wind = -task.wind_speed_range[1]
    obs, _ = env.reset(seed=3, options={"wind": (wind, 0.0)})
    action = np.tile(np.array([1.0, 0.0, 0.1, 0.0, 0.0, 0.0], np.float32), (2, 1))
    for t in range(3):
        obs, reward, terminated, truncated, info = env.step(action)
        assert np.isfinite(obs).all() and np.isfinite(reward).all()
        for key in ("trajectory", "ball_trajectory"):
            if key in info:
                trajectory = np.asarray(info[key], dtype=float)
                assert np.isfinite(trajectory).all()
                # Thrown at +x, the ball never flies backward past the thrower on its way
                # out (a light ball stops within metres and the wind brings it back, slowly).
                if t == 0:
                    assert (trajectory[:, 1, 0] > 0.0).all(), trajectory[:, :3]
    env.close()


@pytest.mark.parametrize("env_id", RK4_IDS)
def test_the_defaults_and_a_100_g_ball_are_accepted(env_id: str) -> None:
    env = gym.make(env_id)
    env.reset(seed=0, options={"wind": (-20.0, 0.0)})  # the strongest wind anyone takes
    env.close()
    gym.make(env_id, ball={"shell_areal_density_kgm2": 0.1 / (4 * math.pi * 0.2**2)}).close()


def test_a_reset_wind_beyond_the_steps_limit_is_refused_naming_the_option() -> None:
    ball = {"shell_areal_density_kgm2": 0.2}
    env = gym.make("BeachballTopple-v2", ball=ball)
    limit = env.unwrapped.task.wind_limit
    gusts = GustParams(speed_std=0.25)
    params = BallParams(**ball)
    assert limit == pytest.approx(rk4_wind_limit_mps(params, 0.05, 18.0, 60.0, 1.5, gusts))
    stable = rk4_stable_air_speed_mps(params, 0.05)
    fall = math.sqrt(2 * 9.81 * 1.5)  # from the launch height
    rolled = 0.4 * 0.2 * 60.0  # a shell's spin, rolling: k / (1 + k) r w with k = 2/3
    fastest = 18.0 + fall + rolled
    assert limit == pytest.approx((stable - fastest) / (1 + GUST_HEADROOM_STDS * 0.25))
    assert 3.0 < limit < 20.0
    env.reset(seed=0, options={"wind": (-limit * 0.999, 0.0)})
    with pytest.raises(ValueError, match=r"options\['wind'\]"):
        env.reset(seed=0, options={"wind": (-limit * 1.01, 0.0)})
    env.close()


def test_a_large_fast_spinning_ball_is_refused() -> None:
    """The configuration the long fuzz run found on Topple-v2: a 2.6 m shell spun at
    500 rad/s, heavy enough for its throw, rolled off at up to 260 m/s when friction
    caught its spin at the touchdown, and its next RK4 step ran to NaN."""
    ball = {"radius_m": 1.3, "shell_areal_density_kgm2": 0.28, "lift_coefficient_max": 0.45}
    with pytest.raises(ValueError, match=r"max_spin=500 .*Magnus"):
        gym.make("BeachballTopple-v2", ball=ball, max_spin=500.0, launch_height=2.6)
    gym.make("BeachballTopple-v2", ball=ball, max_spin=20.0, launch_height=2.6).close()


def test_a_light_high_lift_ball_in_a_gale_is_refused() -> None:
    """The configuration the long fuzz run found on Topple-v1 with ``rk4_events``: no drag,
    but a 3.3 m shell of 0.02 kg/m^2 with C_L up to 0.94 in a 20 m/s wind; its Magnus turn
    ran the flight to NaN."""
    ball = {
        "radius_m": 1.66,
        "shell_areal_density_kgm2": 0.02,
        "drag_coefficient": 0.0,
        "lift_coefficient_max": 0.94,
    }
    with pytest.raises(ValueError, match=r"ball\.shell_areal_density_kgm2=0\.02 .*Magnus"):
        gym.make(
            "BeachballTopple-v1",
            ball=ball,
            wind_speed_range=(13.6, 20.0),
            sim_dt=0.04,
            interval=2.96,
            gust_dt=2.8,
            interval_integrator="rk4_events",
            launch_height=4.47,
        )
