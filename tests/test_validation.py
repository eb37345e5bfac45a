"""One validation layer for every argument: types, finiteness, intervals, ranges, options.

The regression cases of issue 10 (strings, NumPy scalars, one-element ranges, a string
read as a range, ranges that the matching reset option refuses) and the rules the site's
"Validation and errors" page (docs/pages/validation.md) states.
"""

from __future__ import annotations

import copy
import math
import pickle

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import bbgym  # noqa: F401
from bbgym.physics.validation import (
    Interval,
    build_params,
    check_number,
    check_range,
    interval,
)
from bbgym.physics.wind import GustParams
from bbgym.spec import base_ids

ENV_IDS = tuple(base_ids())
"""Every family's base tasks, from the registry (what fuzzing and ``bbgym bench`` cover)."""


def raises(error: type, match: str):
    """``pytest.raises`` matching the argument's name literally."""
    import re

    return pytest.raises(error, match=re.escape(match))


@pytest.mark.parametrize(
    "env_id, kwargs, error, name",
    [
        ("BeachballSail-v0", {"arrival_bonus": "10"}, TypeError, "arrival_bonus"),
        ("BeachballThrow-v0", {"hit_bonus": "5"}, TypeError, "hit_bonus"),
        ("BeachballTopple-v0", {"throw_cost": "0.2"}, TypeError, "throw_cost"),
        ("BeachballThrow-v0", {"windsock_noise": "0.3"}, TypeError, "windsock_noise"),
        (
            "BeachballSail-v0",
            {"gust_params": {"speed_std": "x"}},
            TypeError,
            "gust_params.speed_std",
        ),
        ("BeachballThrow-v0", {"target_bearing_range": (1.0,)}, ValueError, "target_bearing_range"),
        ("BeachballSail-v0", {"wind_speed_range": "37"}, TypeError, "wind_speed_range"),
        ("BeachballSail-v0", {"wind_speed_range": (7.0, 3.0)}, ValueError, "wind_speed_range"),
        ("BeachballSail-v0", {"wind_speed_range": (3.0, 99.0)}, ValueError, "wind_speed_range[1]"),
        (
            "BeachballTopple-v0",
            {"wall_distance_range": (0.1, 0.5)},
            ValueError,
            "wall_distance_range",
        ),
        (
            "BeachballThrow-v0",
            {"target_distance_range": (0.1, 0.5)},
            ValueError,
            "target_distance_range",
        ),
        ("BeachballThrow-v0", {"field_radius": 5.0}, ValueError, "field_radius"),
        ("BeachballSail-v0", {"dinghy": {"hull_mass": 1.0}}, TypeError, "hull_mass"),
        ("BeachballSail-v0", {"dinghy": {"mass_kg": -1.0}}, ValueError, "dinghy.mass_kg"),
        ("BeachballSail-v0", {"dinghy": {"mass_kg": True}}, TypeError, "dinghy.mass_kg"),
        ("BeachballSail-v0", {"dinghy": [("mass_kg", 1.0)]}, TypeError, "dinghy"),
        ("BeachballSail-v0", {"sail_model": "wing"}, ValueError, "sail_model"),
        ("BeachballSail-v1", {"dinghy": {"rig": "yawl"}}, ValueError, "dinghy.rig"),
        ("BeachballSail-v0", {"gusts": "yes"}, TypeError, "gusts"),
        ("BeachballSail-v0", {"ctrl_dt": 0.23}, ValueError, "ctrl_dt"),
        ("BeachballSail-v0", {"mark_radius": 50.0}, ValueError, "mark_distance_range"),
        ("BeachballThrow-v0", {"ball": {"colour": "red"}}, TypeError, "colour"),
        ("BeachballThrow-v0", {"ball": {"radius_m": -0.1}}, ValueError, "ball.radius_m"),
        ("BeachballThrow-v0", {"ball": {"solid": 1}}, TypeError, "ball.solid"),
        ("BeachballThrow-v0", {"throws_per_episode": 3.0}, TypeError, "throws_per_episode"),
        ("BeachballThrow-v0", {"throws_per_episode": 0}, ValueError, "throws_per_episode"),
        ("BeachballThrow-v0", {"screen_position": 1.0}, ValueError, "screen_position"),
        ("BeachballThrow-v0", {"launch_height": 0.1}, ValueError, "launch_height"),
        ("BeachballTopple-v0", {"wall": {"mass_kg": -1.0}}, ValueError, "wall.mass_kg"),
        ("BeachballTopple-v0", {"interval": 1.005}, ValueError, "interval"),
        ("BeachballTopple-v0", {"gust_dt": 10.0}, ValueError, "gust_dt"),
        ("BeachballTopple-v0", {"wait_speed": 30.0}, ValueError, "wait_speed"),
    ],
)
def test_bad_constructor_arguments_name_the_argument(env_id, kwargs, error, name):
    with raises(error, name):
        gym.make(env_id, **kwargs)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_unknown_keyword_raises_type_error_naming_it(env_id):
    with raises(TypeError, "no_such_argument"):
        gym.make(env_id, no_such_argument=1.0)
    with raises(TypeError, "no_such_option"):
        gym.make(env_id).reset(seed=0, options={"no_such_option": 1.0})
    with raises(TypeError, "options"):
        gym.make(env_id).reset(seed=0, options=[("gusts", False)])


@pytest.mark.parametrize(
    "env_id, options, error, name",
    [
        ("BeachballSail-v0", {"speed": 30.0}, ValueError, "options['speed']"),
        ("BeachballSail-v0", {"speed": -1.0}, ValueError, "options['speed']"),
        ("BeachballSail-v0", {"speed": "fast"}, TypeError, "options['speed']"),
        ("BeachballSail-v0", {"wind_speed": 500.0}, ValueError, "options['wind_speed']"),
        ("BeachballSail-v0", {"wind_from": math.nan}, ValueError, "options['wind_from']"),
        ("BeachballSail-v0", {"heading": 1e300}, ValueError, "options['heading']"),
        ("BeachballSail-v0", {"mark": (1.0, 0.0)}, ValueError, "options['mark']"),
        ("BeachballSail-v0", {"mark": (1.0,)}, ValueError, "options['mark']"),
        ("BeachballSail-v0", {"mark": "far"}, TypeError, "options['mark']"),
        ("BeachballSail-v0", {"gusts": 1}, TypeError, "options['gusts']"),
        ("BeachballThrow-v0", {"target": (0.1, 0.0)}, ValueError, "options['target']"),
        ("BeachballThrow-v0", {"target": (1e4, 0.0)}, ValueError, "options['target']"),
        ("BeachballThrow-v0", {"target": (math.inf, 0.0)}, ValueError, "options['target'][0]"),
        ("BeachballThrow-v0", {"wind": (30.0, 0.0)}, ValueError, "options['wind']"),
        ("BeachballThrow-v0", {"screen": "yes"}, TypeError, "options['screen']"),
        ("BeachballTopple-v0", {"wall_distance": 0.5}, ValueError, "options['wall_distance']"),
        ("BeachballTopple-v0", {"wind": (1.0, math.nan)}, ValueError, "options['wind'][1]"),
    ],
)
def test_bad_reset_options_name_the_option(env_id, options, error, name):
    with raises(error, name):
        gym.make(env_id).reset(seed=0, options=options)


def test_numpy_scalars_are_numbers():
    env = gym.make(
        "BeachballSail-v0",
        dinghy={"mass_kg": np.float32(150.0)},
        wind_speed_range=(np.int64(3), np.float64(7.0)),
        arrival_bonus=np.float32(10.0),
    )
    assert env.unwrapped.task.params.mass_kg == 150.0
    assert type(env.unwrapped.task.params.mass_kg) is float
    env.reset(seed=0, options={"speed": np.float32(1.0), "gusts": np.bool_(False)})
    gym.make("BeachballThrow-v0", throws_per_episode=np.int32(2)).reset(seed=0)


@pytest.mark.parametrize(
    "env_id, range_name, option, to_option",
    [
        ("BeachballSail-v0", "wind_speed_range", "wind_speed", float),
        ("BeachballSail-v0", "initial_speed_range", "speed", float),
        ("BeachballSail-v0", "mark_distance_range", "mark", lambda d: (0.0, d)),
        ("BeachballThrow-v0", "target_distance_range", "target", lambda d: (d, 0.0)),
        ("BeachballThrow-v0", "wind_speed_range", "wind", lambda s: (0.0, -s)),
        ("BeachballTopple-v0", "wall_distance_range", "wall_distance", float),
        ("BeachballTopple-v0", "wind_speed_range", "wind", lambda s: (s, 0.0)),
    ],
)
@settings(max_examples=25, deadline=None, derandomize=True)
@given(value=st.floats(-50.0, 6000.0))
def test_constructor_ranges_and_reset_options_agree(env_id, range_name, option, to_option, value):
    """A value is accepted as a range's end exactly when the matching option accepts it
    (a vector option by its length)."""
    assume(to_option is float or value >= 0.0)

    def accepted(call) -> bool:
        try:
            call()
        except ValueError:
            return False
        return True

    by_range = accepted(lambda: gym.make(env_id, **{range_name: (value, value)}))
    env = gym.make(env_id)
    by_option = accepted(lambda: env.reset(seed=0, options={option: to_option(value)}))
    assert by_range == by_option, (value, by_range, by_option)


def test_degenerate_but_meaningful_settings_run():
    """No Magnus lift, no drag, steady wind, plastic and elastic bounces, no friction."""
    cases = [
        ("BeachballThrow-v0", {"ball": {"lift_coefficient_max": 0.0}}),
        ("BeachballThrow-v0", {"ball": {"drag_coefficient": 0.0}}),
        ("BeachballThrow-v0", {"ball": {"restitution": 0.0, "friction": 0.0}}),
        ("BeachballThrow-v0", {"ball": {"restitution": 1.0, "rolling_resistance": 0.0}}),
        ("BeachballCurve-v0", {"gust_params": {"speed_std": 0.0, "shift_std_rad": 0.0}}),
        ("BeachballSail-v0", {"gust_params": {"speed_std": 0.0, "shift_std_rad": 0.0}}),
        ("BeachballSail-v0", {"wind_speed_range": (0.0, 0.0), "initial_speed_range": (0, 0)}),
        ("BeachballTopple-v0", {"ball": {"lift_coefficient_max": 0.0}, "windsock_noise": 0}),
    ]
    for env_id, kwargs in cases:
        env = gym.make(env_id, **kwargs)
        env.action_space.seed(0)
        obs, _ = env.reset(seed=0)
        for _ in range(5):
            obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
            assert np.isfinite(obs).all() and math.isfinite(reward), (env_id, kwargs)
            if terminated or truncated:
                env.reset()


def test_validation_helpers():
    assert check_number("x", np.float32(2.5)) == 2.5
    assert check_range("r", [1, 2], interval(0, 3)) == (1.0, 2.0)
    with raises(ValueError, "r[1]"):
        check_range("r", (1.0, 4.0), interval(0, 3))
    with raises(TypeError, "x"):
        check_number("x", np.array([1.0, 2.0]))
    assert str(Interval(0.0, 1.0, low_open=True)) == "(0, 1]"
    assert str(interval(0.0, math.inf)) == "[0, inf)"
    with raises(TypeError, "gust_params got an unexpected key 'gust'"):
        build_params(GustParams, "gust_params", {"gust": 1.0})
    with raises(ValueError, "gust_params.speed_std"):
        build_params(GustParams, "gust_params", {"speed_std": 2.0})
    with raises(ValueError, "GustParams.smoothing_s"):
        GustParams(smoothing_s=0.0)


@pytest.mark.parametrize("env_id", ENV_IDS)
@pytest.mark.parametrize("copier", [copy.deepcopy, lambda v: pickle.loads(pickle.dumps(v))])
def test_vector_envs_pickle_and_continue_identically(env_id, copier):
    vec = gym.make_vec(env_id, num_envs=3, render_mode="rgb_array")
    vec.reset(seed=5)
    rng = np.random.default_rng(0)
    shape = (3, *vec.single_action_space.shape)
    vec.step(rng.uniform(-1, 1, shape).astype(np.float32))
    vec.render()  # a renderer with pygame surfaces exists now: it must not be copied
    twin = copier(vec)
    for _ in range(4):
        action = rng.uniform(-1, 1, shape).astype(np.float32)
        a, b = vec.step(action), twin.step(action)
        for x, y in zip(a[:4], b[:4], strict=True):
            np.testing.assert_array_equal(x, y)
        np.testing.assert_array_equal(a[4]["is_success"], b[4]["is_success"])
    assert twin.render()[0].shape == vec.render()[0].shape


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_single_envs_pickle_and_continue_identically(env_id):
    env = gym.make(env_id)
    env.reset(seed=2)
    env.action_space.seed(1)
    action = env.action_space.sample()
    twin = pickle.loads(pickle.dumps(env))
    np.testing.assert_array_equal(env.step(action)[0], twin.step(action)[0])


def expected_interval_rows() -> list[tuple[str, str]]:
    """The rows the site's "Validation and errors" page must show, as (start, end) of a
    table line, taken from the code: every env module's ``ARGUMENT_TABLE`` row and every
    parameter field that declares an interval (read from the dataclass fields here, not
    through the page's own generator)."""
    from dataclasses import fields

    from bbgym.envs import sail, throw, topple
    from bbgym.physics.ball import BallParams
    from bbgym.physics.dinghy import DinghyParams
    from bbgym.physics.wall import WallParams

    rows = [
        (f"| {names} |", f" {accepted} |")
        for m in (sail, throw, topple)
        for names, accepted in m.ARGUMENT_TABLE
    ]
    groups = (
        (DinghyParams, "dinghy"),
        (GustParams, "gust_params"),
        (BallParams, "ball"),
        (WallParams, "wall"),
    )
    for cls, group in groups:
        rows += [
            (f"| `{group}.{f.name}` |", f" {f.metadata['interval']} |")  # default between
            for f in fields(cls)
            if f.metadata.get("interval") is not None
        ]
    return rows


def missing_interval_rows(page: str) -> list[str]:
    lines = page.splitlines()
    return [
        start + " ..." + end
        for start, end in expected_interval_rows()
        if not any(line.startswith(start) and line.endswith(end) for line in lines)
    ]


def validation_page() -> str:
    """docs/pages/validation.md as the site shows it: its tables written from the code by
    ``python docs/tables.py write`` (expanded again here, so a stale page fails too)."""
    import importlib.util
    from pathlib import Path

    docs = Path(__file__).resolve().parent.parent / "docs"
    spec = importlib.util.spec_from_file_location("bbgym_docs_tables", docs / "tables.py")
    tables = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tables)
    return tables.expand((docs / "pages" / "validation.md").read_text(encoding="utf-8"))


def test_the_site_lists_every_accepted_interval():
    """The "Validation and errors" page shows the code's intervals, every one of them."""
    page = validation_page()
    assert not missing_interval_rows(page), missing_interval_rows(page)
    assert page.count("<!-- table:") == page.count("<!-- /table -->")  # every table written


def test_a_missing_interval_row_is_noticed():
    """The check above can fail: drop one argument row or one field row from the page."""
    page = validation_page().splitlines()
    for dropped in ("| `sim_dt` |", "| `ball.restitution` |", "| `throws_per_episode` |"):
        kept = "\n".join(line for line in page if not line.startswith(dropped))
        assert missing_interval_rows(kept), dropped
    wrong = "\n".join(
        line.replace("| [0, 1] |", "| [0, 2] |")
        if line.startswith("| `ball.restitution`")
        else line
        for line in page
    )
    assert missing_interval_rows(wrong)
