"""Draw the env pictures of the README and the site (docs/pages/img/*.png).

    python docs/pictures.py

Each picture is the env's own ``render_mode="rgb_array"`` frame, a few steps into a seeded
episode played by its scripted agent, scaled down and saved as a palette PNG (tens of KB).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import gymnasium as gym
from PIL import Image

import bbgym  # noqa: F401  (registers the ids)

OUT = Path(__file__).resolve().parent / "pages" / "img"
WIDTH = 480
"""Width of a saved picture in pixels (the frames are 640 x 480)."""

PICTURES = {
    # file stem: (env id, seed, steps of the scripted agent before the frame)
    "sail": ("BeachballSail-v1", 3, 200),
    "throw": ("BeachballThrow-v0", 0, 1),
    "curve": ("BeachballCurve-v1", 0, 1),
    "topple": ("BeachballTopple-v1", 1, 3),
}


def scripted(env: gym.Env):
    from bbgym.cli.evaluate import make_policy

    return make_policy("scripted", env, None, 0)


def frame(env_id: str, seed: int, steps: int):
    env = gym.make(env_id, render_mode="rgb_array")
    obs, _ = env.reset(seed=seed)
    policy = scripted(env)
    if hasattr(policy, "reset"):
        policy.reset()
    for _ in range(steps):
        obs, _, terminated, truncated, _ = env.step(policy(obs))
        if terminated or truncated:
            break
    picture = env.render()
    env.close()
    return picture


def save(picture, path: Path) -> None:
    image = Image.fromarray(picture)
    height = round(image.height * WIDTH / image.width)
    image = image.resize((WIDTH, height), Image.LANCZOS)
    image.quantize(colors=128, method=Image.Quantize.MEDIANCUT).save(path, optimize=True)


def main(names: list[str]) -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    for name in names or list(PICTURES):
        env_id, seed, steps = PICTURES[name]
        path = OUT / f"{name}.png"
        save(frame(env_id, seed, steps), path)
        print(f"{path}: {env_id}, seed {seed}, {steps} steps, {path.stat().st_size // 1024} KB")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
