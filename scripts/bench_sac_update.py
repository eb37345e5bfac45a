"""Developer tool: the time of one SAC gradient update (SB3's ``SAC.train``) with each
preset's networks and batch, best of ``--repeats`` runs of ``--updates`` updates with the
presets interleaved, on ``--threads`` torch threads (the Baselines page's "How long `make
run` takes"). The updates set a SAC training's time on a CPU; their ratio, measured in one
run, says how much of it a preset saves on any machine.

    python scripts/bench_sac_update.py [--presets BeachballSail-v1,beachball_sail_v1_quick]
        [--repeats 5] [--updates 200] [--threads 2]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path
from typing import Any

import torch

from bbgym.cli.train import _load_or_build_model, _training_envs, resolve_preset
from bbgym.config import load_training

ENV = "BeachballSail-v1"
FILLED_TIMESTEPS = 12_000
"""Steps collected before timing: past the presets' ``learning_starts`` (10,000), so the
replay buffer holds real transitions and the updates have run."""


def model_after_warm_up(preset: str, folder: Path) -> Any:
    """A SAC model of ``preset`` on its training envs (seed 0), trained a little."""
    path, env_kwargs = resolve_preset(ENV, preset)
    algo_kwargs, settings = load_training(path)
    if settings["algo"] != "sac":
        raise SystemExit(f"--presets: {preset} trains {settings['algo']}, not SAC")
    vec_env, eval_env = _training_envs(ENV, env_kwargs, settings, 0, algo_kwargs["gamma"])
    eval_env.close()
    model = _load_or_build_model("sac", algo_kwargs, vec_env, 0, folder / preset, None)
    model.learn(total_timesteps=FILLED_TIMESTEPS)
    return model


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--presets", default=f"{ENV},beachball_sail_v1_quick")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--updates", type=int, default=200)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    with tempfile.TemporaryDirectory() as folder:
        models = {p: model_after_warm_up(p, Path(folder)) for p in args.presets.split(",")}
        best = dict.fromkeys(models, float("inf"))
        for _ in range(args.repeats):
            for preset, model in models.items():
                start = time.perf_counter()
                model.train(gradient_steps=args.updates, batch_size=model.batch_size)
                best[preset] = min(best[preset], (time.perf_counter() - start) / args.updates)
    first = next(iter(best.values()))
    for preset, seconds in best.items():
        print(f"{preset}: {seconds * 1e3:.2f} ms an update ({seconds / first:.2f} of the first)")


if __name__ == "__main__":
    main()
