"""bbgym's envs as TorchRL environments (the ``torchrl`` extra): TorchRL's spec check on
every family, the same steps as the native vector env on the torch backend, resets between
steps (no step spent on an autoreset), determinism under a seed, a collector, and errors
that name the argument."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

torch = pytest.importorskip("torch")
pytest.importorskip("torchrl")
pytest.importorskip("array_api_compat")

from torchrl.envs.utils import check_env_specs  # noqa: E402

from bbgym.spec import newest_ids, spec_of, specs  # noqa: E402
from bbgym.torchrl import BbgymTorchRLEnv  # noqa: E402

N = 4
QUICK_THROWS = {"sim_dt": 0.05, "max_flight_time": 2.0, "max_roll_time": 0.25}
SETTINGS = {
    "sail": {"max_episode_steps": 20},
    "throw": {"max_episode_steps": 2, **QUICK_THROWS},
    "topple": {"max_episode_steps": 2},
}
"""Arguments by family (``EnvSpec.family``): a few steps an episode, quick throws; a family
not named here runs with its registered arguments."""
ENV_IDS = newest_ids()
"""The newest version of every task in the registry."""


def base(family: str) -> str:
    """A family's first base task (``Version.base``): the tests of one env use it."""
    return next(v.env_id for s in specs() if s.family == family for v in s.versions if v.base)


SAIL, THROW = base("sail"), base("throw")


def make(env_id: str, seed: int | None = 0, **kwargs) -> BbgymTorchRLEnv:
    kwargs = {**SETTINGS.get(spec_of(env_id).family, {}), **kwargs}
    return BbgymTorchRLEnv(env_id, N, compile_step=False, seed=seed, **kwargs)


def actions(env: BbgymTorchRLEnv, steps: int) -> torch.Tensor:
    shape = (steps, *env.action_spec.shape)
    return torch.as_tensor(np.random.default_rng(3).uniform(-1, 1, shape), dtype=torch.float32)


def run(env: BbgymTorchRLEnv, steps: int) -> list:
    """(observation, reward, terminated, truncated) after each step, resetting finished
    envs between steps as TorchRL's rollouts and collectors do."""
    td = env.reset()
    out = []
    for a in actions(env, steps):
        td["action"] = a
        td, td_next = env.step_and_maybe_reset(td)
        nxt = td["next"]
        out.append((nxt["observation"], nxt["reward"], nxt["terminated"], nxt["truncated"]))
        td = td_next
    return out


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_torchrl_spec_check_passes(env_id: str) -> None:
    env = make(env_id)
    check_env_specs(env, seed=1)
    assert env.batch_size == torch.Size([N]) and env.batch_locked
    rollout = env.rollout(5, break_when_any_done=False)
    assert rollout["next", "observation"].shape == (
        N,
        5,
        *env.observation_spec["observation"].shape[1:],
    )
    assert torch.isfinite(rollout["next", "observation"]).all()
    assert torch.isfinite(rollout["next", "reward"]).all()


def test_steps_equal_the_native_vector_env_with_resets_between_steps() -> None:
    """The wrapper adds nothing: its steps are the torch vector env's, each finished env
    restarted by ``reset_envs`` before the next step (as the SB3 adapter does)."""
    env = make(SAIL)
    got = run(env, 50)
    native = gym.make_vec(
        SAIL,
        num_envs=N,
        vectorization_mode="vector_entry_point",
        backend="torch",
        dtype="float32",
        output="torch",
        compile=False,
        max_episode_steps=20,
    )
    native.reset(seed=0)
    ends = 0
    for a, (obs, reward, term, trunc) in zip(actions(env, 50), got, strict=True):
        o, r, te, tr, _ = native.step(a)
        torch.testing.assert_close(obs, o.to(torch.float32), rtol=0, atol=0)
        torch.testing.assert_close(reward, r.to(torch.float32).reshape(-1, 1), rtol=0, atol=0)
        assert torch.equal(term, te.reshape(-1, 1)) and torch.equal(trunc, tr.reshape(-1, 1))
        done = (te | tr).numpy()
        ends += int(done.sum())
        if done.any():
            native.unwrapped.reset_envs(done)
    assert ends >= N  # every env restarted at least once


def test_no_step_is_spent_on_an_autoreset() -> None:
    """With episodes cut at 20 steps, an env that never ends early is truncated on steps
    20, 40, 60: TorchRL restarts it between steps, where Gymnasium's next-step autoreset
    would spend the 21st on the restart."""
    env = make(SAIL, wind_speed_range=(0.0, 0.0))  # no wind: no capsize
    got = run(env, 60)
    truncated = torch.stack([t for *_, t in got])[:, :, 0]  # [steps, envs]
    for i in range(N):
        assert torch.nonzero(truncated[:, i]).flatten().tolist() == [19, 39, 59]


def test_deterministic_under_a_seed() -> None:
    first, again, other = (run(make(THROW, seed=s), 6) for s in (5, 5, 6))
    for a, b in zip(first, again, strict=True):
        assert all(torch.equal(x, y) for x, y in zip(a, b, strict=True))
    assert not all(torch.equal(a[0], b[0]) for a, b in zip(first, other, strict=True))
    # set_seed, TorchRL's way, reseeds the next reset
    env = make(THROW, seed=None)
    env.set_seed(5)
    assert torch.equal(env.reset()["observation"], make(THROW, seed=5).reset()["observation"])


def test_a_collector_collects_frames() -> None:
    from torchrl.collectors import Collector

    env = make(SAIL)
    collector = Collector(env, policy=None, frames_per_batch=4 * N, total_frames=8 * N)
    batches = list(collector)
    collector.shutdown()
    assert len(batches) == 2 and all(b.numel() == 4 * N for b in batches)
    assert all(torch.isfinite(b["next", "observation"]).all() for b in batches)


def test_the_step_is_compiled_unless_asked_not_to() -> None:
    assert make(SAIL).core.backend.compile is False
    env = BbgymTorchRLEnv(SAIL, N)
    assert env.core.backend.compile is True and env.core.backend.output == "torch"


def test_bad_arguments_are_named() -> None:
    with pytest.raises(ValueError, match="num_envs must be a positive int, got 0"):
        BbgymTorchRLEnv(SAIL, 0)
    with pytest.raises(ValueError, match="dtype must be one of"):
        BbgymTorchRLEnv(SAIL, 2, dtype="float16")
    with pytest.raises(ValueError, match="env_id 'CartPole-v1' is not a bbgym env"):
        BbgymTorchRLEnv("CartPole-v1", 2)


@pytest.mark.skipif(not torch.cuda.is_available(), reason="no CUDA device")
def test_stays_on_the_cuda_device() -> None:
    env = BbgymTorchRLEnv(SAIL, 64, device="cuda", seed=0)
    rollout = env.rollout(10, break_when_any_done=False)
    assert rollout["next", "observation"].device.type == "cuda"
    assert rollout["next", "reward"].device.type == "cuda"
