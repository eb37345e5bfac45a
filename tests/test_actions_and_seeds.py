"""What a step and a reset refuse, on every path (issue 51): a NaN or inf action raises
``ValueError`` on the torch backend too (it used to pass silently when given a tensor, and
the env's state stayed NaN), a complex action raises ``TypeError`` instead of losing its
imaginary part to a warning, and a seed or ``num_envs`` of the wrong type is refused naming
it. A refused step leaves the env where it was."""

from __future__ import annotations

import math
import warnings

import gymnasium as gym
import numpy as np
import pytest

import bbgym  # noqa: F401  (registers the ids)

ENV_ID = "BeachballSail-v2"
N = 4


def test_numpy_paths_refuse_complex_actions_as_a_type_error() -> None:
    single = gym.make(ENV_ID)
    single.reset(seed=0)
    vector = gym.make_vec(ENV_ID, num_envs=2)
    vector.reset(seed=0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no ComplexWarning on the way
        with pytest.raises(TypeError, match="action must be real"):
            single.step(np.array([0.5j, 0.0, 0.0]))
        with pytest.raises(TypeError, match="action must be real"):
            vector.step(np.zeros((2, 3), dtype=np.complex128))
    with pytest.raises(ValueError, match="action must be finite"):
        single.step(np.array([math.nan, 0.0, 0.0]))


@pytest.mark.parametrize("bad", [1.5, math.nan, True, "3", -1])
def test_a_seed_that_is_no_int_is_refused_naming_it(bad) -> None:
    error = ValueError if bad == -1 else TypeError
    with pytest.raises(error, match="seed must be an int >= 0"):
        gym.make(ENV_ID).reset(seed=bad)
    with pytest.raises(error, match="seed must be an int >= 0"):
        gym.make_vec(ENV_ID, num_envs=2).reset(seed=bad)
    with pytest.raises(error, match=r"seed\[1\] must be an int >= 0"):
        gym.make_vec(ENV_ID, num_envs=2).reset(seed=[0, bad])


def test_num_envs_refuses_a_bool() -> None:
    with pytest.raises(TypeError, match="num_envs must be an int >= 1, got True"):
        gym.make_vec(ENV_ID, num_envs=True)
    with pytest.raises(ValueError, match="num_envs must be an int >= 1, got 0"):
        gym.make_vec(ENV_ID, num_envs=0)


@pytest.mark.parametrize("output", ["torch", "numpy"])
def test_torch_backend_refuses_a_nan_tensor_and_keeps_its_state(output: str) -> None:
    torch = pytest.importorskip("torch")
    pytest.importorskip("array_api_compat")

    def make():
        env = gym.make_vec(ENV_ID, num_envs=N, backend="torch", output=output, compile=False)
        env.reset(seed=0)
        return env

    env, twin = make(), make()
    good = torch.zeros(N, 3, dtype=torch.float64)
    for bad_value in (math.nan, math.inf):
        bad = good.clone()
        bad[2, 1] = bad_value
        with pytest.raises(ValueError, match=r"actions must be finite: rows \[2\]"):
            env.step(bad)
    with pytest.raises(TypeError, match="actions must be real"):
        env.step(good.to(torch.complex64))
    with pytest.raises(ValueError, match=r"actions must have shape \(4, 3\)"):
        env.step(good[:2])
    # The refused steps changed nothing: the env goes on as its twin that never saw them.
    for _ in range(3):
        obs = env.step(good)[0]
        expected = twin.step(good)[0]
        assert np.array_equal(np.asarray(obs), np.asarray(expected))
        assert np.isfinite(np.asarray(obs)).all()


def test_torchrl_env_refuses_a_nan_action() -> None:
    torch = pytest.importorskip("torch")
    pytest.importorskip("torchrl")
    from bbgym.torchrl import BbgymTorchRLEnv

    env = BbgymTorchRLEnv(ENV_ID, N, compile_step=False, seed=0)
    td = env.reset()
    action = torch.zeros(env.action_spec.shape)
    action[1, 0] = math.nan
    td["action"] = action
    with pytest.raises(ValueError, match=r"actions must be finite: rows \[1\]"):
        env.step(td)
    td["action"] = torch.zeros(env.action_spec.shape)
    assert torch.isfinite(env.step(td)["next", "observation"]).all()
