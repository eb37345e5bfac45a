"""The sailing family's demo (``bbgym demo``): one episode of BeachballSail-v0 sailed by
the simple helmsman, its frames and a table of its statistics."""

from __future__ import annotations

import math
import time
from typing import Any

import gymnasium as gym
import numpy as np

from bbgym.agents.sail_simple import SimpleSailController

SPEC_ENV_ID = "BeachballSail-v0"
"""The version the demo sails."""


def sail_episode(seed: int, frame_skip: int = 2) -> tuple[dict[str, Any], list[np.ndarray]]:
    """Sail one episode; return its statistics and the rendered frames kept."""
    env = gym.make(SPEC_ENV_ID, render_mode="rgb_array")
    controller = SimpleSailController()
    obs, info = env.reset(seed=seed)
    controller.reset()
    frames = [env.render()]
    speeds: list[float] = [info["boat_speed"]]
    heels: list[float] = [abs(info["heel"])]
    position = np.asarray(info["position"], dtype=float)
    distance = 0.0
    total_return = 0.0
    steps = 0
    sim_time = 0.0
    terminated = truncated = False
    while not (terminated or truncated):
        action = controller(obs)
        t0 = time.perf_counter()
        obs, reward, terminated, truncated, info = env.step(action)
        sim_time += time.perf_counter() - t0
        steps += 1
        total_return += float(reward)
        speeds.append(info["boat_speed"])
        heels.append(abs(info["heel"]))
        new_position = np.asarray(info["position"], dtype=float)
        distance += float(np.hypot(*(new_position - position)))
        position = new_position
        if steps % frame_skip == 0 or terminated or truncated:
            frames.append(env.render())
    env.close()
    stats = {
        "seed": seed,
        "success": bool(info["is_success"]),
        "capsized": bool(info["capsized"]),
        "truncated": bool(truncated),
        "steps": steps,
        "elapsed_time_s": float(info["elapsed_time"]),
        "distance_sailed_m": distance,
        "final_distance_to_mark_m": float(info["distance_to_mark"]),
        "mean_boat_speed_mps": float(np.mean(speeds)),
        "max_boat_speed_mps": float(np.max(speeds)),
        "max_heel_deg": math.degrees(float(np.max(heels))),
        "tacks": int(info["tacks"]),
        "jibes": int(info["jibes"]),
        "return": total_return,
        "sim_steps_per_s": steps / sim_time if sim_time > 0 else float("nan"),
        "frames": len(frames),
    }
    return stats, frames


def format_table(stats: dict[str, Any]) -> str:
    rows = [
        ("success", str(stats["success"])),
        ("steps", str(stats["steps"])),
        ("elapsed simulated time", f"{stats['elapsed_time_s']:.2f} s"),
        ("distance sailed", f"{stats['distance_sailed_m']:.1f} m"),
        ("final distance to mark", f"{stats['final_distance_to_mark_m']:.1f} m"),
        ("mean boat speed", f"{stats['mean_boat_speed_mps']:.2f} m/s"),
        ("max boat speed", f"{stats['max_boat_speed_mps']:.2f} m/s"),
        ("max heel", f"{stats['max_heel_deg']:.1f} deg"),
        ("tacks", str(stats["tacks"])),
        ("jibes", str(stats["jibes"])),
        ("return", f"{stats['return']:.2f}"),
        ("simulation speed", f"{stats['sim_steps_per_s']:.0f} steps/s"),
    ]
    width = max(len(name) for name, _ in rows)
    lines = [f"| {'statistic':<{width}} | value |", f"|{'-' * (width + 2)}|-------|"]
    lines += [f"| {name:<{width}} | {value} |" for name, value in rows]
    return "\n".join(lines)


def demo(seed: int, frame_skip: int) -> tuple[str, str, dict[str, Any], list[np.ndarray]]:
    """The family's demo for ``bbgym demo``: ``(caption, statistics table, statistics,
    frames)`` of one episode sailed by the simple helmsman (the spec picks the seed when
    the user gives none)."""
    stats, frames = sail_episode(seed, frame_skip)
    caption = f"{SPEC_ENV_ID}, seed {seed}, SimpleSailController"
    return caption, format_table(stats), stats, frames
