"""bbgym's envs as TorchRL environments, on the env's own device (the ``torchrl`` extra).

    from bbgym.torchrl import BbgymTorchRLEnv

    env = BbgymTorchRLEnv(env_id, num_envs=1024, device="cpu", seed=0)
    rollout = env.rollout(300, break_when_any_done=False)   # a TensorDict [1024, 300]

The env is the native vector env on the torch backend with tensors in and out
(``backend="torch", output="torch"``): the step, the observations, rewards and ends and
the random numbers stay on ``device`` (a CUDA device for GPU-resident training), with no
NumPy round trip. It is batch-locked: its batch size is ``[num_envs]``.

TorchRL resets a finished env itself, between steps (``step_and_maybe_reset``, a
collector): ``_reset`` with a ``"_reset"`` mask restarts those envs alone
(:meth:`bbgym.envs.core.CoreVectorEnv.reset_envs`), so no step is spent on Gymnasium's
next-step autoreset. Keys: ``observation`` (float, the env's observation), ``action``
(bounded in [-1, 1]), ``reward`` (``[num_envs, 1]``), ``done``, ``terminated`` and
``truncated`` (``[num_envs, 1]``, bool) and ``is_success`` (bool, at an episode's end).
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

try:
    import torch
    from tensordict import TensorDict, TensorDictBase
    from torchrl.data import Bounded, Categorical, Composite, Unbounded
    from torchrl.envs import EnvBase
except ImportError as error:  # the fix, not a bare ModuleNotFoundError
    from bbgym._extras import install_hint

    raise ImportError(f"bbgym.torchrl needs TorchRL (the 'torchrl' extra): "
                      f"{install_hint('torchrl')}") from error  # fmt: skip

import bbgym  # noqa: F401  (registers the ids)
from bbgym.envs.core import CoreVectorEnv
from bbgym.spec import env_ids

DTYPES = {"float32": torch.float32, "float64": torch.float64}


class BbgymTorchRLEnv(EnvBase):
    """A bbgym env id's native vector env on the torch backend, as a batch-locked TorchRL
    ``EnvBase`` of ``num_envs`` envs on ``device``.

    ``dtype`` is the physics' float type (``"float32"`` or ``"float64"``; observations and
    rewards come in it), ``compile_step`` whether bbgym's step is ``torch.compile``d (the
    default; ``False`` runs it eagerly; the name is not ``compile``, which TorchRL's
    ``EnvBase`` takes for itself), ``seed`` the first reset's seed (env ``i`` is seeded
    ``seed + i``; :meth:`set_seed` reseeds), and ``env_kwargs`` the env's own arguments."""

    batch_locked = True

    def __init__(
        self,
        env_id: str,
        num_envs: int,
        *,
        device: str | torch.device = "cpu",
        dtype: str = "float32",
        compile_step: bool = True,
        seed: int | None = None,
        **env_kwargs: Any,
    ) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, int) or num_envs < 1:
            raise ValueError(f"num_envs must be a positive int, got {num_envs!r}")
        if dtype not in DTYPES:
            raise ValueError(f"dtype must be one of {sorted(DTYPES)}, got {dtype!r}")
        if env_id not in env_ids():
            raise ValueError(
                f"env_id {env_id!r} is not a bbgym env; bbgym's: {', '.join(env_ids())}"
            )
        device = torch.device(device)
        super().__init__(device=device, batch_size=torch.Size([num_envs]))
        self.env_id = env_id
        self.vector_env = gym.make_vec(
            env_id, num_envs=num_envs, vectorization_mode="vector_entry_point",
            backend="torch", device=str(device), dtype=dtype, output="torch",
            compile=compile_step, **env_kwargs,
        )  # fmt: skip
        self.core: CoreVectorEnv = self.vector_env.unwrapped
        self._float = DTYPES[dtype]
        self._make_specs(num_envs)
        self._seed = seed

    def _make_specs(self, n: int) -> None:
        obs, act = self.core.single_observation_space, self.core.single_action_space
        self.observation_spec = Composite(
            observation=Bounded(
                low=torch.as_tensor(np.broadcast_to(obs.low, (n, *obs.shape)).copy()),
                high=torch.as_tensor(np.broadcast_to(obs.high, (n, *obs.shape)).copy()),
                shape=(n, *obs.shape), dtype=self._float, device=self.device,
            ),
            is_success=Categorical(2, shape=(n, 1), dtype=torch.bool, device=self.device),
            shape=(n,),
        )  # fmt: skip
        self.action_spec = Bounded(low=-1.0, high=1.0, shape=(n, *act.shape),
                                   dtype=self._float, device=self.device)  # fmt: skip
        self.reward_spec = Unbounded(shape=(n, 1), dtype=self._float, device=self.device)
        flag = Categorical(2, shape=(n, 1), dtype=torch.bool, device=self.device)
        self.done_spec = Composite(done=flag, terminated=flag.clone(), truncated=flag.clone(),
                                   shape=(n,))  # fmt: skip

    def _reset(self, tensordict: TensorDictBase | None = None, **kwargs: Any) -> TensorDictBase:
        mask = None if tensordict is None else tensordict.get("_reset", None)
        if mask is None or not self.core.started:
            obs, _ = self.core.reset(seed=self._seed)
            self._seed = None  # later full resets continue each env's stream
        else:
            obs = self.core.reset_envs(mask.reshape(-1).cpu().numpy())
        false = torch.zeros((self.batch_size[0], 1), dtype=torch.bool, device=self.device)
        return TensorDict(
            {"observation": self._obs(obs), "is_success": false.clone(), "done": false,
             "terminated": false.clone(), "truncated": false.clone()},
            batch_size=self.batch_size, device=self.device,
        )  # fmt: skip

    def _step(self, tensordict: TensorDictBase) -> TensorDictBase:
        obs, reward, terminated, truncated, info = self.core.step(tensordict.get("action"))
        terminated = terminated.reshape(-1, 1)
        truncated = truncated.reshape(-1, 1)
        success = info.get("is_success")
        success = (torch.zeros_like(terminated) if success is None
                   else torch.as_tensor(success, device=self.device).reshape(-1, 1))  # fmt: skip
        out = {
            "observation": self._obs(obs),
            "is_success": success.to(torch.bool),
            "reward": reward.to(self._float).reshape(-1, 1),
            "done": terminated | truncated,
            "terminated": terminated,
            "truncated": truncated,
        }
        return TensorDict(out, batch_size=self.batch_size, device=self.device)

    def _obs(self, obs: Any) -> torch.Tensor:
        return torch.as_tensor(obs, device=self.device).to(self._float)

    def _set_seed(self, seed: int | None) -> None:
        """The next full reset seeds env ``i`` with ``seed + i`` (TorchRL's ``set_seed``)."""
        self._seed = seed

    def close(self, *, raise_if_closed: bool = True) -> None:
        self.vector_env.close()
        super().close(raise_if_closed=raise_if_closed)
