"""The ball envs (Throw, Curve, Topple) from the keyboard (``bbgym play``): aim, then throw.

Shared by the throwing and toppling families (their specs name it)."""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np

# pygame as bbgym.keyboard imports it (quietly, and only where the render extra is in)
from bbgym.keyboard import KeyboardWrapper, pygame, show_status

# Throw aim: initial values, change per frame and limits.
INITIAL_SPEED_MPS, INITIAL_ELEVATION_DEG = 10.0, 35.0
SPEED_STEP_MPS, ANGLE_STEP_DEG, SPIN_STEP_RPS = 0.2, 1.0, 2.0
ELEVATION_RANGE_DEG = (-30.0, 90.0)

# Throw command: [speed, elevation, azimuth, side spin, back spin] changes, and throw.
SPEED, ELEVATION, AZIMUTH, SIDE_SPIN, BACK_SPIN, THROW = range(6)


def _unit(index: int, sign: float = 1.0) -> tuple[float, ...]:
    return tuple(sign if k == index else 0.0 for k in range(6))


THROW_KEYS: dict[int, tuple[float, ...]] = {
    pygame.K_w: _unit(SPEED),
    pygame.K_s: _unit(SPEED, -1.0),
    pygame.K_UP: _unit(ELEVATION),
    pygame.K_DOWN: _unit(ELEVATION, -1.0),
    pygame.K_LEFT: _unit(AZIMUTH),
    pygame.K_RIGHT: _unit(AZIMUTH, -1.0),
    pygame.K_a: _unit(SIDE_SPIN),
    pygame.K_d: _unit(SIDE_SPIN, -1.0),
    pygame.K_e: _unit(BACK_SPIN),
    pygame.K_q: _unit(BACK_SPIN, -1.0),
    pygame.K_SPACE: _unit(THROW),
}


class ThrowKeys(KeyboardWrapper):
    """A ball env (Throw, Curve, Topple) from the keys. The wrapper holds an aim (launch
    speed, elevation, azimuth, side spin, back spin) that commands change without stepping
    the env (such a step returns the last observation and info, reward 0, not done); a
    throw command steps the env once with :meth:`throw_action` (again only after the
    command was released). ``render()`` then plays the flight back frame by frame
    (``render_flight()``) and, after the last throw of an episode, holds where it landed
    for one second at ``render_fps``."""

    key_effects = THROW_KEYS

    def __init__(self, env: gym.Env, seed: int | None = None) -> None:
        super().__init__(env, seed)
        task = env.unwrapped.task
        self.max_speed, self.max_spin = float(task.max_speed), float(task.max_spin)
        self.speed, self.elevation_deg = INITIAL_SPEED_MPS, INITIAL_ELEVATION_DEG
        self.azimuth_deg = 0.0
        self.side_spin, self.back_spin = 0.0, 0.0
        self.throws = 0
        self._held = False
        self._frames: list[np.ndarray] = []
        self._last: tuple[Any, dict[str, Any]] = (None, {})

    def reset(self, **kwargs: Any) -> Any:
        obs, info = super().reset(**kwargs)
        self._last = (obs, info)
        self._held = False
        self.speed, self.elevation_deg = INITIAL_SPEED_MPS, INITIAL_ELEVATION_DEG
        self.side_spin, self.back_spin = 0.0, 0.0
        target = info.get("target")
        self.azimuth_deg = (
            math.degrees(math.atan2(float(target[1]), float(target[0])))
            if target is not None
            else 0.0
        )
        self._show_aim()
        return obs, info

    def aim(self) -> dict[str, float]:
        return {
            "speed": self.speed,
            "elevation_deg": self.elevation_deg,
            "azimuth_deg": self.azimuth_deg,
            "side_spin": self.side_spin,
            "back_spin": self.back_spin,
        }

    def _show_aim(self) -> None:
        show_status(
            f"speed {self.speed:4.1f} m/s, elevation {self.elevation_deg:+5.1f} deg, "
            f"azimuth {self.azimuth_deg:+6.1f} deg, side spin {self.side_spin:+5.1f}, "
            f"back spin {self.back_spin:+5.1f} rad/s"
        )

    def throw_action(self) -> np.ndarray:
        """The env action of the current aim: launch velocity / ``max_speed``, spin /
        ``max_spin`` (side spin about +z, back spin about the horizontal axis to the
        thrower's right, so that it lifts the ball)."""
        el, az = math.radians(self.elevation_deg), math.radians(self.azimuth_deg)
        velocity = self.speed * np.array(
            [math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)]
        )
        spin = np.array(
            [self.back_spin * math.sin(az), -self.back_spin * math.cos(az), self.side_spin]
        )
        action = np.concatenate([velocity / self.max_speed, spin / self.max_spin])
        return np.clip(action, -1.0, 1.0).astype(np.float32)

    def step(self, command: np.ndarray) -> Any:
        c = np.asarray(command, dtype=np.float64)
        before = self.aim()
        self.speed = float(np.clip(self.speed + SPEED_STEP_MPS * c[SPEED], 0.0, self.max_speed))
        self.elevation_deg = float(
            np.clip(self.elevation_deg + ANGLE_STEP_DEG * c[ELEVATION], *ELEVATION_RANGE_DEG)
        )
        azimuth = self.azimuth_deg + ANGLE_STEP_DEG * c[AZIMUTH]
        self.azimuth_deg = float((azimuth + 180.0) % 360.0 - 180.0)
        spin = self.max_spin
        self.side_spin = float(np.clip(self.side_spin + SPIN_STEP_RPS * c[SIDE_SPIN], -spin, spin))
        self.back_spin = float(np.clip(self.back_spin + SPIN_STEP_RPS * c[BACK_SPIN], -spin, spin))
        if self.aim() != before:
            self._show_aim()
        pressed = bool(c[THROW] > 0.5)
        throw = pressed and not self._held and not self._frames
        self._held = pressed
        if not throw:
            obs, info = self._last
            return obs, 0.0, False, False, info
        obs, reward, terminated, truncated, info = self.env.step(self.throw_action())
        self.throws += 1
        self._last = (obs, info)
        print(
            f"\nthrow {self.throws}: reward {reward:+.2f}"
            + (", success!" if info.get("is_success") else "")
        )
        if self.env.render_mode == "rgb_array":
            render_flight = getattr(self.env.unwrapped, "render_flight", None)
            self._frames = list(render_flight()) if render_flight else []
            if terminated or truncated:  # the next reset comes at once: hold the landing
                self._frames += [self.env.render()] * int(self.metadata.get("render_fps", 20))
        return obs, reward, terminated, truncated, info

    def render(self) -> Any:
        if self._frames:
            return self._frames.pop(0)
        return self.env.render()
