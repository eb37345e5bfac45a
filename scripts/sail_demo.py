"""Sail one episode of BeachballSail-v0 with the scripted controller; save a GIF and stats.

    python scripts/sail_demo.py [--seed 16] [--out runs/demo] [--format gif]

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
import sys
import time
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from bbgym.agents.sail_simple import SimpleSailController  # noqa: E402

import bbgym  # noqa: E402, F401  (registers BeachballSail-v0)

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


def write_gif(path: Path, frames: list[np.ndarray], fps: float) -> None:
    """Write frames (H, W, 3) uint8 as a looping GIF."""
    from PIL import Image

    images = [Image.fromarray(np.asarray(f, dtype=np.uint8)) for f in frames]
    duration_ms = int(round(1000.0 / fps))
    images[0].save(
        path,
        save_all=True,
        append_images=images[1:],
        duration=duration_ms,
        loop=0,
        optimize=False,
    )


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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED, help="episode seed")
    parser.add_argument("--out", type=Path, default=Path("runs/demo"), help="output folder")
    parser.add_argument("--format", choices=["gif"], default="gif", help="animation format")
    parser.add_argument("--frame-skip", type=int, default=2, help="keep every n-th frame")
    parser.add_argument("--fps", type=float, default=10.0, help="animation playback rate")
    args = parser.parse_args(argv)
    if args.frame_skip < 1:
        parser.error("--frame-skip must be >= 1")
    if args.fps <= 0:
        parser.error("--fps must be > 0")

    stats, frames = sail_episode(args.seed, args.frame_skip)
    print(f"BeachballSail-v0, seed {args.seed}, SimpleSailController")
    print(format_table(stats))

    args.out.mkdir(parents=True, exist_ok=True)
    animation = args.out / f"sail_episode.{args.format}"
    write_gif(animation, frames, args.fps)
    stats_path = args.out / "episode.json"
    stats_path.write_text(json.dumps(stats, indent=2) + "\n")
    print(f"wrote {animation} ({len(frames)} frames at {args.fps:g} fps)")
    print(f"wrote {stats_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
