"""Smoke test of an installed bbgym (a wheel in a fresh virtual environment, run from a
folder outside the checkout): what a user gets from ``pip install bbgym``.

    python scripts/smoke_installed.py [--out DIR]

Checks, printing one line each: the package imports from site-packages (not from a
checkout) and is its only top-level package; every registered id makes, resets and steps
(single and native vector env); every shipped preset loads by env id and by name and
builds its env; ``bbgym --help``, ``python -m bbgym --help`` and every subcommand's
``--help`` exit 0; a short scripted evaluation writes its table. Exit status 1 on the first
failure, with what failed. Needs only bbgym's core dependencies.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from importlib import metadata
from pathlib import Path


def check(condition: bool, what: str) -> None:
    if not condition:
        raise SystemExit(f"FAILED: {what}")
    print(f"ok  {what}")


def run(*argv: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy", "PYTHONPATH": ""}
    return subprocess.run(argv, cwd=cwd, env=env, capture_output=True, text=True, timeout=600)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None, help="work folder (default: a temp)")
    args = parser.parse_args(argv)
    work = args.out or Path(tempfile.mkdtemp(prefix="bbgym-smoke-"))
    work.mkdir(parents=True, exist_ok=True)
    os.chdir(work)  # nothing of a checkout on the path

    import gymnasium as gym
    import numpy as np

    import bbgym
    from bbgym.cli import COMMANDS, bbgym_env_ids
    from bbgym.config import load_preset, preset_files

    location = Path(bbgym.__file__).resolve()
    check("site-packages" in location.parts, f"bbgym imports from site-packages ({location})")
    files = metadata.files("bbgym") or []
    roots = {f.parts[0] for f in files if f.suffix == ".py"}
    check(roots == {"bbgym"}, f"the only top-level package is bbgym ({sorted(roots)})")

    ids = bbgym_env_ids()
    check(len(ids) >= 4, f"registered ids: {', '.join(ids)}")
    for env_id in ids:
        env = gym.make(env_id)
        obs, _ = env.reset(seed=0)
        obs, reward, *_ = env.step(env.action_space.sample())
        check(env.observation_space.contains(obs) and np.isfinite(reward), f"{env_id} steps")
        env.close()
        venv = gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point")
        obs, _ = venv.reset(seed=0)
        obs, *_ = venv.step(venv.action_space.sample())
        check(obs.shape[0] == 2 and np.isfinite(obs).all(), f"{env_id} native vector env steps")
        venv.close()

    for env_id, name in preset_files().items():
        for key in (env_id, Path(name).stem):
            preset_id, kwargs = load_preset(key)
            kwargs.pop("max_episode_steps", None)
            env = gym.make(preset_id, **kwargs)
            env.reset(seed=0)
            env.close()
            named = preset_id == env_id or key != env_id  # an id gives that id's kwargs
            check(named, f"preset {key!r} loads as {preset_id} and builds")

    bbgym_command = shutil.which("bbgym")
    check(bbgym_command is not None, f"the bbgym console command is installed ({bbgym_command})")
    for prefix in ([bbgym_command], [sys.executable, "-m", "bbgym"]):
        done = run(*prefix, "--help", cwd=work)
        check(done.returncode == 0 and "baseline" in done.stdout, f"{prefix[-1]} --help")
    for command in COMMANDS:
        done = run(bbgym_command, command, "--help", cwd=work)
        failure = "" if done.returncode == 0 else ": " + done.stderr[-500:]
        check(done.returncode == 0 and "default" in done.stdout, f"bbgym {command} --help{failure}")
    done = run(bbgym_command, "evaluate", "--env", "NoSuchEnv-v0", cwd=work)
    check(done.returncode == 2 and "unknown env id" in done.stderr, "an unknown env id is named")

    out = work / "eval"
    done = run(
        bbgym_command,
        "evaluate",
        "--env",
        "BeachballThrow-v0",
        "--policies",
        "random,scripted",
        "--episodes",
        "2",
        "--out",
        str(out),
        cwd=work,
    )
    failure = "" if done.returncode == 0 else ": " + done.stderr[-2000:]
    check(done.returncode == 0, f"bbgym evaluate runs{failure}")
    results = json.loads((out / "BeachballThrow-v0.json").read_text())
    check(
        [r["policy"] for r in results] == ["random", "scripted"]
        and all(r["episodes"] == 2 for r in results),
        "the evaluation table has both policies",
    )
    print("smoke test passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
