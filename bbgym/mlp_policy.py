"""A trained policy network as a NumPy function: the deterministic action of a small MLP,
saved as one ``.npz`` file.

``bbgym train --engine rejax`` trains in JAX and saves its policy this way, so that
evaluating, recording or deploying it needs NumPy alone (no JAX, no flax):

    from bbgym.mlp_policy import MLPPolicy

    policy = MLPPolicy.load("runs/rejax/<env id>-seed0/best_model.npz")
    action = policy(obs)          # one observation or a batch of them

The network is ``hidden = activation(x @ W + b)`` per hidden layer, then the mean head
``m = hidden @ W + b``. The action is ``tanh(m)`` scaled into the action bounds (``squash``:
SAC's squashed Gaussian) or ``m`` clipped to them (PPO's Gaussian). Where the learner
normalized observations, ``(obs - obs_mean) / sqrt(obs_var + 1e-8)`` comes first.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

OBS_VAR_EPS = 1e-8
"""What the observation normalizer adds to the variance (rejax's and Gymnasium's value)."""


def _silu(x: np.ndarray) -> np.ndarray:
    return x / (1.0 + np.exp(-x))


ACTIVATIONS = {
    "relu": lambda x: np.maximum(x, 0.0),
    "tanh": np.tanh,
    "swish": _silu,
    "silu": _silu,
}
"""The hidden layers' activations a saved policy may name."""


@dataclass(frozen=True)
class MLPPolicy:
    """The deterministic action of an MLP policy (see the module docstring).

    Attributes:
        kernels: each layer's weight matrix ``(inputs, outputs)``, the mean head last.
        biases: each layer's bias.
        activation: the hidden layers' activation, a key of :data:`ACTIVATIONS`.
        squash: ``tanh`` into the bounds (True) or clip to them (False).
        action_low: the action's lower bounds.
        action_high: the action's upper bounds.
        obs_mean: the observation normalizer's mean (None: no normalizer).
        obs_var: its variance.
        meta: what made it (env id, algorithm, seed, timesteps), JSON-able.
    """

    kernels: tuple[np.ndarray, ...]
    biases: tuple[np.ndarray, ...]
    activation: str
    squash: bool
    action_low: np.ndarray
    action_high: np.ndarray
    obs_mean: np.ndarray | None = None
    obs_var: np.ndarray | None = None
    meta: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.activation not in ACTIVATIONS:
            raise ValueError(f"activation {self.activation!r} is not one of {sorted(ACTIVATIONS)}")
        if len(self.kernels) != len(self.biases) or not self.kernels:
            raise ValueError("kernels and biases: one of each per layer, at least one layer")

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        """The action for ``obs``.

        Args:
            obs: one observation ``(obs_size,)`` or a batch ``(n, obs_size)``.

        Returns:
            The action, ``(action_size,)`` or ``(n, action_size)``, float32.
        """
        x = np.asarray(obs, dtype=np.float64)
        if self.obs_mean is not None:
            x = (x - self.obs_mean) / np.sqrt(self.obs_var + OBS_VAR_EPS)
        hidden = ACTIVATIONS[self.activation]
        for kernel, bias in zip(self.kernels[:-1], self.biases[:-1], strict=True):
            x = hidden(x @ kernel + bias)
        mean = x @ self.kernels[-1] + self.biases[-1]
        if self.squash:
            centre = (self.action_high + self.action_low) / 2.0
            half_width = (self.action_high - self.action_low) / 2.0
            action = centre + np.tanh(mean) * half_width
        else:
            action = np.clip(mean, self.action_low, self.action_high)
        return action.astype(np.float32)

    def save(self, path: str | Path) -> None:
        """Write the policy to ``path`` (an ``.npz`` file).

        Args:
            path: the file.
        """
        arrays: dict[str, np.ndarray] = {
            "activation": np.array(self.activation),
            "squash": np.array(self.squash),
            "action_low": np.asarray(self.action_low),
            "action_high": np.asarray(self.action_high),
            "meta": np.array(json.dumps(self.meta)),
        }
        for i, (kernel, bias) in enumerate(zip(self.kernels, self.biases, strict=True)):
            arrays[f"kernel_{i}"], arrays[f"bias_{i}"] = np.asarray(kernel), np.asarray(bias)
        if self.obs_mean is not None:
            arrays["obs_mean"], arrays["obs_var"] = self.obs_mean, self.obs_var
        with open(path, "wb") as f:
            np.savez(f, **arrays)

    @classmethod
    def load(cls, path: str | Path) -> MLPPolicy:
        """Read a policy that :meth:`save` wrote.

        Args:
            path: the ``.npz`` file.

        Returns:
            The policy.

        Raises:
            ValueError: where the file is not such a policy, naming it.
        """
        with np.load(path, allow_pickle=False) as data:
            names = set(data.files)
            if not {"activation", "squash", "kernel_0", "bias_0"} <= names:
                raise ValueError(
                    f"{path}: not a policy of bbgym.mlp_policy (its arrays: {sorted(names)})"
                )
            layers = sum(1 for name in names if name.startswith("kernel_"))
            return cls(
                kernels=tuple(data[f"kernel_{i}"] for i in range(layers)),
                biases=tuple(data[f"bias_{i}"] for i in range(layers)),
                activation=str(data["activation"]),
                squash=bool(data["squash"]),
                action_low=data["action_low"],
                action_high=data["action_high"],
                obs_mean=data["obs_mean"] if "obs_mean" in names else None,
                obs_var=data["obs_var"] if "obs_var" in names else None,
                meta=json.loads(str(data["meta"])) if "meta" in names else {},
            )
