"""Train stable-baselines3 on bbgym's native vector envs (needs the ``train`` extra).

    from stable_baselines3 import PPO
    from bbgym.sb3 import make_sb3_vec_env

    model = PPO("MlpPolicy", make_sb3_vec_env(env_id, n_envs=8, seed=0))

SB3's ``VecEnv`` resets an env on the very step that ends its episode and puts the last
observation in ``info["terminal_observation"]``; Gymnasium's native vector envs reset on
the next step. The adapter restarts finished envs at once (``reset_envs``) and fills the
infos SB3 reads: ``terminal_observation``, ``TimeLimit.truncated`` and ``is_success`` (and
any ``info_keys``) for the envs that finished. Other steps carry empty infos, so a step
costs no Python loop over the batch beyond the finished envs.
"""

from __future__ import annotations

import json
import warnings
import zipfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from stable_baselines3.common.vec_env import VecEnv

from bbgym.envs.core import CoreVectorEnv
from bbgym.spec import is_native_vector_env

BBGYM_VECTOR_ENVS = (CoreVectorEnv,)


class NativeVecEnvAdapter(VecEnv):
    """A bbgym native vector env seen through stable-baselines3's ``VecEnv`` interface."""

    def __init__(self, venv: Any, info_keys: Sequence[str] = ("is_success",)) -> None:
        if not (isinstance(venv, BBGYM_VECTOR_ENVS) or is_native_vector_env(venv)):
            raise ValueError(f"venv must be a bbgym native vector env, got {type(venv).__name__}")
        self.venv = venv
        self.info_keys = tuple(info_keys)
        self._actions: np.ndarray | None = None
        super().__init__(venv.num_envs, venv.single_observation_space, venv.single_action_space)

    def reset(self) -> np.ndarray:
        seeds = None if all(s is None for s in self._seeds) else list(self._seeds)
        options = [o for o in self._options if o]
        if options and any(o != options[0] for o in self._options):
            raise ValueError("options must be the same for every env of a native vector env")
        obs, _ = self.venv.reset(seed=seeds, options=options[0] if options else None)
        self._reset_seeds()
        self._reset_options()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions)

    def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        obs, reward, terminated, truncated, info = self.venv.step(self._actions)
        dones = terminated | truncated
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        finished = np.flatnonzero(dones)
        for i in finished:
            infos[i]["terminal_observation"] = obs[i].copy()
            infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
            for key in self.info_keys:
                if key in info:
                    value = info[key][i]
                    infos[i][key] = value.item() if isinstance(value, np.generic) else value
        if finished.size:
            obs = self.venv.reset_envs(dones)
        return obs, reward.astype(np.float32), dones, infos

    def close(self) -> None:
        self.venv.close()

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        return [getattr(self.venv, attr_name)] * len(self._get_indices(indices))

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        setattr(self.venv, attr_name, value)

    def env_method(self, method_name: str, *args: Any, indices: Any = None, **kwargs: Any) -> list:
        result = getattr(self.venv, method_name)(*args, **kwargs)
        return [result] * len(self._get_indices(indices))

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        return [False] * len(self._get_indices(indices))

    def get_images(self) -> Sequence[np.ndarray | None]:
        frames = self.venv.render()
        return list(frames) if frames is not None else [None] * self.num_envs


def make_sb3_vec_env(
    env_id: str, n_envs: int = 8, seed: int | None = None, **kwargs: Any
) -> NativeVecEnvAdapter:
    """``gym.make_vec(env_id, n_envs)`` (native) wrapped for stable-baselines3, seeded."""
    venv = gym.make_vec(env_id, num_envs=n_envs, vectorization_mode="vector_entry_point", **kwargs)
    adapter = NativeVecEnvAdapter(venv)
    if seed is not None:
        adapter.seed(seed)
    return adapter


def algorithm_class(algo: str) -> type:
    """The stable-baselines3 class of a preset's ``algo`` (:data:`bbgym.config.ALGORITHMS`)."""
    from stable_baselines3 import PPO, SAC

    classes = {"ppo": PPO, "sac": SAC}
    if algo not in classes:
        raise ValueError(f"algo must be one of {sorted(classes)}, got {algo!r}")
    return classes[algo]


def saved_algorithm(path: str | Path) -> str:
    """Which algorithm saved the stable-baselines3 model ``path`` (``"ppo"`` or ``"sac"``),
    read from the zip's ``data`` (the policy class's module: SAC's live in
    ``stable_baselines3.sac``, PPO's ``MlpPolicy`` is the common actor-critic one)."""
    try:
        with zipfile.ZipFile(path) as archive:
            data = json.loads(archive.read("data"))
        module = data["policy_class"]["__module__"]
    except (OSError, KeyError, ValueError, zipfile.BadZipFile) as err:
        raise ValueError(f"{path}: not a saved stable-baselines3 model ({err})") from None
    return "sac" if module.startswith("stable_baselines3.sac") else "ppo"


def load_model(path: str | Path, algo: str, name: str = "--model", **kwargs: Any) -> Any:
    """Load the ``algo`` model saved at ``path`` on the CPU; a model of another algorithm
    raises an error naming the argument ``name`` (``--model``) and what the file holds."""
    found = saved_algorithm(path)
    if found != algo:
        raise ValueError(f"{name} {path} is a {found.upper()} model, not {algo.upper()}")
    with warnings.catch_warnings():
        # A SAC model saved with n-step returns records its NStepReplayBuffer class, and
        # SB3 2.9 warns on load that n_steps "is ignored": the buffer is rebuilt with the
        # saved n_steps and gamma all the same (tests/test_train_smoke.py resumes one).
        warnings.filterwarnings("ignore", message=r"`n_steps=\d+` is ignored")
        return algorithm_class(algo).load(path, device="cpu", **kwargs)
