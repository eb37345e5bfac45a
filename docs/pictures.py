"""Draw the env and scene pictures of the README and the site (docs/pages/img/*.png).

    python docs/pictures.py [NAME ...]

Each env picture is the env's own ``render_mode="rgb_array"`` frame, a few steps into a
seeded episode played by its scripted agent (the race's: every boat the scripted racer);
each scene picture (``scene-*``) is a frame of the scene's view (:mod:`bbgym.scenes.view`)
at a step, or for the bouncing balls their energy over the run (matplotlib). All are
scaled down and saved as palette PNGs (tens of KB).
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
    # file stem: (env id, seed, steps of the scripted agent before the frame): each family's
    # newest version (the sail's with its jib, waves and current)
    "sail": ("BeachballSail-v2", 3, 60),
    "throw": ("BeachballThrow-v1", 0, 1),
    "curve": ("BeachballCurve-v2", 0, 1),
    "topple": ("BeachballTopple-v2", 1, 3),
}
RACE_PICTURE = ("race", 3, 300)
"""(file stem, seed, steps): the race (bbgym/BeachballRace-v0, the PettingZoo env), every
boat the scripted racer, 45 s after the start: the fleet on the first beat, boat 1's
wind shadow over boat 2."""


SCENE_FRAMES = {
    # file stem: (scene, the step drawn)
    "scene-push": ("push", 30),
    "scene-arrow": ("arrow", 36),
    "scene-arrow-2": ("arrow-2", 40),
    "scene-double-bounce": ("double-bounce", 560),
    "scene-rotation-box": ("rotation-box", 150),
    "scene-double-bounce-2": ("double-bounce-2", 520),
    "scene-plank-free": ("plank-free", 120),
    "scene-plank-anchored": ("plank-anchored", 120),
    "scene-many-beachballs": ("many-beachballs", 300),
    "scene-many-beachballs-bad": ("many-beachballs-bad", 300),
    "scene-sproing-cloth": ("sproing-cloth", 480),
    "scene-gerstner": ("gerstner", 20),
    "scene-dam-break": ("dam-break", 300),
    "scene-dam-break-settled": ("dam-break", 2652),
    "scene-sliding-block-2": ("sliding-block-2", 60),
    "scene-points-of-sail": ("points-of-sail", 1200),
    "scene-bowling-balls": ("bowling-balls", 150),
    "scene-falling-wall": ("falling-wall", 70),
    "scene-confetti": ("confetti", 360),
    "scene-aeroplane": ("aeroplane", 750),
}
SCENE_ENERGY = {
    # file stem: (scene, its parameters, a log scale, the measure drawn)
    "scene-three-beachballs-1": ("three-beachballs-1", {}, False, "energy_jpkg"),
    "scene-three-beachballs-1a": ("three-beachballs-1a", {}, False, "energy_jpkg"),
    "scene-three-beachballs-2": ("three-beachballs-2", {}, False, "energy_jpkg"),
    "scene-sproing": ("sproing", {"damping_nspm": 0.0}, True, "energy_j"),
    "scene-sliding-block": ("sliding-block", {"blocks": 3}, False, "velocity_mps"),
    "scene-golf-ball": ("golf-ball", {}, False, "velocity_mps"),
    "scene-rolling-ball": ("rolling-ball", {}, True, "speed_mps"),
    "scene-magnus": ("magnus", {}, False, "height_m"),
    "scene-turbulence": ("turbulence", {}, False, "fall_speed_mps"),
    "scene-turbulence-drift": ("turbulence", {}, False, "drift_speed_mps"),
    "scene-confetti-tilt": ("confetti", {"wind_speed_mps": 0.0}, False, "tilt_deg"),
    "scene-aeroplane-altitude": ("aeroplane", {}, False, "altitude_m"),
}
"""Scenes pictured by a measure of each body over the run."""
LABELS = {
    "tilt_deg": "tilt of the normal (deg)",
    "altitude_m": "altitude (m)",
    "energy_jpkg": "energy per kg (J/kg)",
    "energy_j": "energy (J)",
    "velocity_mps": "velocity (m/s)",
    "height_m": "height (m)",
    "fall_speed_mps": "fall speed (m/s)",
    "drift_speed_mps": "drift along the wind (m/s)",
    "speed_mps": "speed (m/s)",
}


def scene_frame(name: str, step: int):
    from bbgym.scenes import get_scene, simulate
    from bbgym.scenes.view import SceneView

    scene = get_scene(name)
    states = []
    run = simulate(scene, steps=step, on_step=lambda p, state: states.append(state))
    view = SceneView(scene, run.params)
    picture = view.render((run.times_s[-1], scene.frame(run.params, states[-1])))
    view.close()
    return picture


def scene_energy(name: str, params: dict, log: bool, key: str, path: Path) -> None:
    """A measure (an energy, a velocity) of each body of a scene over its run."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from bbgym.scenes import get_scene, simulate

    scene = get_scene(name)
    run = simulate(scene, params)
    fig, ax = plt.subplots(figsize=(6.4, 3.2), dpi=100)
    for k, body in enumerate(scene.names(run.params)):
        ax.plot(run.times_s, run.measures[key][:, k], label=body, linewidth=1.2)
    ax.set_xlabel("time (s)")
    ax.set_ylabel(LABELS[key])
    if log:
        ax.set_yscale("log")
    settings = ", ".join(f"{k} {v:g}" for k, v in params.items())
    ax.set_title(
        f"{scene.section} {scene.title}" + (f" ({settings})" if settings else ""), fontsize=10
    )
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    Image.open(path).convert("RGB").quantize(colors=64).save(path, optimize=True)


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


def race_frame(seed: int, steps: int):
    """The race's ``rgb_array`` frame ``steps`` steps (0.25 s each) into a seeded race of
    scripted racers (their autopilot's polar takes seconds first: it says so on stderr)."""
    from bbgym.agents import RaceRacer

    from bbgym.envs.race.parallel import BeachballRaceEnv

    env = BeachballRaceEnv(render_mode="rgb_array")
    racer = RaceRacer.for_env(env)
    observations, _ = env.reset(seed=seed)
    racer.reset()
    for _ in range(steps):
        if not env.agents:
            break
        observations, *_ = env.step(racer.actions(observations, list(env.agents)))
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
    race, race_seed, race_steps = RACE_PICTURE
    for name in names or [*PICTURES, race, *SCENE_FRAMES, *SCENE_ENERGY]:
        path = OUT / f"{name}.png"
        if name == race:
            save(race_frame(race_seed, race_steps), path)
            what = f"bbgym/BeachballRace-v0, seed {race_seed}, {race_steps} steps"
        elif name in SCENE_FRAMES:
            scene, step = SCENE_FRAMES[name]
            save(scene_frame(scene, step), path)
            what = f"scene {scene}, step {step}"
        elif name in SCENE_ENERGY:
            scene, params, log, key = SCENE_ENERGY[name]
            scene_energy(scene, params, log, key, path)
            what = f"scene {scene} {params or ''}, {key} over its run"
        else:
            env_id, seed, steps = PICTURES[name]
            save(frame(env_id, seed, steps), path)
            what = f"{env_id}, seed {seed}, {steps} steps"
        print(f"{path}: {what}, {path.stat().st_size // 1024} KB")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
