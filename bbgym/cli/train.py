"""Train PPO or SAC on a bbgym env from its preset.

    bbgym train --env ENV_ID [--preset NAME] [--timesteps N] [--seed 0]
        [--out runs/<algo>/ENV_ID-seed0] [--resume]
    bbgym train --env ENV_ID --engine torchrl [--device cpu]
    bbgym train --env ENV_ID --engine rllib [--num-env-runners 2] [--iterations 10]
        [--address auto]

The preset (the env's shipped one, or ``--preset`` naming another by env id, name or file)
gives the env's arguments (``env``), the algorithm (``algo``: ``ppo``, the default, or
``sac``), its keyword arguments (the section of that name) and the run settings
(``train``: number of envs, budget, evaluation and checkpoint periods).

Engine ``sb3`` (default, the ``train`` extra): stable-baselines3 on the env's native vector
env through :mod:`bbgym.sb3`, with a progress bar, TensorBoard logs in ``<out>/tb``, a
periodic evaluation on separate seeds (10000 + seed; success rate and return in
``<out>/eval``, the best model as ``<out>/best_model.zip``; the end of training is always
evaluated, so a short budget still has a best model) and checkpoints in
``<out>/checkpoints`` (:mod:`bbgym.cli.checkpoints`); a preset with
``train.normalize_reward`` trains on normalized rewards and keeps their statistics in
``<out>/vecnormalize.pkl``. The final model is ``<out>/model.zip`` (SAC's replay buffer
beside it, ``<out>/replay_buffer.pkl``). Every file of the run folder is written whole or
not at all (:mod:`bbgym._files`; TensorBoard's logs, appended as they go, aside), so a
training killed at any instant leaves its last checkpoint intact, and ``--resume``
continues the run from its newest checkpoint (a finished run's is its end) up to the
budget: ``--resume --timesteps N`` trains N minus what the run has. A summary goes to
``<out>/train.json``; the terminal gets a few lines of it. A budget is rounded up to what
SB3 collects at once (PPO: rollouts of ``n_envs x n_steps``; SAC: ``n_envs x train_freq``
steps), said in one line. The training
rate (``timesteps_per_s``) counts the training alone; the evaluations' time is
``eval_time_s``. A run that ends before its first scheduled evaluation is evaluated on one
episode per evaluation env, not the preset's ``eval_episodes``: its one model is not chosen
among others.

Engine ``torchrl`` (the ``torchrl`` extra): PPO from TorchRL's ``ClipPPOLoss`` and
``GAE`` on the env's torch backend, env and policy on ``--device`` (``cpu``, ``cuda``) with
no NumPy between them (:func:`bbgym.torchrl.train_ppo`), from the preset's ``torchrl``
section; seeded and reproducible like ``sb3``, evaluated alike (``<out>/eval``), the
policies saved as ``<out>/model.pt`` and ``<out>/best_model.pt`` (which ``bbgym evaluate
--policies ppo --model`` reads).

Engine ``rejax`` (the ``rejax`` extra): rejax's SAC or PPO with the env in one
``jax.jit`` program (:mod:`bbgym.rejax`), from the preset's ``rejax`` section; the run
folder has the final policy as ``<out>/model.npz`` and the best evaluation's as
``<out>/best_model.npz`` (:class:`bbgym.mlp_policy.MLPPolicy`, which ``bbgym evaluate
--model`` reads with NumPy alone), and the evaluations made inside the program in
``<out>/eval``. ``bbgym baseline --engine rejax`` trains its seeds in one
program.

Engine ``rllib`` (the ``rllib`` extra; PPO presets): Ray RLlib's PPO on its new API stack, each env
runner stepping the env's native vector env; ``--iterations`` training iterations, a
checkpoint in ``<out>/checkpoint`` and a summary in ``<out>/rllib.json``. Without
``--address`` a local Ray starts for the run; ``--address auto`` joins the cluster of
``ray start --head`` (see the documentation's Training page, "Scale-out with Ray RLlib").
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import time
from pathlib import Path
from typing import Any

import numpy as np

from bbgym._extras import extra_needs
from bbgym._files import copy_atomic, link_or_copy, write_atomic, write_text_atomic
from bbgym.cli import (
    UsageError,
    check_device,
    env_id,
    nonnegative_int,
    positive_int,
    require_all,
)

EVAL_SEED_OFFSET = 10_000
"""Evaluation episodes use seeds far from the training ones."""

ENGINES = ("sb3", "rllib", "torchrl", "rejax")

MODEL_FILE = "model.zip"
"""The final model of a run, which ``--resume`` continues."""

VEC_NORMALIZE_FILE = "vecnormalize.pkl"
"""The reward normalizer's running statistics (``normalize_reward``), for ``--resume``."""

REPLAY_BUFFER_FILE = "replay_buffer.pkl"
"""An off-policy algorithm's (SAC's) replay buffer at the end of training, for ``--resume``."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--env", required=True, type=env_id, help="a bbgym env id")
    add_preset_arguments(parser, "sb3: the budget")
    parser.add_argument("--seed", type=int, default=0, help="training seed")
    parser.add_argument(
        "--out", type=Path, default=None, help="run folder (default runs/<engine>/<env>-seed<seed>)"
    )
    parser.add_argument(
        "--resume",
        action="store_true",
        help="sb3: continue the run in --out from its newest checkpoint up to the budget",
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_threads_argument(parser)
    parser.add_argument("--engine", choices=ENGINES, default="sb3", help="training library")
    add_device_argument(parser)
    parser.add_argument(
        "--iterations", type=positive_int, default=10, help="rllib: training iterations"
    )
    parser.add_argument(
        "--num-env-runners",
        type=nonnegative_int,
        default=2,
        help="rllib: env runner processes (0: sample in the driver)",
    )
    parser.add_argument(
        "--num-envs-per-env-runner",
        type=positive_int,
        default=None,
        help="rllib: vector env size per runner (default: n_envs)",
    )
    parser.add_argument(
        "--address", default=None, help="rllib: a Ray cluster to join ('auto' or host:port)"
    )
    parser.add_argument(
        "--num-cpus",
        type=positive_int,
        default=None,
        help="rllib: CPUs of the local Ray started without --address",
    )


def needs(args: argparse.Namespace) -> list[tuple[str, str]]:
    """``(module, extra)`` the run needs, checked before it starts (:func:`bbgym.cli.main`)."""
    return extra_needs({"sb3": "train"}.get(args.engine, args.engine))


def add_preset_arguments(parser: argparse.ArgumentParser, budget_help: str) -> None:
    """``--preset`` and ``--timesteps``: what a training follows and for how long, as
    ``bbgym train`` and ``bbgym baseline`` take them; ``budget_help`` heads the help of
    ``--timesteps``."""
    parser.add_argument(
        "--preset",
        default=None,
        help="preset: an env id, a shipped preset's name or a YAML file (default: the env's)",
    )
    parser.add_argument(
        "--timesteps",
        type=positive_int,
        default=None,
        help=f"{budget_help} (default: the preset's total_timesteps)",
    )


def add_device_argument(parser: argparse.ArgumentParser) -> None:
    """``--device`` of a torchrl training (``bbgym train``, ``bbgym baseline``)."""
    parser.add_argument(
        "--device", default="cpu", help="torchrl: the env's and the policy's device (cpu, cuda)"
    )


def add_threads_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--torch-threads",
        type=positive_int,
        default=1,
        help="torch's thread count while training (the result depends on it: pinned)",
    )


def pin_torch_threads(threads: int) -> None:
    """Set torch's intra-op thread count: a model trained with another count differs (its
    float sums are split differently), so every training entry point pins it."""
    import torch

    torch.set_num_threads(threads)


def run_provenance(seed: int, threads: int) -> dict[str, Any]:
    """What a training run's result depends on besides its preset: the seed, torch's thread
    count, the versions of the libraries, the machine and the command line."""
    import os
    import platform
    import sys
    from importlib import metadata

    def version(name: str) -> str | None:
        try:
            return metadata.version(name)
        except metadata.PackageNotFoundError:
            return None

    from bbgym import __version__  # the code's, even where an editable install is stale

    names = (
        "torch",
        "stable-baselines3",
        "gymnasium",
        "numpy",
        "ray",
        "torchrl",
        "tensordict",
        "jax",
        "rejax",
    )
    versions = {"python": platform.python_version(), "bbgym": __version__}
    return {
        "seed": seed,
        "torch_threads": threads,
        "versions": {**versions, **{n: version(n) for n in names}},
        "machine": {"platform": platform.platform(), "cpus": os.cpu_count()},
        "command": [Path(sys.argv[0]).name, *sys.argv[1:]],
    }


def run(args: argparse.Namespace) -> int:
    if args.engine == "rllib":
        return _run_rllib(args)
    if args.engine == "torchrl":
        return _run_torchrl(args)
    if args.engine == "rejax":
        return _run_rejax(args)
    if args.out is None:
        from bbgym.config import load_training

        algo = load_training(resolve_preset(args.env, args.preset)[0])[1]["algo"]
        args.out = Path("runs") / algo / f"{args.env}-seed{args.seed}"
    summary = train_sb3(
        args.env,
        preset=args.preset,
        timesteps=args.timesteps,
        seed=args.seed,
        out=args.out,
        resume=args.resume,
        progress=not args.no_progress,
        torch_threads=args.torch_threads,
    )
    print(format_summary(summary, args.out))
    return 0


def format_summary(summary: dict[str, Any], out: Path) -> str:
    """A few lines for the terminal: what was trained, how fast, the evaluations and where
    the files are (the whole summary is ``<out>/train.json``)."""
    asked = summary.get("timesteps_requested")
    trained = summary["timesteps_trained"]
    rounded = f" (asked {asked})" if asked is not None and asked != trained else ""
    models = dict.fromkeys([Path(summary["model"]).name, Path(summary["best_model"]).name])
    files = [
        *models,
        "train.json with the full summary",
        "eval/",
    ]
    if summary.get("engine") == "sb3":
        files.append("tb/")
    lines = [
        f"{summary['env']}: {summary['algo'].upper()} trained {trained} timesteps{rounded} "
        f"in {summary['train_time_s']:.1f} s, {summary['timesteps_per_s']:.0f} timesteps/s "
        "(training only)",
        f"evaluations: {summary['evaluations']} (the last of {summary['last_eval_episodes']} "
        f"episodes) in {summary['eval_time_s']:.1f} s; best mean "
        f"return {summary['best_mean_return']:.2f} at {summary['best_model_timesteps']} timesteps",
        f"wall time {summary['wall_time_s']:.1f} s; run folder {out} ({', '.join(files)})",
    ]
    return "\n".join(lines)


def budget_granule(algo_kwargs: dict[str, Any], n_envs: int) -> tuple[int | None, str]:
    """The multiple a stable-baselines3 run's timesteps come in, and why: SB3 stops only
    between collections, so ``learn(total_timesteps=N)`` trains N rounded up to it. An
    on-policy algorithm (PPO) collects whole rollouts of ``n_envs x n_steps``; an
    off-policy one (SAC) steps every env together, ``train_freq`` vector steps a
    collection. None where it collects whole episodes (``train_freq`` in episodes)."""
    from stable_baselines3.common.off_policy_algorithm import OffPolicyAlgorithm

    from bbgym.sb3 import algorithm_class

    algo_class = algorithm_class(algo_kwargs.get("algo", "ppo"))
    if not issubclass(algo_class, OffPolicyAlgorithm):
        import inspect

        default = inspect.signature(algo_class).parameters["n_steps"].default
        n_steps = int(algo_kwargs.get("n_steps", default))
        return n_envs * n_steps, f"whole rollouts of n_envs {n_envs} x n_steps {n_steps}"
    freq = algo_kwargs.get("train_freq", 1)
    if isinstance(freq, (list, tuple)):
        if str(freq[1]).startswith("episode"):
            return None, ""
        freq = freq[0]
    return n_envs * int(freq), f"the {n_envs} envs step together, train_freq {freq} step(s)"


def round_budget(algo: str, algo_kwargs: dict[str, Any], n_envs: int, budget: int) -> int:
    """The timesteps a run of ``budget`` will train (:func:`budget_granule`); prints one
    line saying so where that is more than ``budget``."""
    granule, why = budget_granule({**algo_kwargs, "algo": algo}, n_envs)
    if granule is None or budget % granule == 0:
        return budget
    rounded = -(-budget // granule) * granule
    print(
        f"{budget} timesteps round up to {rounded}: stable-baselines3 {algo.upper()} stops "
        f"only between collections of {granule} timesteps ({why})"
    )
    return rounded


def resolve_preset(env: str, preset: str | Path | None) -> tuple[Path, dict[str, Any]]:
    """:func:`bbgym.config.env_preset`, its errors as usage errors of ``--preset``."""
    from bbgym.config import env_preset

    try:
        return env_preset(env, preset)
    except ValueError as err:
        raise UsageError(f"--preset: {err}") from None


def train_sb3(
    env: str,
    *,
    preset: str | Path | None = None,
    timesteps: int | None = None,
    seed: int = 0,
    out: Path,
    resume: bool = False,
    progress: bool = True,
    torch_threads: int = 1,
) -> dict[str, Any]:
    """Train the preset's stable-baselines3 algorithm (PPO or SAC) on ``env`` into the run
    folder ``out``; return the summary also written to ``<out>/train.json``.

    Reproducible: torch runs on ``torch_threads`` threads; ``seed`` seeds the algorithm (Python's,
    NumPy's and torch's generators and the action space, through SB3's
    ``set_random_seed``), the training envs (``seed + i``) and the evaluation envs
    (``seed + 10000 + i``); the same command and seed on the same machine give the same
    model. ``train.json`` records the seed, threads, versions, machine and command."""
    require_all(extra_needs("train"))
    from bbgym.config import load_training

    path, env_kwargs = resolve_preset(env, preset)
    algo_kwargs, settings = load_training(path)
    algo = settings["algo"]
    budget = timesteps or settings["total_timesteps"]
    pin_torch_threads(torch_threads)
    if progress:
        progress = _progress_bar_available()

    out.mkdir(parents=True, exist_ok=True)
    point = resume_point(out, algo, budget) if resume else None
    copy_atomic(path, out / "config.yaml")
    gamma = algo_kwargs.get("gamma", 0.99)
    vec_env, eval_env = _training_envs(env, env_kwargs, settings, seed, gamma, point)
    evaluation, checkpoints = _training_callbacks(eval_env, settings, out, point)
    model = _load_or_build_model(algo, algo_kwargs, vec_env, seed, out, point)
    first = int(model.num_timesteps)  # 0, or where --resume continues
    round_budget(
        algo,
        {k: v for k, v in algo_kwargs.items() if k != "policy"},
        settings["n_envs"],
        budget - first,
    )
    start = time.perf_counter()
    model.learn(
        total_timesteps=budget - first,
        callback=[evaluation, checkpoints],
        progress_bar=progress,
        reset_num_timesteps=point is None,
    )
    wall = time.perf_counter() - start
    _save_run(model, out, algo, evaluation)
    shutil.rmtree(out / EVAL_SCRATCH, ignore_errors=True)
    trained = int(model.num_timesteps) - first
    train_time = max(wall - evaluation.eval_time_s, 1e-9)
    summary = {
        "env": env,
        "engine": "sb3",
        "algo": algo,
        "seed": seed,
        "timesteps": int(model.num_timesteps),
        "timesteps_requested": budget,
        "timesteps_trained": trained,
        "wall_time_s": wall,
        # The rate of training alone: the evaluations' time is reported apart.
        "train_time_s": train_time,
        "timesteps_per_s": trained / train_time,
        "eval_time_s": evaluation.eval_time_s,
        "evaluations": len(evaluation.evaluations_timesteps),
        "last_eval_episodes": len(evaluation.evaluations_results[-1]),
        "config": str(path),
        "model": str(out / MODEL_FILE),
        "best_model": str(out / "best_model.zip"),
        "best_model_timesteps": evaluation.best_timesteps,
        "best_mean_return": float(evaluation.best_mean_reward),
        **run_provenance(seed, torch_threads),
    }
    write_text_atomic(out / "train.json", json.dumps(summary, indent=2) + "\n")
    vec_env.close()
    eval_env.close()
    return summary


def _training_envs(
    env: str,
    env_kwargs: dict[str, Any],
    settings: dict[str, Any],
    seed: int,
    gamma: float,
    point: Any = None,
) -> tuple[Any, Any]:
    """The training and evaluation vector envs, seeded ``seed + i`` and
    ``seed + EVAL_SEED_OFFSET + i``, each inside a ``VecMonitor`` (the episode statistics);
    with the preset's ``normalize_reward``, also inside :func:`_normalize_reward`."""
    from stable_baselines3.common.vec_env import VecMonitor

    from bbgym.config import eval_env_count
    from bbgym.sb3 import make_sb3_vec_env

    n_envs = settings["n_envs"]
    vec_env = VecMonitor(make_sb3_vec_env(env, n_envs=n_envs, seed=seed, **env_kwargs))
    # Several envs evaluate at once: a native vector env of one is NumPy on one element.
    n_eval = eval_env_count(settings)
    eval_env = VecMonitor(
        make_sb3_vec_env(env, n_envs=n_eval, seed=seed + EVAL_SEED_OFFSET, **env_kwargs)
    )
    if settings["normalize_reward"]:
        stats = point.vecnormalize if point is not None else None
        vec_env, eval_env = _normalize_reward(vec_env, eval_env, gamma, stats)
    return vec_env, eval_env


def _training_callbacks(
    eval_env: Any, settings: dict[str, Any], out: Path, point: Any = None
) -> tuple[Any, Any]:
    """The periodic evaluation (:func:`_final_eval_callback`: the best model as
    ``<out>/best_model.zip``, the log in ``<out>/eval``; resumed from ``point``) and the
    periodic checkpoints (``<out>/checkpoints``). The preset's periods count timesteps over
    all envs; SB3's count calls, one per vector step, hence the division by ``n_envs``."""
    from bbgym.cli.checkpoints import checkpoint_callback

    n_envs = settings["n_envs"]
    evaluation = _final_eval_callback()(
        eval_env,
        out,
        n_eval_episodes=settings["eval_episodes"],
        eval_freq=max(1, settings["eval_every_timesteps"] // n_envs),
        deterministic=True,
    )
    if point is not None:
        evaluation.restore(point, n_envs)
    every = settings["checkpoint_every_timesteps"]
    checkpoints = checkpoint_callback(out, settings["algo"], every, evaluation)
    return evaluation, checkpoints


def resume_point(out: Path, algo: str, budget: int) -> Any:
    """Where ``--resume`` continues: the newest complete checkpoint of the run in ``out``
    (:func:`bbgym.cli.checkpoints.latest_checkpoint`), or the end of a run written before
    checkpoints held it (:func:`~bbgym.cli.checkpoints.finished_run`) where that is
    further; it must be short of ``budget``."""
    from bbgym.cli.checkpoints import finished_run, latest_checkpoint

    point, finished = latest_checkpoint(out, algo), finished_run(out)
    if finished is not None and (point is None or finished.timesteps > point.timesteps):
        point = finished
    if point is None:
        raise UsageError(
            f"--resume: no {algo.upper()} checkpoint in {out / 'checkpoints'} "
            "(a run of this bbgym saves one every checkpoint_every_timesteps "
            "and at its end)"
        )
    if point.timesteps >= budget:
        raise UsageError(
            f"--resume: the run in {out} has trained {point.timesteps} "
            f"timesteps, the budget is {budget}: nothing is left to train "
            "(pass a larger --timesteps)"
        )
    print(f"resuming from {point.model} at {point.timesteps} of {budget} timesteps")
    return point


def _load_or_build_model(
    algo: str, algo_kwargs: dict[str, Any], vec_env: Any, seed: int, out: Path, point: Any
) -> Any:
    """The model to train: the checkpoint ``point``'s model (and SAC's replay buffer)
    where ``--resume`` gives one; else a new ``algo`` model from the preset's keyword
    arguments, seeded with ``seed``, on the CPU. Both log to ``<out>/tb``."""
    from bbgym.sb3 import algorithm_class, load_model

    if point is not None:
        model = load_model(
            point.model, algo, "--resume:", env=vec_env, tensorboard_log=str(out / "tb")
        )
        if point.replay_buffer is not None:
            model.load_replay_buffer(point.replay_buffer)
        return model
    kwargs = dict(algo_kwargs)
    policy = kwargs.pop("policy")
    return algorithm_class(algo)(
        policy,
        vec_env,
        seed=seed,
        device="cpu",
        tensorboard_log=str(out / "tb"),
        verbose=0,
        **kwargs,
    )


def _save_run(model: Any, out: Path, algo: str, evaluation: Any) -> None:
    """The end of training as a checkpoint (what ``--resume`` continues from), and the
    run's final model, an off-policy algorithm's (SAC's) replay buffer and the reward
    normalizer's statistics as links to its files."""
    from bbgym.cli.checkpoints import save_checkpoint

    final = save_checkpoint(model, out, algo, evaluation)
    link_or_copy(final.model, out / MODEL_FILE)
    if final.replay_buffer is not None:
        link_or_copy(final.replay_buffer, out / REPLAY_BUFFER_FILE)
    if final.vecnormalize is not None:
        link_or_copy(final.vecnormalize, out / VEC_NORMALIZE_FILE)


def _normalize_reward(
    vec_env: Any, eval_env: Any, gamma: float, stats_path: Path | None = None
) -> tuple[Any, Any]:
    """SB3's ``VecNormalize`` on the rewards only (the observations are already scaled):
    each reward is divided by the running standard deviation of the discounted return (RL
    Zoo's ``norm_reward``). On Sail-v1 it is what let every training seed learn to beat to
    windward (the documentation's Baselines page). The episode statistics stay raw
    (``VecMonitor`` is inside), and ``--resume`` continues the saved ``stats_path``. The
    evaluation env is wrapped alike, as SB3's evaluation expects, but scores the env's own
    rewards."""
    from stable_baselines3.common.vec_env import VecNormalize

    if stats_path is not None:
        train_env = VecNormalize.load(str(stats_path), vec_env)
    else:
        train_env = VecNormalize(vec_env, norm_obs=False, norm_reward=True, gamma=gamma)
    return train_env, VecNormalize(eval_env, training=False, norm_obs=False, norm_reward=False)


def _progress_bar_available() -> bool:
    """SB3's progress bar needs tqdm and rich (the ``train`` extra has them)."""
    import importlib.util

    return all(importlib.util.find_spec(m) is not None for m in ("tqdm", "rich"))


EVAL_SCRATCH = ".eval-scratch"
"""Where SB3's evaluation writes its files before they are renamed into the run folder."""


def _final_eval_callback() -> type:
    """SB3's ``EvalCallback`` that also evaluates at the end of training (unless the last
    periodic evaluation was at that very timestep), remembers when its best model was
    saved, writes its files whole (SB3 writes them in ``<out>/.eval-scratch``, renamed
    into place: ``<out>/eval/evaluations.npz``, ``<out>/best_model.zip``) and resumes from
    a checkpoint. Without it a budget shorter than the evaluation period saves no best
    model."""
    from stable_baselines3.common.callbacks import EvalCallback

    class FinalEvalCallback(EvalCallback):
        best_timesteps: int | None = None
        eval_time_s: float = 0.0
        """Seconds spent evaluating (and saving the best model), apart from training."""

        def __init__(self, eval_env: Any, out: Path, **kwargs: Any) -> None:
            self.out = out
            scratch = str(out / EVAL_SCRATCH)
            super().__init__(eval_env, log_path=scratch, best_model_save_path=scratch, **kwargs)

        def state(self) -> dict[str, Any]:
            """What a checkpoint keeps of the evaluation (its log is the run's own)."""
            return {
                "best_mean_reward": float(self.best_mean_reward),
                "best_timesteps": self.best_timesteps,
            }

        def restore(self, point: Any, n_envs: int) -> None:
            """Continue from the checkpoint ``point``: its best model and best return, the
            log's evaluations up to it, and the evaluation schedule where it was."""
            import numpy as np

            log = self.out / "eval" / "evaluations.npz"
            if log.exists():
                with np.load(log, allow_pickle=True) as saved:
                    keep = [i for i, t in enumerate(saved["timesteps"]) if t <= point.timesteps]
                    self.evaluations_timesteps = [int(saved["timesteps"][i]) for i in keep]
                    self.evaluations_results = [list(saved["results"][i]) for i in keep]
                    self.evaluations_length = [list(saved["ep_lengths"][i]) for i in keep]
                    if "successes" in saved:
                        self.evaluations_successes = [list(saved["successes"][i]) for i in keep]
            self.best_mean_reward = point.eval_state.get("best_mean_reward", -np.inf)
            self.best_timesteps = point.eval_state.get("best_timesteps")
            if "best_mean_reward" not in point.eval_state and self.evaluations_results:
                # An older run's end: its best is the log's (SB3 keeps the first of equals).
                means = [float(np.mean(r)) for r in self.evaluations_results]
                best = int(np.argmax(means))
                self.best_mean_reward = means[best]
                self.best_timesteps = self.evaluations_timesteps[best]
            if point.best_model is not None:
                link_or_copy(point.best_model, self.out / "best_model.zip")
            self.n_calls = point.timesteps // n_envs  # SB3 evaluates every eval_freq calls

        def _on_step(self) -> bool:
            best, evaluations = self.best_mean_reward, len(self.evaluations_timesteps)
            start = time.perf_counter()
            keep_going = super()._on_step()
            scratch = self.out / EVAL_SCRATCH
            if len(self.evaluations_timesteps) > evaluations:
                (self.out / "eval").mkdir(exist_ok=True)
                os.replace(scratch / "evaluations.npz", self.out / "eval" / "evaluations.npz")
            if self.best_mean_reward > best:
                self.best_timesteps = int(self.num_timesteps)
                os.replace(scratch / "best_model.zip", self.out / "best_model.zip")
            self.eval_time_s += time.perf_counter() - start
            return keep_going

        def _on_training_end(self) -> None:
            if self.evaluations_timesteps and self.evaluations_timesteps[-1] == self.num_timesteps:
                return
            # A run that ended before its first scheduled evaluation has one model only:
            # the evaluation chooses nothing, it only gives best_model.zip (which baseline
            # and evaluate read) and one point of the learning curve. It runs one episode
            # per evaluation env (one batch), not the preset's eval_episodes: a 10-step
            # smoke run does not spend 13 s on 50 episodes. A run that had scheduled
            # evaluations gets a full one, comparable with them for the best model.
            episodes = self.n_eval_episodes
            if not self.evaluations_timesteps:
                self.n_eval_episodes = min(episodes, self.eval_env.num_envs)
            period, self.eval_freq = self.eval_freq, 1  # n_calls % 1 == 0: evaluate now
            try:
                self._on_step()
            finally:
                self.eval_freq, self.n_eval_episodes = period, episodes

    return FinalEvalCallback


def _run_rllib(args: argparse.Namespace) -> int:
    require_all(extra_needs("rllib"))
    from bbgym import rllib
    from bbgym.config import load_training

    if args.resume:
        raise UsageError("--resume is for --engine sb3")
    out = args.out or Path("runs") / "rllib" / f"{args.env}-seed{args.seed}"
    path, env_kwargs = resolve_preset(args.env, args.preset)
    algo = load_training(path)[1]["algo"]
    if algo != "ppo":
        raise UsageError(f"--engine rllib trains PPO presets; {path.name} trains {algo} (algo)")
    summary = rllib.train(
        args.env,
        learner_threads=args.torch_threads,
        iterations=args.iterations,
        num_env_runners=args.num_env_runners,
        num_envs_per_env_runner=args.num_envs_per_env_runner,
        seed=args.seed,
        out=out,
        address=args.address,
        num_cpus=args.num_cpus,
        env_kwargs=env_kwargs,
        preset=path,
        callback=_print_iteration,
    )
    # What the result depends on, beside the summary bbgym.rllib wrote.
    summary.update(run_provenance(args.seed, args.torch_threads))
    write_text_atomic(out / rllib.SUMMARY_FILE, json.dumps(summary, indent=2, default=str) + "\n")
    print(json.dumps({k: v for k, v in summary.items() if k != "history"}, indent=2, default=str))
    return 0


def _print_iteration(row: dict[str, Any]) -> None:
    """One line per RLlib training iteration."""
    print(", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in row.items()))


def _run_torchrl(args: argparse.Namespace) -> int:
    if args.resume:
        raise UsageError("--resume is for --engine sb3")
    out = args.out or Path("runs") / "torchrl" / f"{args.env}-seed{args.seed}"
    summary = train_torchrl(
        args.env,
        preset=args.preset,
        timesteps=args.timesteps,
        seed=args.seed,
        out=out,
        device=args.device,
        torch_threads=args.torch_threads,
    )
    print(format_summary(summary, out))
    return 0


def _run_rejax(args: argparse.Namespace) -> int:
    if args.resume:
        raise UsageError("--resume is for --engine sb3")
    out = args.out or Path("runs") / "rejax" / f"{args.env}-seed{args.seed}"
    summary = train_rejax(
        args.env, preset=args.preset, timesteps=args.timesteps, folders={args.seed: out}
    )[args.seed]
    print(format_summary(summary, out))
    return 0


def rejax_settings(path: Path) -> dict[str, Any]:
    """:func:`bbgym.config.load_rejax`, its errors as usage errors of ``--preset``."""
    from bbgym.config import load_rejax

    return _section(load_rejax, path)


def _section(load: Any, path: Path) -> dict[str, Any]:
    """An engine's section of the preset ``path`` by ``load``, a ``ValueError`` turned into
    a usage error of ``--preset``."""
    try:
        return load(path)
    except ValueError as err:
        raise UsageError(f"--preset: {err}") from None


def train_rejax(
    env: str,
    *,
    folders: dict[int, Path],
    preset: str | Path | None = None,
    timesteps: int | None = None,
) -> dict[int, dict[str, Any]]:
    """Train rejax's algorithm on ``env`` for every seed of ``folders`` in one compiled
    program (:func:`bbgym.rejax.train`), from the preset's ``rejax`` section and its env
    arguments; write each seed's run folder (``model.npz``, ``eval/evaluations.npz`` in
    stable-baselines3's layout, ``best_model.npz``: the policy of the evaluation with the
    highest mean return, ``config.yaml``, ``train.json``).

    Args:
        env: a bbgym id.
        folders: training seed -> its run folder.
        preset: the preset (None: the env's).
        timesteps: the budget per seed (None: the section's).

    Returns:
        Each seed's summary (its ``train.json``). Its wall and training times are the
        program's shared among the seeds: one program trains them all.
    """
    require_all(extra_needs("rejax"))
    path, env_kwargs = resolve_preset(env, preset)
    settings = rejax_settings(path)
    from bbgym import rejax

    try:
        algorithm_kwargs = rejax.algorithm_settings(settings)
    except ValueError as err:
        raise UsageError(f"--preset {path}: {err}") from None
    start = time.perf_counter()
    result = rejax.train(env, settings, list(folders), timesteps=timesteps, env_kwargs=env_kwargs)
    wall = time.perf_counter() - start
    share = len(folders)
    summaries = {}
    for seed, out in folders.items():
        out.mkdir(parents=True, exist_ok=True)
        (out / "eval").mkdir(exist_ok=True)
        copy_atomic(path, out / "config.yaml")
        write_atomic(out / "model.npz", result.policies[seed].save)
        best_policy = result.best_policies[seed]
        write_atomic(out / "best_model.npz", best_policy.save)
        curve = result.evaluations[seed]
        write_atomic(
            out / "eval" / "evaluations.npz",
            lambda file, curve=curve: _save_evaluations(file, curve),
        )
        last_returns = curve["returns"][-1]
        best = list(curve["timesteps"]).index(best_policy.meta["timesteps"])
        summary = {
            "env": env,
            "engine": "rejax",
            "algo": settings["algo"],
            "seed": seed,
            "seeds_in_program": list(folders),
            "timesteps": result.timesteps,
            "timesteps_requested": timesteps or settings["total_timesteps"],
            "timesteps_trained": result.timesteps,
            "wall_time_s": wall / share,
            "train_time_s": result.train_time_s / share,
            "timesteps_per_s": result.timesteps * share / result.train_time_s,
            "compile_time_s": result.compile_time_s,
            "program_wall_time_s": wall,
            # Inside the program, part of its training time: not measured apart.
            "eval_time_s": 0.0,
            "evaluations": len(curve["timesteps"]),
            "last_eval_episodes": len(last_returns),
            "last_success_rate": float(np.mean(curve["successes"][-1])),
            "model": str(out / "model.npz"),
            "best_model": str(out / "best_model.npz"),
            "best_model_timesteps": int(curve["timesteps"][best]),
            "best_mean_return": float(curve["returns"][best].mean()),
            "config": str(path),
            "settings": {**result.algorithm, "algorithm_kwargs": algorithm_kwargs},
            **run_provenance(seed, 1),
        }
        write_text_atomic(out / "train.json", json.dumps(summary, indent=2) + "\n")
        summaries[seed] = summary
    return summaries


def _save_evaluations(file: Path, curve: dict[str, np.ndarray]) -> None:
    """stable-baselines3's ``evaluations.npz`` layout, which the learning curves read."""
    with open(file, "wb") as f:
        np.savez(
            f,
            timesteps=curve["timesteps"],
            results=curve["returns"],
            ep_lengths=curve["lengths"],
            successes=curve["successes"],
        )


def torchrl_settings(path: Path) -> dict[str, Any]:
    """:func:`bbgym.config.load_torchrl`, its errors as usage errors of ``--preset``."""
    from bbgym.config import load_torchrl

    return _section(load_torchrl, path)


def train_torchrl(
    env: str,
    *,
    preset: str | Path | None = None,
    timesteps: int | None = None,
    seed: int = 0,
    out: Path,
    device: str = "cpu",
    torch_threads: int = 1,
) -> dict[str, Any]:
    """Train PPO with TorchRL on ``env``'s torch backend, env and policy on ``device``
    (:func:`bbgym.torchrl.train_ppo`), from the preset's ``torchrl`` section
    (:func:`bbgym.config.load_torchrl`) and its env arguments, into the run folder ``out``;
    return the summary written to ``<out>/train.json`` (with the seed, threads, versions,
    machine and command)."""
    require_all(extra_needs("torchrl"))
    check_device(device, "--device")

    path, env_kwargs = resolve_preset(env, preset)
    settings = torchrl_settings(path)
    pin_torch_threads(torch_threads)
    from bbgym import torchrl

    out.mkdir(parents=True, exist_ok=True)
    copy_atomic(path, out / "config.yaml")
    summary = torchrl.train_ppo(
        env, settings, out=out, seed=seed, device=device, timesteps=timesteps, env_kwargs=env_kwargs
    )
    summary.update(config=str(path), **run_provenance(seed, torch_threads))
    write_text_atomic(out / "train.json", json.dumps(summary, indent=2) + "\n")
    return summary
