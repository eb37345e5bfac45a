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

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bbgym.fuzz import (
    BAD_ACTIONS,
    check_episode,
    log_floor,
    pin_version,
    sample_kwargs,
    sample_options,
)
from bbgym.fuzz.envs import _Stepper
from bbgym.physics.ball import BallParams
from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.validation import Interval
from bbgym.physics.wall import WallParams
from bbgym.physics.wind import GustParams
from bbgym.spec import base_ids, env_ids

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


# The base tasks draw every argument; a later version keeps what it pins (fewer draws).
VERSION_FUZZ = settings(FUZZ, max_examples=12)
TORCH_FUZZ = settings(FUZZ, max_examples=3)


def fuzz_one(env_id, num_envs, data, seed, backend="numpy"):
    import gymnasium as gym

    draw = hypothesis_draw(data)
    kwargs = sample_kwargs(env_id, draw)
    probe = gym.make(env_id, **kwargs)
    options = sample_options(env_id, probe, draw)
    probe.close()
    steps = 40 if "Sail" in env_id else 6
    steps = steps if backend == "numpy" else steps // 2
    check_episode(env_id, kwargs, options, steps, seed, num_envs, backend)


@pytest.mark.parametrize("env_id", base_ids())
@pytest.mark.parametrize("num_envs", [0, 3], ids=["single", "vector"])
@FUZZ
@given(data=st.data(), seed=st.integers(0, 2**31 - 1))
def test_valid_inputs_run_finite(env_id, num_envs, data, seed):
    fuzz_one(env_id, num_envs, data, seed)


@pytest.mark.parametrize("env_id", [e for e in env_ids() if e not in base_ids()])
@pytest.mark.parametrize("num_envs", [0, 3], ids=["single", "vector"])
@VERSION_FUZZ
@given(data=st.data(), seed=st.integers(0, 2**31 - 1))
def test_every_version_runs_finite_with_what_it_pins(env_id, num_envs, data, seed):
    fuzz_one(env_id, num_envs, data, seed)


@pytest.mark.parametrize("env_id", env_ids())
@pytest.mark.parametrize("backend", ["torch", "torchrl"])
@TORCH_FUZZ
@given(data=st.data(), seed=st.integers(0, 2**31 - 1))
def test_torch_paths_run_finite(env_id, backend, data, seed):
    pytest.importorskip(backend)
    pytest.importorskip("array_api_compat")
    fuzz_one(env_id, 3, data, seed, backend)


PATHS = [("numpy", 0), ("numpy", 2), ("torch", 2), ("torchrl", 2)]


@pytest.mark.parametrize("backend,num_envs", PATHS)
@pytest.mark.parametrize("name,value,error", BAD_ACTIONS, ids=[b[0] for b in BAD_ACTIONS])
def test_every_path_refuses_each_bad_action_and_goes_on(backend, num_envs, name, value, error):
    """A NaN, inf or complex entry raises on every path (the torch ones passed NaN on
    silently, issue 51), and the env then steps on as its twin that never saw it."""
    if backend != "numpy":
        pytest.importorskip(backend)
        pytest.importorskip("array_api_compat")
    env_id = "BeachballSail-v2"
    env, twin = (_Stepper(env_id, {}, num_envs, backend, 0) for _ in range(2))
    env.reset(0, None), twin.reset(0, None)
    action = np.full(env.shape, 0.25, np.float32)
    bad = action.astype(np.complex128 if isinstance(value, complex) else np.float64)
    bad.flat[-1] = value
    with pytest.raises(error):
        env.step(bad)
    for _ in range(2):
        assert np.array_equal(env.step(action)[0], twin.step(action)[0])
    env.close(), twin.close()


def test_pinning_keeps_a_versions_choices_and_takes_the_drawn_numbers():
    pinned = {"sim_dt": 0.05, "dinghy": {"rig": "sloop", "mass_kg": 70.0, "jib_area_m2": 1.0}}
    drawn = {"sim_dt": 0.01, "seed_x": 1, "dinghy": {"rig": "cat", "mass_kg": 150.0}}
    kwargs = pin_version(pinned, drawn)
    assert kwargs["sim_dt"] == 0.05 and kwargs["seed_x"] == 1
    assert kwargs["dinghy"] == {"rig": "sloop", "mass_kg": 150.0, "jib_area_m2": 1.0}


@pytest.mark.parametrize("cls", [DinghyParams, BallParams, WallParams, GustParams])
def test_every_physical_constant_declares_its_interval(cls):
    """The fuzzers and the site's tables read the intervals: none may be missing."""
    for f in fields(cls):
        if isinstance(f.default, (int, float)) and not isinstance(f.default, bool):
            accepted = f.metadata.get("interval")
            assert accepted is not None, f"{cls.__name__}.{f.name} has no accepted interval"
            assert accepted.contains(f.default), f"{cls.__name__}.{f.name}: default outside"
