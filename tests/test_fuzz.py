"""Property-based fuzzing of the four envs through their public API (hypothesis).

Random valid constructor arguments (every physical constant over its whole accepted
interval, log-uniform, ends included), random reset options and random actions, on the
single env and the native vector env: observations inside the space, rewards and every
float in ``info`` finite, nothing raises. And every invalid number raises the right error
naming the argument. ``scripts/fuzz.py`` runs the same checks for 10^6 steps.
"""

from __future__ import annotations

import math
from dataclasses import fields

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bbgym.fuzz import (
    BAD_NUMBERS,
    check_episode,
    check_rejections,
    log_floor,
    numeric_arguments,
    sample_kwargs,
    sample_options,
)
from bbgym.physics.ball import BallParams
from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.validation import Interval
from bbgym.physics.wall import WallParams
from bbgym.physics.wind import GustParams
from bbgym.spec import base_ids

# CI explores the same examples every run (derandomize); scripts/fuzz.py explores anew.
FUZZ = settings(
    max_examples=40,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


def hypothesis_draw(data: st.DataObject):
    """A ``bbgym.fuzz.Draw`` that lets hypothesis choose (and shrink) every number."""

    def draw(name: str, accepted: Interval, log: bool) -> float:
        lo, hi = accepted.low, accepted.high
        ends = [v for v, open_ in ((lo, accepted.low_open), (hi, accepted.high_open)) if not open_]
        if log and hi > 0.0:
            inner = st.floats(math.log(log_floor(accepted)), math.log(hi)).map(math.exp)
        else:
            inner = st.floats(lo, hi, exclude_min=accepted.low_open, exclude_max=accepted.high_open)
        strategy = st.sampled_from(ends) | inner if ends else inner
        value = data.draw(strategy, label=name)
        value = min(max(value, lo), hi)
        return value if accepted.contains(value) else 0.5 * (lo + hi)

    return draw


@pytest.mark.parametrize("env_id", base_ids())
@pytest.mark.parametrize("num_envs", [0, 3], ids=["single", "vector"])
@FUZZ
@given(data=st.data(), seed=st.integers(0, 2**31 - 1))
def test_valid_inputs_run_finite(env_id, num_envs, data, seed):
    import gymnasium as gym

    draw = hypothesis_draw(data)
    kwargs = sample_kwargs(env_id, draw)
    probe = gym.make(env_id, **kwargs)
    options = sample_options(env_id, probe, draw)
    probe.close()
    steps = 40 if env_id == "BeachballSail-v0" else 6
    check_episode(env_id, kwargs, options, steps, seed, num_envs)


@pytest.mark.parametrize("env_id", base_ids())
def test_invalid_numbers_raise_naming_the_argument(env_id):
    names = numeric_arguments(env_id)
    assert check_rejections(env_id) == len(names) * len(BAD_NUMBERS)


@pytest.mark.parametrize("cls", [DinghyParams, BallParams, WallParams, GustParams])
def test_every_physical_constant_declares_its_interval(cls):
    """The fuzzers and the site's tables read the intervals: none may be missing."""
    for f in fields(cls):
        if isinstance(f.default, (int, float)) and not isinstance(f.default, bool):
            accepted = f.metadata.get("interval")
            assert accepted is not None, f"{cls.__name__}.{f.name} has no accepted interval"
            assert accepted.contains(f.default), f"{cls.__name__}.{f.name}: default outside"
