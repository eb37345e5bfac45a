"""Fuzzing the registered env ids: their arguments (:func:`sample_kwargs`, a later version
keeping what it pins), reset options, episodes on every path (:func:`check_episode`: a
single env, vector envs on NumPy, torch and TorchRL, bad actions among the valid ones)
and invalid numbers (:func:`check_rejections`)."""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable, Mapping
from dataclasses import fields
from typing import Any

import gymnasium as gym
import numpy as np

import bbgym  # noqa: F401  (registers the ids)
from bbgym.fuzz.draws import (
    Draw,
)
from bbgym.spec import spec_of


def _fuzzed(env_id: str) -> Any:
    spec = spec_of(env_id)
    if spec.fuzz is None:
        raise ValueError(f"{env_id}: its family ({spec.family}) declares no fuzz sampler")
    return spec.fuzz


def sample_kwargs(env_id: str, draw: Draw) -> dict[str, Any]:
    """Constructor arguments of ``env_id`` drawn over their accepted intervals (by its
    family's sampler, :attr:`bbgym.spec.FuzzSpec.sample_kwargs`). A version that is no
    base task keeps what it pins (:func:`pin_version`), so Topple-v2 is fuzzed in its RK4
    steps and Sail-v2 as a sloop; the family's :attr:`~bbgym.spec.FuzzSpec.fit` then
    meets the constraints between arguments."""
    version = spec_of(env_id).version(env_id)
    fuzz = _fuzzed(env_id)
    kwargs = fuzz.sample_kwargs(version, draw)
    if not version.base:
        kwargs = pin_version(version.kwargs, kwargs)
    return fuzz.fit(kwargs) if fuzz.fit is not None else kwargs


def pin_version(pinned: Mapping[str, Any], drawn: dict[str, Any]) -> dict[str, Any]:
    """Drawn arguments with a version's registered ones in their place. A parameter group
    the version sets (Sail-v2's ``dinghy``) keeps the version's choices (strings: the rig,
    the sail model) and takes the drawn numbers over the version's: the version's boat
    with random constants, as a user changing one constant gets it."""
    kwargs = {**drawn, **pinned}
    for key, value in pinned.items():
        if isinstance(value, Mapping) and isinstance(drawn.get(key), Mapping):
            numbers = {k: v for k, v in drawn[key].items() if not isinstance(v, str)}
            kwargs[key] = {**value, **numbers}
    return kwargs


def sample_options(env_id: str, env: Any, draw: Draw) -> dict[str, Any] | None:
    """``reset`` options for an env made with some kwargs (``env.unwrapped.task``), each
    key present or not, within the same intervals as the constructor's ranges."""
    return _fuzzed(env_id).sample_options(getattr(env, "unwrapped", env).task, draw)


def finite_floats(value: Any, path: str) -> None:
    """Raise AssertionError naming the first non-finite float inside ``value``."""
    if isinstance(value, Mapping):
        for key, item in value.items():
            finite_floats(item, f"{path}[{key!r}]")
    elif isinstance(value, np.ndarray) and value.dtype == object:
        for i, item in enumerate(value):
            finite_floats(item, f"{path}[{i}]")
    elif isinstance(value, (float, int, np.floating, np.integer, np.ndarray)) and not isinstance(
        value, (bool, np.bool_)
    ):
        array = np.asarray(value)
        if array.dtype.kind in "fc" and not np.isfinite(array).all():
            raise AssertionError(f"non-finite value in {path}: {value!r}")


def check_step(space: gym.Space, obs: Any, reward: Any, info: Mapping, where: str) -> None:
    """Obs inside the space, reward finite, every float in info finite."""
    if not space.contains(obs):
        raise AssertionError(f"{where}: observation outside its space: {obs!r}")
    finite_floats(reward, f"{where}: reward")
    finite_floats(info, f"{where}: info")


BACKENDS = ("numpy", "torch", "torchrl")
"""The paths :func:`check_episode` steps a vector env through: the NumPy reference, the
torch backend (eager: a compile per configuration would cost minutes) with tensors in and
out, and the TorchRL env over it."""

BAD_ACTIONS: tuple[tuple[str, float | complex, type], ...] = (
    ("nan", math.nan, ValueError),
    ("inf", math.inf, ValueError),
    ("-inf", -math.inf, ValueError),
    ("complex", 1j, TypeError),
)
"""Action entries every path refuses, and the error each raises."""

BAD_ACTION_RATE = 0.1
"""The share of steps :func:`check_episode` first tries with one bad entry."""


class _Stepper:
    """One env of a kind behind one interface: ``reset``, ``step`` with a NumPy action,
    ``bad(action)`` (the same action as the path's own type, for the refusal), the
    observation space, and NumPy outputs."""

    def __init__(
        self, env_id: str, kwargs: Mapping[str, Any], num_envs: int, backend: str, seed: int
    ) -> None:
        self.num_envs, self.backend = num_envs, backend
        self.torch: Any = None
        if backend == "torchrl":
            import torch

            from bbgym.torchrl import BbgymTorchRLEnv

            self.torch = torch
            self.env: Any = BbgymTorchRLEnv(
                env_id, num_envs, compile_step=False, seed=seed, **kwargs
            )
            core = self.env.core
            self.space = core.observation_space
            self.shape = (num_envs, *core.single_action_space.shape)
            self.autoreset = False  # TorchRL resets the finished envs between steps
        elif num_envs:
            extra = {}
            if backend == "torch":
                import torch

                self.torch = torch
                extra = {"backend": "torch", "output": "torch", "compile": False}
            self.env = gym.make_vec(env_id, num_envs=num_envs, **kwargs, **extra)
            self.space = self.env.observation_space
            self.shape = (num_envs, *self.env.single_action_space.shape)
            self.autoreset = True
        else:
            self.env = gym.make(env_id, **kwargs)
            self.space = self.env.observation_space
            self.shape = self.env.action_space.shape
            self.autoreset = False

    def _tensor(self, action: Any) -> Any:
        if self.torch is None:
            return action
        dtype = self.torch.complex128 if np.iscomplexobj(action) else self.torch.float32
        return self.torch.as_tensor(action, dtype=dtype)

    def reset(self, seed: int | None, options: Any) -> tuple[Any, dict]:
        if self.backend == "torchrl":  # seeded on construction; takes no options
            self._td = self.env.reset()
            return _numpy(self._td["observation"]), {}
        obs, info = self.env.reset(seed=seed, options=options)
        return _numpy(obs), info

    def step(self, action: np.ndarray) -> tuple[Any, Any, Any, Any, Mapping]:
        if self.backend == "torchrl":
            self._td["action"] = self._tensor(action)
            td, self._td = self.env.step_and_maybe_reset(self._td)
            nxt = td["next"]
            info = {"is_success": _numpy(nxt["is_success"])}
            return (
                _numpy(nxt["observation"]),
                _numpy(nxt["reward"]),
                _numpy(nxt["terminated"]),
                _numpy(nxt["truncated"]),
                info,
            )
        obs, reward, terminated, truncated, info = self.env.step(self._tensor(action))
        return _numpy(obs), _numpy(reward), terminated, truncated, _numpy_tree(info)

    def close(self) -> None:
        self.env.close()


def _numpy(x: Any) -> Any:
    return x.detach().cpu().numpy() if hasattr(x, "detach") else x


def _numpy_tree(info: Any) -> Any:
    if isinstance(info, Mapping):
        return {k: _numpy_tree(v) for k, v in info.items()}
    return _numpy(info)


def check_episode(
    env_id: str,
    kwargs: Mapping[str, Any],
    options: Mapping[str, Any] | None,
    steps: int,
    seed: int,
    num_envs: int = 0,
    backend: str = "numpy",
) -> int:
    """Step ``steps`` random actions (the action space's full box, beyond [-1, 1] too,
    which the env clips) through a single env (``num_envs == 0``, resetting with
    ``options`` when an episode ends) or a vector env of ``num_envs`` on ``backend`` (one
    of :data:`BACKENDS`; autoreset), checking every output. Before one step in ten
    (:data:`BAD_ACTION_RATE`) the same action with one entry NaN, inf or complex
    (:data:`BAD_ACTIONS`) must raise the right error and change nothing (the valid step
    that follows is checked as usual). Returns the number of env steps taken.

    Args:
        env_id: a registered bbgym id.
        kwargs: its constructor arguments.
        options: ``reset`` options, or ``None``.
        steps: steps to take.
        seed: seeds the env and the actions.
        num_envs: 0 for a single env, else the vector env's size.
        backend: the vector env's path (single envs run on NumPy).

    Returns:
        ``steps * max(num_envs, 1)``.
    """
    if backend not in BACKENDS or (backend != "numpy" and not num_envs):
        raise ValueError(f"backend must be one of {BACKENDS} (a vector env), got {backend!r}")
    rng = np.random.default_rng(seed)
    env = _Stepper(env_id, kwargs, num_envs, backend, seed)
    where = f"{env_id} ({backend}, num_envs={num_envs})"
    try:
        obs, info = env.reset(seed, options)
        check_step(env.space, obs, 0.0, info, f"{where} reset")
        for t in range(steps):
            action = rng.uniform(-1.5, 1.5, env.shape).astype(np.float32)
            if rng.random() < BAD_ACTION_RATE:
                _check_refused(env, action, rng, f"{where} step {t}")
            obs, reward, terminated, truncated, info = env.step(action)
            check_step(env.space, obs, reward, info, f"{where} step {t}")
            if not env.autoreset and not num_envs and (terminated or truncated):
                obs, info = env.reset(None, options)
                check_step(env.space, obs, 0.0, info, f"{where} reset after step {t}")
    finally:
        env.close()
    return steps * max(num_envs, 1)


def bad_action(action: np.ndarray, rng: np.random.Generator) -> tuple[str, np.ndarray, type]:
    """A copy of ``action`` with one entry of :data:`BAD_ACTIONS` (drawn, as its place):
    the bad value's name, the action and the error it must raise."""
    name, value, error = BAD_ACTIONS[int(rng.integers(len(BAD_ACTIONS)))]
    bad = action.astype(np.complex128 if isinstance(value, complex) else np.float64)
    bad[np.unravel_index(int(rng.integers(bad.size)), bad.shape)] = value
    return name, bad, error


def _check_refused(env: _Stepper, action: np.ndarray, rng: np.random.Generator, where: str):
    """``action`` with one bad entry raises the right error on ``env``'s path."""
    name, bad, error = bad_action(action, rng)
    try:
        env.step(bad)
    except error:
        return
    except Exception as raised:  # noqa: BLE001 - reported as the wrong error
        raise AssertionError(
            f"{where}: a {name} action raised {type(raised).__name__} ({raised}), "
            f"expected {error.__name__}"
        ) from None
    raise AssertionError(f"{where}: a {name} action was accepted")


# -- invalid input ---------------------------------------------------------------------------

BAD_NUMBERS: tuple[tuple[Any, type], ...] = (
    ("x", TypeError),
    (True, TypeError),
    (None, TypeError),
    (1 + 2j, TypeError),
    (float("nan"), ValueError),
    (float("inf"), ValueError),
    (-float("inf"), ValueError),
    (np.array([1.0, 2.0]), TypeError),
)
"""Values no number argument accepts, and the error each raises."""


def numeric_arguments(env_id: str) -> list[str]:
    """The env's constructor arguments that take one number (for :func:`check_rejections`),
    and each field of its parameter groups as ``group.field``."""
    import inspect

    spec = spec_of(env_id)
    env_class = getattr(importlib.import_module(spec.module), spec.env_class)
    params_class = getattr(env_class.task_class, "params_class", None)
    if params_class is not None:  # every argument is a field of one dataclass
        return [
            f.name
            for f in fields(params_class)
            if "interval" in f.metadata and not isinstance(f.default, bool)
        ]
    names = []
    for name, parameter in inspect.signature(env_class.task_class.__init__).parameters.items():
        default = parameter.default
        if name in spec.param_groups:
            names += [
                f"{name}.{f.name}"
                for f in fields(spec.param_groups[name])
                if "interval" in f.metadata and not isinstance(f.default, bool)
            ]
        elif isinstance(default, (int, float)) and not isinstance(default, bool):
            names.append(name)
    return names


def check_refusals(
    make: Callable[..., Any], paths: list[str], integers: set[str], where: str
) -> int:
    """``make(**kwargs)`` with each number argument (or parameter field, ``group.field``)
    of ``paths`` set to each value of :data:`BAD_NUMBERS` raises the right error naming the
    path; an int argument (in ``integers``) refuses every float by its type, NaN and inf
    included. Returns how many errors were checked."""
    checked = 0
    for path in paths:
        for value, error in BAD_NUMBERS:
            error = TypeError if path in integers else error
            case = f"{where}: {path}={value!r}"
            try:
                make(**_nested(path, value))
            except error as raised:
                if path not in str(raised):
                    message = f"{case} raised {raised!r}, which does not name {path}"
                    raise AssertionError(message) from None
            except Exception as raised:  # noqa: BLE001 - reported as the wrong error
                raise AssertionError(
                    f"{case} raised {type(raised).__name__} ({raised}), expected {error.__name__}"
                ) from None
            else:
                raise AssertionError(f"{case} was accepted")
            checked += 1
    return checked


def _nested(path: str, value: Any) -> dict[str, Any]:
    """``{"a": {"b": value}}`` for the path ``a.b``."""
    head, _, rest = path.partition(".")
    return {head: _nested(rest, value) if rest else value}


def check_rejections(env_id: str) -> int:
    """Every number argument (and parameter field) of ``env_id`` refuses every value of
    :data:`BAD_NUMBERS` with the right error naming it, at construction
    (:func:`check_refusals`). Returns how many errors were checked."""
    integers = set(spec_of(env_id).integer_arguments)

    def make(**kwargs: Any) -> None:
        gym.make(env_id, **kwargs).close()

    return check_refusals(make, numeric_arguments(env_id), integers, env_id)
