"""A tiny env family declared in the test suite alone: a point mass pushed to a target.

It is what ``docs/new-env.md`` asks of a family, at its smallest: a task core (pure
functions over an immutable state, on Python floats, NumPy or torch), the two Gymnasium
adapters, and a spec. Registering the spec is all it takes for the package's machinery
(check_env, vector envs, the fuzzer, ``bbgym evaluate``, ``bbgym bench``, RL Zoo) to serve it.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from gymnasium import spaces

from bbgym.envs.common import check_box_action, check_option_keys, option_path
from bbgym.envs.core import CoreEnv, CoreVectorEnv
from bbgym.envs.functional import InitialNoise, TaskCore
from bbgym.physics.validation import check_number, interval
from bbgym.spec import EnvSpec, FuzzSpec, Version, register_spec, unregister_spec

ENV_ID = "PointMass-v0"
MASS_KG = interval(0.0, 100.0, low_open=True)
FORCE_N = interval(0.0, 100.0, low_open=True)
DT_S = interval(0.0, 1.0, low_open=True)
START_DISTANCE_M = interval(0.0, 10.0)
TARGET_RADIUS_M = 0.1


class PointState(NamedTuple):
    x_m: Any
    v_mps: Any
    arrived: Any
    elapsed_s: Any


class PointTask(TaskCore):
    """A mass on a line pushed by a force in [-max_force, max_force] toward x = 0."""

    initial_noise_counts = (1, 0)

    def __init__(self, mass_kg: float = 1.0, max_force_n: float = 1.0, dt: float = 0.1) -> None:
        self.mass_kg = check_number("mass_kg", mass_kg, MASS_KG)
        self.max_force_n = check_number("max_force_n", max_force_n, FORCE_N)
        self.dt = check_number("dt", dt, DT_S)
        self.action_space = spaces.Box(-1.0, 1.0, (1,), np.float32)
        self.observation_space = spaces.Box(-1.0, 1.0, (2,), np.float32)

    def initial(self, noise: InitialNoise, options: Mapping[str, Any], xp: Any) -> PointState:
        zero = 0.0 * noise.uniform[0]
        x = zero + options["x"] if "x" in options else 2.0 * (2.0 * noise.uniform[0] - 1.0)
        return PointState(x, zero, zero > 1.0, zero)

    def check_options(self, options: Mapping[str, Any] | None) -> dict[str, Any]:
        checked = check_option_keys(options, ("x",))
        for key, value in checked.items():
            checked[key] = check_number(option_path(key), value, START_DISTANCE_M)
        return checked

    def check_action(self, action: Any, batch: int) -> Any:
        a = check_box_action(action, 1, batch)
        return (float(a[0]),) if batch == 0 else a

    def step_noise_mask(self, state: PointState, xp: Any) -> Any:
        return state.arrived & False

    def begin(self, state: PointState, action: Any, noise: Any, xp: Any, record: bool) -> Any:
        push = action[0] if isinstance(action, tuple) else action[..., 0]
        return (state, push * self.max_force_n)

    def chunk(self, carry: Any, xp: Any) -> Any:
        return carry

    def end(self, state: PointState, carry: Any, xp: Any) -> tuple[PointState, None]:
        _, force = carry
        v = state.v_mps + force / self.mass_kg * self.dt  # semi-implicit Euler
        x = state.x_m + v * self.dt
        arrived = xp.abs(x) <= TARGET_RADIUS_M
        return PointState(x, v, arrived, state.elapsed_s + self.dt), None

    def measure(self, state: PointState, xp: Any) -> dict[str, Any]:
        return {}

    def observation(self, state: PointState, m: dict, xp: Any) -> tuple:
        return (state.x_m / 10.0, state.v_mps / 10.0)

    def reward(self, state: PointState, xp: Any) -> Any:
        return xp.where(state.arrived, 1.0, 0.0) - 0.01

    def terminal(self, state: PointState, xp: Any) -> Any:
        return state.arrived

    def info(self, state: PointState, m: dict, xp: Any) -> dict[str, Any]:
        return {"is_success": state.arrived, "position": state.x_m}


class PointMassEnv(CoreEnv):
    """Push a point mass to x = 0 (the test suite's tiny env)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}
    task_class = PointTask


class PointMassVectorEnv(CoreVectorEnv):
    """Native vector version of :class:`PointMassEnv`."""

    metadata = {**CoreVectorEnv.metadata, "render_modes": ["rgb_array"], "render_fps": 10}
    task_class = PointTask


def _scripted(env: Any) -> Any:
    """A PD controller on the observation: push against position and speed."""

    def policy(obs: np.ndarray) -> np.ndarray:
        x, v = 10.0 * obs[..., 0], 10.0 * obs[..., 1]
        return np.clip(-(2.0 * x + 3.0 * v), -1.0, 1.0)[..., None].astype(np.float32)

    return policy


def _sample_kwargs(version: Version, draw: Any) -> dict[str, Any]:
    return {
        "mass_kg": draw("mass_kg", MASS_KG, True),
        "max_force_n": draw("max_force_n", FORCE_N, True),
        "dt": draw("dt", DT_S, True),
    }


def _sample_options(task: Any, draw: Any) -> dict[str, Any] | None:
    return {"x": draw("options['x']", START_DISTANCE_M, False)}


PRESET = """\
env_id: PointMass-v0
env: {mass_kg: 1.0, max_force_n: 1.0, dt: 0.1}
algo: ppo
ppo: {n_steps: 32, batch_size: 64, learning_rate: 0.001}
train: {n_envs: 4, total_timesteps: 256}
"""


def make_spec(preset: Path) -> EnvSpec:
    return EnvSpec(
        family="point_mass",
        env_class="PointMassEnv",
        vector_env_class="PointMassVectorEnv",
        max_episode_steps=200,
        summary="push a point mass to a target",
        actions="force",
        versions=(Version(ENV_ID, "the first version", preset=preset, base=True),),
        policies={"scripted": _scripted},
        fuzz=FuzzSpec(_sample_kwargs, _sample_options, episode_steps=30),
        classes_module=__name__,
    )


def register(preset_dir: Path) -> EnvSpec:
    """Register the family (its classes are looked up in this module, as a package's
    family's are in ``bbgym.envs.<family>``)."""
    preset = preset_dir / "point_mass.yaml"
    preset.write_text(PRESET)
    return register_spec(make_spec(preset))


def unregister() -> None:
    unregister_spec("point_mass")
