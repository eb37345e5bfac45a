"""The puck's task core: pure functions over an immutable state, on any array namespace.

The template family of ``docs/new-env.md``: a puck on an air table, pushed toward a target
circle by the drag of an air jet the agent aims. Every law is a function of
:mod:`bbgym.physics` (the drag is :func:`~bbgym.physics.common.quadratic_drag_rate`, seed §8).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from gymnasium import spaces

from bbgym.envs.common import check_option_keys, option_path
from bbgym.envs.functional import Draws, TaskCore
from bbgym.physics.common import quadratic_drag_rate
from bbgym.physics.validation import CheckedFields, check_number, interval, param

START_DISTANCE_M = interval(1.0, 10.0)
"""``options['distance']``: how far from the target the puck starts."""


@dataclass(frozen=True)
class PuckParams(CheckedFields):
    """The puck, the air jet and the target: every argument of ``gym.make``."""

    mass_kg: float = param(0.5, interval(0.01, 100.0))
    drag_area_m2: float = param(0.05, interval(1e-4, 1.0))
    """C_d times the area the jet meets."""
    air_density_kgm3: float = param(1.2, interval(0.5, 2.0))
    max_jet_speed_mps: float = param(10.0, interval(0.0, 50.0, low_open=True))
    jet_noise_mps: float = param(0.5, interval(0.0, 5.0))
    """Standard deviation of the jet's gusts, per component and step."""
    target_radius_m: float = param(0.25, interval(0.05, 1.0))
    dt_s: float = param(0.1, interval(0.001, 0.5))


class PuckState(NamedTuple):
    """One puck per env: position and velocity in the table's frame (target at 0, 0)."""

    x_m: Any
    y_m: Any
    vx_mps: Any
    vy_mps: Any
    arrived: Any


class PuckTask(TaskCore[PuckState, PuckState]):
    """Blow the puck into the target circle; each step draws the jet's gusts."""

    params_class = PuckParams
    params: PuckParams
    action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
    """The jet's velocity (x, y) as fractions of ``max_jet_speed_mps``."""
    observation_space = spaces.Box(-1.0, 1.0, (4,), np.float32)

    def check_options(self, options: Any) -> dict[str, Any]:
        checked = check_option_keys(options, ("distance",))
        for key, value in checked.items():
            checked[key] = check_number(option_path(key), value, START_DISTANCE_M)
        return checked

    def initial(self, noise: Draws, options: Any, xp: Any) -> PuckState:
        bearing = 2.0 * math.pi * noise.uniform()
        distance = 2.0 + 2.0 * noise.uniform()
        distance = options.get("distance", distance)
        x, y = distance * xp.cos(bearing), distance * xp.sin(bearing)
        return PuckState(x, y, xp.zeros_like(x), xp.zeros_like(y), xp.zeros_like(x, dtype=xp.bool))

    def advance(self, state: PuckState, action: Any, noise: Draws, xp: Any) -> PuckState:
        p = self.params
        jet_x = p.max_jet_speed_mps * action_column(action, 0) + p.jet_noise_mps * noise.normal()
        jet_y = p.max_jet_speed_mps * action_column(action, 1) + p.jet_noise_mps * noise.normal()
        # The drag pushes the puck toward the jet's velocity; taken implicitly (the rate at
        # the old speed), so any accepted step is stable: v' = (v + h k/m w) / (1 + h k/m).
        relative = xp.sqrt((jet_x - state.vx_mps) ** 2 + (jet_y - state.vy_mps) ** 2)
        rate = p.dt_s * quadratic_drag_rate(p.drag_area_m2, p.air_density_kgm3, relative)
        rate = rate / p.mass_kg
        vx = (state.vx_mps + rate * jet_x) / (1.0 + rate)
        vy = (state.vy_mps + rate * jet_y) / (1.0 + rate)
        x, y = state.x_m + p.dt_s * vx, state.y_m + p.dt_s * vy  # semi-implicit Euler
        arrived = xp.sqrt(x * x + y * y) <= p.target_radius_m
        return PuckState(x, y, vx, vy, arrived)

    def observation(self, state: PuckState, m: Any, xp: Any) -> tuple:
        speed_scale = self.params.max_jet_speed_mps
        return (
            state.x_m / 10.0,
            state.y_m / 10.0,
            state.vx_mps / speed_scale,
            state.vy_mps / speed_scale,
        )

    def reward(self, state: PuckState, xp: Any) -> Any:
        return xp.where(state.arrived, 1.0, xp.full_like(state.x_m, -0.01))

    def terminal(self, state: PuckState, xp: Any) -> Any:
        return state.arrived

    def info(self, state: PuckState, m: Any, xp: Any) -> dict[str, Any]:
        return {"is_success": state.arrived, "distance_m": xp.sqrt(state.x_m**2 + state.y_m**2)}


def action_column(action: Any, k: int) -> Any:
    """Entry ``k`` of one env's action (a tuple) or column ``k`` of a batch's."""
    return action[k] if isinstance(action, tuple) else action[..., k]
