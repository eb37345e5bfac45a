"""v0 never changes behaviour: every env, single and native vector, replays the exact
observations, rewards and ends recorded from bbgym 0.2.0 under fixed seeds and actions
(gusts on, autoresets included). Regenerate only for a new env version:
``python tests/test_golden_v0.py --write``."""

from __future__ import annotations

import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import bbgym  # noqa: F401

GOLDEN = Path(__file__).parent / "data" / "golden_v0.npz"
ENV_IDS = ("BeachballSail-v0", "BeachballThrow-v0", "BeachballCurve-v0", "BeachballTopple-v0")
STEPS = {
    "BeachballSail-v0": 120,
    "BeachballThrow-v0": 24,
    "BeachballCurve-v0": 24,
    "BeachballTopple-v0": 20,
}
NUM_ENVS = 3


def _actions(env_id: str, shape: tuple[int, ...], steps: int) -> np.ndarray:
    rng = np.random.default_rng(1234)
    return rng.uniform(-1.0, 1.0, (steps, *shape)).astype(np.float32)


def record(env_id: str) -> dict[str, np.ndarray]:
    """Observations, rewards and ends of one single env and one native vector env."""
    steps = STEPS[env_id]
    out: dict[str, list] = {"single": [], "vector": []}
    env = gym.make(env_id)
    obs, _ = env.reset(seed=7)
    rows = [np.concatenate([obs, [0.0, 0.0]])]
    for a in _actions(env_id, env.action_space.shape, steps):
        obs, r, term, trunc, _ = env.step(a)
        rows.append(np.concatenate([obs, [r, float(term or trunc)]]))
        if term or trunc:
            obs, _ = env.reset()
            rows.append(np.concatenate([obs, [0.0, 0.0]]))
    out["single"] = np.array(rows)
    venv = gym.make_vec(env_id, num_envs=NUM_ENVS, vectorization_mode="vector_entry_point")
    obs, _ = venv.reset(seed=11)
    rows = [np.concatenate([obs, np.zeros((NUM_ENVS, 2))], axis=1)]
    for a in _actions(env_id, venv.action_space.shape, steps):
        obs, r, term, trunc, _ = venv.step(a)
        rows.append(np.concatenate([obs, r[:, None], (term | trunc)[:, None]], axis=1))
    out["vector"] = np.array(rows)
    env.close()
    venv.close()
    return out


def check_replay(golden_file: Path, env_id: str) -> dict[str, np.ndarray]:
    """Replays ``env_id`` and compares it with ``golden_file``; returns the recording."""
    golden = np.load(golden_file)
    now = record(env_id)
    for kind in ("single", "vector"):
        expected = golden[f"{env_id}/{kind}"]
        assert now[kind].shape == expected.shape, kind
        np.testing.assert_allclose(now[kind], expected, rtol=0, atol=1e-6, err_msg=kind)
    return now


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_replays_recorded_v0_episodes(env_id: str) -> None:
    check_replay(GOLDEN, env_id)


if __name__ == "__main__" and "--write" in sys.argv:
    data = {f"{e}/{k}": v for e in ENV_IDS for k, v in record(e).items()}
    np.savez_compressed(GOLDEN, **data)
    print({k: v.shape for k, v in data.items()})
