"""Train the preset's algorithm (PPO or SAC) on a bbgym env over several seeds, evaluate it
beside random and scripted play, write a run folder.

    bbgym baseline --env ENV_ID [--preset NAME] [--timesteps N]
        [--seed 0] [--seeds 5] [--jobs 1] [--episodes 100] [--torch-threads 1]
        [--engine sb3|torchrl] [--device cpu] [--out runs/baseline/<env>] [--no-train]

The main job (``make run``, see the Makefile) is this command on the sailing env with its
quick preset (``beachball_sail_v2_quick``) and one training seed. Steps, each reported as
it goes:

1. train as ``bbgym train`` does (the preset's ``algo``, its section and ``train``; with
   ``--engine torchrl``, TorchRL's PPO from its ``torchrl`` section on ``--device``; with
   ``--engine rejax``, rejax's algorithm from its ``rejax`` section, every seed in one JAX
   program), once per training seed ``seed .. seed + seeds - 1``, into ``<out>/seed<k>``
   (``--jobs`` trainings at once, each on ``--torch-threads`` threads); ``--no-train``
   skips this and evaluates the models already there;
2. evaluate each seed's best model of training (``best_model.zip``, or ``best_model.pt`` of
   ``--engine torchrl``; chosen on the evaluation seeds 10000+; or its final model, where
   the preset's ``train.evaluate_model`` is ``final``; ``best_model.npz`` of ``--engine
   rejax``), a
   uniform random policy and the env's scripted agent (the VMG autopilot for sailing) over
   the same ``--episodes`` seeded episodes (seeds ``0 .. episodes-1``, apart from
   training's), with the breakdown of failures;
3. write into the run folder: ``results.md`` and ``results.json`` (per policy and per
   training seed: success with a 95% interval, return, length, time to mark, time / oracle
   time, failures; for the learnt policy over the seeds: the mean, the worst seed and the
   95% interval of the mean over seeds), ``learning_curve.png`` (of the first seed; each
   seed's in its folder), ``episode.gif`` (one episode of the first seed's policy) and
   ``summary.json`` (budget, wall times, steps per second, seeds, threads, versions,
   command).
"""

from __future__ import annotations

import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import argparse
import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import bbgym  # noqa: F401  (registers the ids)
from bbgym._extras import extra_needs
from bbgym._files import copy_atomic, write_atomic, write_text_atomic
from bbgym.cli import UsageError, env_id, evaluate, positive_int, record, require_all, train
from bbgym.spec import base_ids, spec_of


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--env", default=base_ids()[0], type=env_id, help="a bbgym env id")
    train.add_preset_arguments(parser, "training budget")
    parser.add_argument("--seed", type=int, default=0, help="first training seed")
    parser.add_argument("--seeds", type=positive_int, default=5, help="training seeds")
    parser.add_argument(
        "--jobs",
        type=positive_int,
        default=1,
        help="trainings at once (processes; each on --torch-threads)",
    )
    parser.add_argument("--episodes", type=positive_int, default=100, help="evaluation episodes")
    parser.add_argument(
        "--out", type=Path, default=None, help="run folder (default runs/baseline/<env>)"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    train.add_threads_argument(parser)
    parser.add_argument(
        "--engine",
        choices=("sb3", "torchrl", "rejax"),
        default="sb3",
        help="training library (torchrl: PPO on the env's torch backend, the "
        "preset's torchrl section; rejax: the seeds in one JAX program, the preset's rejax "
        "section)",
    )
    train.add_device_argument(parser)
    parser.add_argument(
        "--no-train", action="store_true", help="skip training: evaluate the run folder's model"
    )


def needs(args: argparse.Namespace) -> list[tuple[str, str]]:
    """``(module, extra)`` the run needs, checked before training starts: training
    (``train``), the learning curves (``plots``) and the recorded episode (``render`` to
    draw it, Pillow of ``plots`` to write the GIF)."""
    learner = {"sb3": "train"}.get(args.engine, args.engine)
    return extra_needs(learner, "plots", "render")


def best_model_index(timesteps: np.ndarray, mean_returns: np.ndarray, train_log: dict) -> int:
    """Which evaluation's model is ``best_model.zip``: the one at the log's
    ``best_model_timesteps`` (``train.json``; the nearest evaluation if none is at exactly that
    step), else, as SB3's EvalCallback saves on a new best mean return, the first evaluation
    with the highest mean return."""
    best = train_log.get("best_model_timesteps")
    if best is not None and len(timesteps):
        return int(np.argmin(np.abs(np.asarray(timesteps, dtype=float) - float(best))))
    finite = np.where(np.isfinite(mean_returns), mean_returns, -np.inf)
    return int(np.argmax(finite))  # the first of equal maxima: SB3 needs a strict improvement


def _seed_range(result: dict) -> str:
    seeds = result.get("seeds")
    if not seeds:
        return f"{result.get('episodes', '?')} episodes"
    return f"seeds {seeds[0]}..{seeds[-1]}"


def _steps_label(steps: float) -> str:
    if steps >= 1e6:
        return f"{steps / 1e6:.3g}M"
    if steps >= 1e4:
        return f"{steps / 1e3:.3g}k"
    return f"{steps:.0f}"


REFERENCE_COLORS = {"random": "tab:gray", "scripted": "tab:green"}
"""The reference policies a learning curve draws as horizontal lines, with their colours."""


@dataclass(frozen=True)
class _Evaluations:
    """SB3's evaluations during a training run (``<run>/eval/evaluations.npz``), one entry
    an evaluation, with the run's ``train.json`` (empty where it has none)."""

    steps: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    n_episodes: int
    successes: np.ndarray | None
    """The success rate in percent; None where the run logged none."""
    train_log: dict

    @classmethod
    def load(cls, run: Path) -> _Evaluations:
        with np.load(run / "eval" / "evaluations.npz") as npz:
            data = {key: npz[key] for key in npz.files}
        log_path = run / "train.json"
        train_log = json.loads(log_path.read_text()) if log_path.exists() else {}
        steps = np.asarray(data["timesteps"], dtype=float).reshape(-1)
        returns = np.asarray(data["results"], dtype=float).reshape(len(steps), -1)
        successes = None
        if "successes" in data and data["successes"].size:
            successes = 100.0 * np.asarray(data["successes"], dtype=float).reshape(len(steps), -1)
            successes = successes.mean(axis=1)
        return cls(
            steps, returns.mean(axis=1), returns.std(axis=1), returns.shape[1], successes, train_log
        )

    def seeds_label(self) -> str:
        """Which seed the evaluation env had: training's plus the offset."""
        seed = self.train_log.get("seed")
        if seed is None:
            return f"eval env seeded {train.EVAL_SEED_OFFSET} + the training seed"
        return f"eval env seeded {int(seed) + train.EVAL_SEED_OFFSET}"


def learning_curve_figure(
    run: Path, results: dict[str, dict], env_id: str, algo: str = "ppo", evaluated: str = "best"
) -> Any:
    """The learning-curve figure of :func:`plot_learning_curve` (a matplotlib Figure);
    ``results[algo]`` is the learnt policy's re-evaluation, of its ``evaluated`` model
    (``best`` or ``final``)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curve = _Evaluations.load(run)
    steps = curve.steps
    i_best = best_model_index(steps, curve.mean, curve.train_log)
    fig, (ax_success, ax_return) = plt.subplots(1, 2, figsize=(12, 5), constrained_layout=True)
    # (axes, values, the key of a result, its scale on the plot, the number's format)
    panels = [(ax_return, curve.mean, "mean_return", 1.0, "{:.1f}")]
    if curve.successes is not None:
        panels.insert(0, (ax_success, curve.successes, "success_rate", 100.0, "{:.0f}%"))
    else:
        ax_success.text(
            0.5,
            0.5,
            "no success rate logged",
            ha="center",
            va="center",
            transform=ax_success.transAxes,
            color="grey",
        )
    _draw_return_spread(ax_return, curve, algo)
    learnt_label = (
        f"{algo.upper()} evaluations ({curve.seeds_label()}, {curve.n_episodes} episodes per point)"
    )
    # The re-evaluation stands to the right of the curve, not on its last point, where the
    # final and best marks may already be.
    reevaluated_x = steps[-1] + REEVALUATION_GAP * max(steps[-1] - steps[0], steps[-1], 1.0)
    for ax, values, key, scale, fmt in panels:
        _draw_evaluations(ax, steps, values, fmt, learnt_label, i_best)
        _draw_references(ax, results, key, scale, fmt, algo, evaluated, reevaluated_x)
    _label_figure(fig, ax_success, ax_return, env_id, curve, algo)
    return fig


REEVALUATION_GAP = 0.06
"""How far right of the last evaluation the re-evaluated model is drawn, as a share of the
curve's span."""


def _draw_return_spread(ax: Any, curve: _Evaluations, algo: str) -> None:
    """The band of the evaluations' return, mean +- std over their episodes."""
    steps, mean, std = curve.steps, curve.mean, curve.std
    ax.fill_between(
        steps, mean - std, mean + std, alpha=0.2, label=f"{algo.upper()} mean +- std", zorder=2
    )
    if len(steps) == 1:  # a band of one point is not drawn: show its spread as an error bar
        ax.errorbar(steps, mean, yerr=std, fmt="none", ecolor="tab:blue", alpha=0.5)


def _draw_evaluations(
    ax: Any, steps: np.ndarray, values: np.ndarray, fmt: str, label: str, i_best: int
) -> None:
    """The evaluations during training, with the final one and the best model's marked:
    one mark where they are the same evaluation, so that no mark hides another."""
    ax.plot(steps, values, "o-", ms=4, label=label, zorder=4)
    i_final = len(steps) - 1
    final = _evaluation_text(steps, values, fmt, i_final)
    if i_best == i_final:
        label = f"final evaluation, also the best model (best_model.zip): {final}"
        _mark_evaluation(ax, steps, values, i_best, BEST_MARK, label)
        return
    _mark_evaluation(ax, steps, values, i_final, FINAL_MARK, f"final evaluation: {final}")
    best = _evaluation_text(steps, values, fmt, i_best)
    _mark_evaluation(ax, steps, values, i_best, BEST_MARK, f"best model (best_model.zip): {best}")


FINAL_MARK = ("s", {"ms": 11, "mfc": "none", "mec": "tab:red", "mew": 2})
"""How a learning curve marks its final evaluation: a matplotlib format and style."""
BEST_MARK = ("*", {"ms": 15, "color": "tab:orange", "mec": "black"})
"""How a learning curve marks the best model's evaluation."""


def _mark_evaluation(
    ax: Any,
    steps: np.ndarray,
    values: np.ndarray,
    i: int,
    mark: tuple[str, dict[str, Any]],
    label: str,
) -> None:
    """Evaluation ``i`` of a learning curve marked by ``mark`` (:data:`FINAL_MARK`,
    :data:`BEST_MARK`), above the curve."""
    fmt, style = mark
    ax.plot(steps[i], values[i], fmt, label=label, zorder=5, **style)


def _evaluation_text(steps: np.ndarray, values: np.ndarray, fmt: str, i: int) -> str:
    """Evaluation ``i`` in a legend: its value and when, ``"95% at 1.2M steps"``."""
    return f"{fmt.format(values[i])} at {_steps_label(steps[i])} steps"


def _draw_references(
    ax: Any,
    results: dict[str, dict],
    key: str,
    scale: float,
    fmt: str,
    algo: str,
    evaluated: str,
    reevaluated_x: float,
) -> None:
    """The baseline's own evaluations: each reference policy's ``key`` as a horizontal
    line under the curve, and the learnt policy's as a diamond at ``reevaluated_x``."""
    for name, color in REFERENCE_COLORS.items():
        if name in results:
            r = results[name]
            ax.axhline(
                scale * r[key],
                color=color,
                ls="--",
                lw=1.2,
                alpha=0.8,
                zorder=1,
                label=f"{name}: {fmt.format(scale * r[key])} ({_seed_range(r)})",
            )
    if algo in results:
        r = results[algo]
        ax.plot(
            reevaluated_x,
            scale * r[key],
            "D",
            ms=8,
            mfc="none",
            mec="tab:purple",
            mew=1.5,
            zorder=5,
            label=f"{evaluated} model re-evaluated: {fmt.format(scale * r[key])} "
            f"({_seed_range(r)})",
        )


def _label_figure(
    fig: Any, ax_success: Any, ax_return: Any, env_id: str, curve: _Evaluations, algo: str
) -> None:
    """The axes' ranges, labels, titles, grids and legends, and a one-line figure title
    (which seeds each point and line come from is in the legends)."""
    steps = curve.steps
    for ax in (ax_success, ax_return):
        # Room on the right for the re-evaluated model, and around a single evaluation.
        span = max(steps[-1] - steps[0], steps[-1], 1.0)
        low = 0.0 if len(steps) == 1 else steps[0] - 0.02 * span
        ax.set_xlim(low, steps[-1] + 2.0 * REEVALUATION_GAP * span)
    # Headroom above 100%: a curve at the top is not drawn on the axis' edge.
    ax_success.set(xlabel="timesteps", ylabel="success (%)", ylim=(-3, 109))
    ax_success.set_title("success rate")
    ax_return.set(xlabel="timesteps", ylabel="episode return")
    ax_return.set_title("episode return (mean +- std over episodes)")
    seed = curve.train_log.get("seed")
    trained = f", training seed {seed}" if seed is not None else ""
    fig.suptitle(f"{env_id}: {algo.upper()} while it learns{trained}", fontsize=12)
    for ax in (ax_success, ax_return):
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), fontsize=8, frameon=False)


def plot_learning_curve(
    run: Path,
    results: dict[str, dict],
    env_id: str,
    out: Path,
    algo: str = "ppo",
    evaluated: str = "best",
) -> None:
    """Evaluation success rate and mean return against timesteps (SB3's
    ``<run>/eval/evaluations.npz``), marking the saved best model (``train.json``'s
    ``best_model_timesteps``) and the final evaluation, with the reference policies'
    evaluation results (``results``) as horizontal lines; the legend and title say which
    seeds each uses. Works for a run of one evaluation too."""
    import matplotlib.pyplot as plt

    fig = learning_curve_figure(run, results, env_id, algo, evaluated)
    write_atomic(out, lambda path: fig.savefig(path, dpi=110))
    plt.close(fig)


def run(args: argparse.Namespace) -> int:
    from bbgym.config import EVALUATED_MODELS, load_training

    require_all(needs(args))  # also where run() is called without bbgym.cli.main
    args.out = args.out or Path("runs") / "baseline" / args.env
    seeds = list(range(args.seed, args.seed + args.seeds))
    folders = {seed: args.out / f"seed{seed}" for seed in seeds}
    missing = [str(f) for f in folders.values() if not (f / "train.json").exists()]
    if args.no_train and missing:
        raise UsageError(f"--no-train needs trained runs (their train.json) in {missing}")
    config, _ = train.resolve_preset(args.env, args.preset)
    train.pin_torch_threads(args.torch_threads)  # evaluation too (--no-train)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.engine == "torchrl":
        settings = train.torchrl_settings(config)
        algo, evaluated, n_envs = "ppo", "best", settings["num_envs"]
        model_file = "best_model.pt"
    elif args.engine == "rejax":
        settings = train.rejax_settings(config)
        algo, evaluated = settings["algo"], "best"
        n_envs, model_file = settings.get("num_envs", "rejax's default"), "best_model.npz"
    else:
        _, settings = load_training(config)
        algo, evaluated, n_envs = settings["algo"], settings["evaluate_model"], settings["n_envs"]
        model_file = EVALUATED_MODELS[evaluated]
    budget = args.timesteps or settings["total_timesteps"]
    how = (
        "all in one JAX program"
        if args.engine == "rejax"
        else f"{args.jobs} at once, {args.torch_threads} torch thread(s) each"
    )
    print(
        f"[1/4] training {algo.upper()} ({args.engine}) on {args.env}: seeds {seeds}, "
        f"{budget} timesteps each, {n_envs} envs, {how}"
    )
    train_logs, train_wall = _train_or_reuse(args, folders, budget)
    budget = train_logs[seeds[0]]["timesteps"]

    print(
        f"[2/4] evaluating random, scripted and {algo.upper()} ({len(seeds)} seeds, each "
        f"seed's {model_file}) over {args.episodes} seeded episodes"
    )
    start = time.perf_counter()
    results, per_seed = _evaluate_policies(args.env, algo, folders, model_file, args.episodes)
    eval_wall = time.perf_counter() - start
    _write_results(args.out, results, per_seed, algo)

    print("[3/4] plotting the learning curves")
    _plot_learning_curves(args.env, folders, results, per_seed, algo, evaluated, args.out)

    print(f"[4/4] recording an episode of seed {seeds[0]}'s policy")
    animation = args.out / "episode.gif"
    showcase = spec_of(args.env).showcase
    write_atomic(
        animation,
        lambda path: record.record_to_file(
            args.env,
            algo,
            path,
            model=folders[seeds[0]] / model_file,
            seed=showcase.seed,
            frame_skip=showcase.frame_skip,
            fps=showcase.fps,
        ),
    )

    summary = {
        "env": args.env,
        "config": str(config),
        "algo": algo,
        "engine": args.engine,
        "evaluated_model": model_file,
        **train.run_provenance(args.seed, args.torch_threads),
        "training_seeds": seeds,
        "jobs": args.jobs,
        "timesteps": budget,
        "n_envs": n_envs,
        # With --no-train this call trained nothing: its rate would be the JSON files'
        # reading speed. Each seed's own training time stays, from its train.json.
        "train_wall_time_s": None if args.no_train else train_wall,
        "train_wall_time_s_per_seed": {s: log["wall_time_s"] for s, log in train_logs.items()},
        "train_timesteps_per_s": None if args.no_train else budget * len(seeds) / train_wall,
        "eval_wall_time_s": eval_wall,
        "eval_episodes": args.episodes,
        "eval_seeds": [0, args.episodes - 1],
        "success_rate": {
            "random": results["random"]["success_rate"],
            "scripted": results["scripted"]["success_rate"],
            f"{algo}_mean": results[algo]["success_rate"],
            f"{algo}_worst_seed": results[algo]["worst_seed_success_rate"],
        },
    }
    write_text_atomic(args.out / "summary.json", json.dumps(summary, indent=2) + "\n")
    print(f"run folder {args.out}: " + ", ".join(sorted(p.name for p in args.out.iterdir())))
    return 0


def _train_or_reuse(
    args: argparse.Namespace, folders: dict[int, Path], budget: int
) -> tuple[dict[int, dict], float]:
    """Step 1: train every seed (:func:`train_seeds`), or with ``--no-train`` take the
    runs already there; return each seed's ``train.json`` and the wall time."""
    start = time.perf_counter()
    if args.no_train:
        print(f"      (--no-train: using the models already in {args.out}/seed*)")
    else:
        train_seeds(args, folders, budget)
    train_logs = {s: json.loads((f / "train.json").read_text()) for s, f in folders.items()}
    return train_logs, time.perf_counter() - start


def _evaluate_policies(
    env: str, algo: str, folders: dict[int, Path], model_file: str, episodes: int
) -> tuple[dict[str, dict], list[dict]]:
    """Step 2: evaluate random play, the scripted agent and each seed's ``model_file`` on
    the same ``episodes`` seeded episodes. Return the results by policy (the learnt
    policy's over all seeds, under ``algo``) and the learnt policy's per seed."""
    results = {
        name: evaluate.evaluate(env, name, episodes, 0, None) for name in ("random", "scripted")
    }
    per_seed = []
    for seed, folder in folders.items():
        result = evaluate.evaluate(env, algo, episodes, 0, folder / model_file)
        result["policy"] = f"{algo} seed {seed}"
        result["training_seed"] = seed
        per_seed.append(result)
    if spec_of(env).timed_by_oracle:
        for result in [*results.values(), *per_seed]:
            evaluate.add_time_vs_oracle(result, results["scripted"])
    results[algo] = evaluate.over_seeds(per_seed, algo)
    return results, per_seed


def _write_results(out: Path, results: dict[str, dict], per_seed: list[dict], algo: str) -> None:
    """Print the results table and write it to ``results.md`` and ``results.json``: the
    references, the learnt policy over the seeds and, with more than one seed, each
    seed's."""
    rows = [results["random"], results["scripted"], results[algo]]
    rows += per_seed if len(per_seed) > 1 else []
    table = evaluate.format_table(rows)
    summary_line = evaluate.format_over_seeds(results[algo])
    print(table)
    print(summary_line)
    write_text_atomic(out / "results.md", table + "\n\n" + summary_line + "\n")
    write_text_atomic(out / "results.json", json.dumps(rows, indent=2) + "\n")


def _plot_learning_curves(
    env: str,
    folders: dict[int, Path],
    results: dict[str, dict],
    per_seed: list[dict],
    algo: str,
    evaluated: str,
    out: Path,
) -> None:
    """Step 3: each seed's learning curve in its folder, against that seed's own
    re-evaluation; the first seed's is copied into the run folder ``out``."""
    for folder, seed_result in zip(folders.values(), per_seed, strict=True):
        curve_results = {**results, algo: seed_result}
        plot_learning_curve(
            folder, curve_results, env, folder / "learning_curve.png", algo, evaluated
        )
    first = next(iter(folders.values()))
    copy_atomic(first / "learning_curve.png", out / "learning_curve.png")


def train_seeds(args: argparse.Namespace, folders: dict[int, Path], budget: int) -> None:
    """Train every seed's model into its folder: one after another with a progress bar, or
    ``--jobs`` at once in separate processes (each pinned to ``--torch-threads``)."""
    if args.engine == "rejax":  # every seed in one program
        print(f"      seeds {list(folders)} in one program -> {args.out}/seed*")
        train.train_rejax(args.env, folders=folders, preset=args.preset, timesteps=budget)
        return
    kwargs = {"preset": args.preset, "timesteps": budget, "torch_threads": args.torch_threads}
    trainer = train.train_sb3
    if args.engine == "torchrl":
        trainer = train.train_torchrl
        kwargs["device"] = args.device
    else:  # stable-baselines3's progress bar: one training at a time only
        kwargs["progress"] = args.jobs == 1 and not args.no_progress
    if args.jobs == 1:
        for seed, folder in folders.items():
            print(f"      seed {seed} -> {folder}")
            trainer(args.env, seed=seed, out=folder, **kwargs)
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    context = multiprocessing.get_context("spawn")  # a fresh torch in each process
    with ProcessPoolExecutor(max_workers=args.jobs, mp_context=context) as pool:
        futures = {
            seed: pool.submit(trainer, args.env, seed=seed, out=folder, **kwargs)
            for seed, folder in folders.items()
        }
        for seed, future in futures.items():
            log = future.result()
            print(f"      seed {seed}: {log['timesteps']} timesteps in {log['wall_time_s']:.0f} s")
