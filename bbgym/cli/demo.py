"""Sail one episode of BeachballSail-v0 with the scripted controller; save a GIF and stats.

    bbgym demo [--seed 16] [--out runs/demo] [--format gif]

Prints a statistics table, writes ``<out>/sail_episode.gif`` (every ``--frame-skip``-th
frame) and ``<out>/episode.json``. Runs headless (SDL's dummy video driver).
"""

from __future__ import annotations

import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import argparse
import json
import math
import time
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import bbgym  # noqa: F401  (registers BeachballSail-v0)
from bbgym.agents.sail_simple import SimpleSailController
from bbgym.cli import positive_float, positive_int, require

# Seed 16: the mark lies upwind; the controller beats to it with two tacks.
DEFAULT_SEED = 16


def sail_episode(seed: int, frame_skip: int = 2) -> tuple[dict[str, Any], list[np.ndarray]]:
    """Sail one episode; return its statistics and the rendered frames kept."""
    env = gym.make("BeachballSail-v0", render_mode="rgb_array")
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


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED, help="episode seed")
    parser.add_argument("--out", type=Path, default=Path("runs/demo"), help="output folder")
    parser.add_argument("--format", choices=["gif", "mp4"], default="gif", help="animation format")
    parser.add_argument("--frame-skip", type=positive_int, default=2, help="keep every n-th frame")
    parser.add_argument("--fps", type=positive_float, default=10.0, help="animation playback rate")


def run(args: argparse.Namespace) -> int:
    from bbgym.cli.record import check_format, open_writer

    require("pygame", "render")
    animation = args.out / f"sail_episode.{args.format}"
    check_format(animation)
    stats, frames = sail_episode(args.seed, args.frame_skip)
    print(f"BeachballSail-v0, seed {args.seed}, SimpleSailController")
    print(format_table(stats))

    args.out.mkdir(parents=True, exist_ok=True)
    writer = open_writer(animation, args.fps)
    for frame in frames:
        writer(frame)
    writer.close()
    stats_path = args.out / "episode.json"
    stats_path.write_text(json.dumps(stats, indent=2) + "\n")
    print(f"wrote {animation} ({len(frames)} frames at {args.fps:g} fps)")
    print(f"wrote {stats_path}")
    return 0
