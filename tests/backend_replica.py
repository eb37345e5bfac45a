"""The torch backend's step run on NumPy, for the backend equivalence tests: the same
``VectorStep`` functions, keys and counters as the compiled step, so torch float64 must
match it to rounding."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import gymnasium as gym
import numpy as np

from bbgym import backends
from bbgym.envs.functional import VectorStep, counter_initial_noise


def make_torch(
    env_id: str, num_envs: int, dtype: str = "float64", compile: bool = False, **kwargs: Any
) -> gym.vector.VectorEnv:
    """The env's native vector env on the torch backend (CPU)."""
    return gym.make_vec(
        env_id,
        num_envs=num_envs,
        vectorization_mode="vector_entry_point",
        backend="torch",
        dtype=dtype,
        compile=compile,
        **kwargs,
    )


def replica_run(
    env_id: str,
    num_envs: int,
    seed: int,
    actions: np.ndarray,
    extra: Callable[[Any, dict], Any] | None = None,
    **kwargs: Any,
) -> list[tuple]:
    """(obs, reward, terminated, truncated[, extra(state, info)]) per step of ``actions``
    (``(steps, num_envs, ...)``), from a reset with ``seed``."""
    task = make_torch(env_id, num_envs, **kwargs).unwrapped
    step = VectorStep(task.task, task.max_episode_steps, np, np.float64)
    task = task.task
    keys = np.array([backends.env_keys(seed + i, 1, np)[0] for i in range(num_envs)])
    counter = np.zeros(num_envs, dtype=np.int64)
    state = task.initial(counter_initial_noise(task, keys, counter, np.float64, np), {}, np)
    counter = counter + 1
    steps = np.zeros(num_envs, dtype=np.int64)
    restarting = np.zeros(num_envs, dtype=bool)
    out = []
    for a in actions:
        state, obs, reward, term, trunc, info, counter, steps = step(
            state, a.astype(np.float64), keys, counter, steps, restarting
        )
        restarting = term | trunc
        row = (obs, reward, term, trunc)
        out.append(row if extra is None else (*row, extra(state, info)))
    return out


@contextmanager
def compiles() -> Iterator[Any]:
    """Fails the test unless ``torch.compile`` really compiled graphs inside the block.

    Dynamo's caches are emptied first, so every compiled part called in the block traces a
    new graph; a run that fell back to eager torch (or never reached the compiler) counts
    none. Yields Dynamo's counters (``counters["stats"]["unique_graphs"]``, ...)."""
    import torch._dynamo
    from torch._dynamo.utils import counters

    torch._dynamo.reset()
    counters.clear()
    yield counters
    graphs = counters["stats"]["unique_graphs"]
    assert graphs >= 1, f"torch.compile compiled no graph: {dict(counters['stats'])}"
