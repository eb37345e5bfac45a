"""Evaluate policies on a bbgym env over the same seeded episodes; write a results table.

    bbgym evaluate --env ENV_ID [--policies random,scripted]
        [--model runs/ppo/ENV_ID-seed0/best_model.zip] [--episodes 100] [--seed 0]
        [--out runs/eval] [--overwrite]

Every policy meets the same scenarios (episode ``k`` is reset with ``seed + k``). Reports
the success rate with a 95% Wilson interval, the mean return, the mean episode length
(steps; throws for the ball envs), the failure breakdown (how each failed episode ended,
by the env family's :attr:`~bbgym.spec.EnvSpec.outcome`) and, where the env keeps time
(``elapsed_time`` in its info), the mean time to the mark of the successful episodes.
Writes ``<out>/<env>.json`` and ``<out>/<env>.md``, and refuses (before evaluating) to
replace them unless ``--overwrite`` is given. In the table a mean over fewer than 10 finished
episodes (time to the mark, time / oracle) shows their count, "1.80 (2 ep.)"; the time
columns are left out for an env that keeps no time.

Policies: ``random`` (uniform actions), ``ppo`` and ``sac`` (a stable-baselines3 PPO or SAC
model saved at ``--model``; for ``ppo`` also a policy ``.pt`` of ``bbgym train --engine
torchrl``), and the env family's own (:attr:`bbgym.spec.EnvSpec.policies`):
``scripted`` (its scripted agent from ``bbgym.agents``: the VMG autopilot for sailing, the
throw solver, the topple agent), ``planner`` (the ball envs: the privileged planners of
:mod:`bbgym.agents.planner`, which read the true wind and the env's random stream and
search through the physics; the success rate is the winnable fraction they prove) and
``simple`` (sailing: the simple helmsman). Where the family is ``timed_by_oracle``
(sailing), each policy's time to the mark is also compared with the scripted policy's on
the episodes both finished ("time / oracle time"; the scripted policy is run for it if it
is not among the policies).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import bbgym  # noqa: F401  (registers the envs)
from bbgym._extras import extra_needs
from bbgym.backends import announced
from bbgym.cli import UsageError, add_aliased, as_passed, env_id, positive_int, require
from bbgym.spec import env_id_of, spec_of

Policy = Callable[[np.ndarray], np.ndarray]
LEARNT = ("ppo", "sac")
"""Policies that are a saved stable-baselines3 model (``--model``), named by its algorithm."""
POLICIES = ("random", "scripted", "simple", "planner", *LEARNT)
"""Every policy name ``--policies`` takes; an env family has some of the non-learning ones
(``scripted`` always)."""


def wilson_interval(successes: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """95% Wilson score interval of a success rate (sound at 0% and 100% too)."""
    if n == 0:
        return (0.0, 1.0)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return (max(0.0, centre - half), min(1.0, centre + half))


def make_policy(name: str, env: gym.Env, model_path: Path | None, seed: int) -> Any:
    """A callable ``obs -> action`` (with an optional ``reset()``): ``random``, a saved
    stable-baselines3 model (``ppo``, ``sac``), or one of the env family's own policies
    (:attr:`bbgym.spec.EnvSpec.policies`: ``scripted``, ``planner``, ...)."""
    if name == "random":
        space = env.action_space
        space.seed(seed)
        return lambda obs: space.sample()
    if name in LEARNT:
        if model_path is None:
            raise ValueError(f"--policies {name} needs --model")
        if not Path(model_path).is_file():
            raise ValueError(
                f"--model {model_path}: no such file (a saved SB3 model .zip, "
                "a policy .pt of --engine torchrl, or a policy .npz of --engine rejax)"
            )
        if Path(model_path).suffix == ".pt":
            return _torchrl_policy(name, model_path)
        if Path(model_path).suffix == ".npz":  # bbgym train --engine rejax: NumPy alone
            from bbgym.mlp_policy import MLPPolicy

            policy = MLPPolicy.load(model_path)
            if policy.meta.get("algo", name) != name:
                raise ValueError(
                    f"--model {model_path}: a policy of {policy.meta['algo']} "
                    f"(--policies {policy.meta['algo']}), not {name}"
                )
            return policy
        require("stable_baselines3", "train")
        from bbgym.sb3 import load_model

        model = load_model(model_path, name)
        return lambda obs: model.predict(obs, deterministic=True)[0]
    if name not in POLICIES:
        raise ValueError(f"unknown policy {name!r}; known: {', '.join(POLICIES)}")
    return spec_of(env_id_of(env)).policy(name, env)


def _torchrl_policy(name: str, model_path: Path) -> Policy:
    """The deterministic action of a PPO policy saved by ``bbgym train --engine torchrl``."""
    if name != "ppo":
        raise ValueError(
            f"--model {model_path}: a policy of --engine torchrl is PPO's "
            f"(--policies ppo), not {name}"
        )
    require("torchrl", "torchrl")
    import torch

    from bbgym.torchrl import load_policy

    net = load_policy(model_path)

    def act(obs: np.ndarray) -> np.ndarray:
        with torch.no_grad():
            return net.act(torch.as_tensor(obs, dtype=torch.float32)).numpy()

    return act


def outcome_kind(env: gym.Env, info: dict[str, Any], terminated: bool, truncated: bool) -> str:
    """An episode's row in the failure breakdown: ``success``, or how it failed (the env
    family's :meth:`~bbgym.spec.EnvSpec.episode_outcome`: ``capsized``, ``timed out``,
    ``missed long``, ...)."""
    text, success = spec_of(env_id_of(env)).episode_outcome(env, info, terminated, truncated)
    return "success" if success else text


def evaluate(env_id: str, policy_name: str, episodes: int, seed: int, model: Path | None) -> dict:
    """``episodes`` seeded episodes (seeds ``seed ..``) of ``policy_name`` on ``env_id``, a
    bbgym id (else ``ValueError`` listing them: the outcomes come from the family's spec).

    Args:
        env_id: a bbgym env id.
        policy_name: ``random``, a learnt policy (``ppo``, ``sac``) or one of the family's.
        episodes: how many episodes.
        seed: the first episode's seed.
        model: the saved model of a learnt policy.

    Returns:
        The result row; its ``wall_time_s`` counts making the env and the policy (a
        sailing autopilot's polar, a model's loading) as well as the episodes.
    """
    spec_of(env_id)
    start = time.perf_counter()
    with announced(f"evaluate: making {env_id} and the {policy_name} policy"):
        env = gym.make(env_id)
        policy = make_policy(policy_name, env, model, seed)
    successes, returns, lengths, times = 0, [], [], []
    outcomes: Counter[str] = Counter()
    episode_times: list[float | None] = []  # time to the mark per episode, None if missed
    with announced(f"evaluate: {episodes} episodes of {policy_name} on {env_id}"):
        for k in range(episodes):
            obs, info = env.reset(seed=seed + k)
            if hasattr(policy, "reset"):
                policy.reset()
            total, steps, done = 0.0, 0, False
            while not done:
                obs, reward, terminated, truncated, info = env.step(policy(obs))
                total += reward
                steps += 1
                done = terminated or truncated
            successes += bool(info["is_success"])
            outcomes[outcome_kind(env, info, terminated, truncated)] += 1
            returns.append(total)
            lengths.append(steps)
            if info["is_success"] and "elapsed_time" in info:
                times.append(info["elapsed_time"])
            if "elapsed_time" in info:  # sailing
                episode_times.append(float(info["elapsed_time"]) if info["is_success"] else None)
        env.close()
    low, high = wilson_interval(successes, episodes)
    return {
        "env": env_id,
        "policy": policy_name,
        "episodes": episodes,
        "seeds": [seed, seed + episodes - 1],
        "success_rate": successes / episodes,
        "success_ci95": [low, high],
        "mean_return": float(np.mean(returns)),
        "mean_length": float(np.mean(lengths)),
        "mean_time_to_mark_s": float(np.mean(times)) if times else None,
        "time_to_mark_episodes": len(times),
        "outcomes": dict(outcomes.most_common()),
        "wall_time_s": time.perf_counter() - start,
        "episode_time_to_mark_s": episode_times if times else None,
    }


def _oracle_ratios(result: dict, oracle: dict) -> list[float]:
    mine, best = result["episode_time_to_mark_s"], oracle["episode_time_to_mark_s"]
    if not mine or not best:
        return []
    return [a / b for a, b in zip(mine, best, strict=True) if a is not None and b is not None]


def time_vs_oracle(result: dict, oracle: dict) -> float | None:
    """Mean of ``time / oracle time`` over the episodes both policies finished."""
    ratios = _oracle_ratios(result, oracle)
    return float(np.mean(ratios)) if ratios else None


def add_time_vs_oracle(result: dict, oracle: dict) -> None:
    """Set ``result``'s ``time_vs_oracle`` (:func:`time_vs_oracle`) and
    ``time_vs_oracle_episodes``, the number of episodes it is the mean of."""
    result["time_vs_oracle"] = time_vs_oracle(result, oracle)
    result["time_vs_oracle_episodes"] = len(_oracle_ratios(result, oracle))


FEW_EPISODES = 10
"""A mean over fewer finished episodes than this is shown with their count in a table
("1.80 (2 ep.)"): random play's time / oracle may rest on two lucky arrivals."""


def _with_count(text: str, episodes: int | None) -> str:
    """``text``, with ``" (n ep.)"`` where it is a mean over fewer than
    :data:`FEW_EPISODES` episodes."""
    if episodes is None or episodes >= FEW_EPISODES:
        return text
    return f"{text} ({episodes} ep.)"


T_975 = {
    1: 12.706,
    2: 4.303,
    3: 3.182,
    4: 2.776,
    5: 2.571,
    6: 2.447,
    7: 2.365,
    8: 2.306,
    9: 2.262,
    10: 2.228,
    15: 2.131,
    20: 2.086,
    30: 2.042,
}
"""Student's t 0.975 quantile by degrees of freedom (between the listed ones, the next
smaller listed, so the interval errs wide; beyond 30, 1.96)."""


def mean_interval(values: list[float]) -> tuple[float, float]:
    """95% interval of the mean of ``values`` (Student's t; one value: the whole [0, 1])."""
    n = len(values)
    if n < 2:
        return (0.0, 1.0)
    dof = n - 1
    t = 1.96 if dof > 30 else T_975[max(k for k in T_975 if k <= dof)]
    half = t * float(np.std(values, ddof=1)) / math.sqrt(n)
    mean = float(np.mean(values))
    return (max(0.0, mean - half), min(1.0, mean + half))


def over_seeds(per_seed: list[dict], algo: str = "ppo") -> dict:
    """One result of the ``algo`` models of several training seeds: the mean success rate
    with the 95% interval of the mean over seeds (``success_ci95``; for a single seed, its
    Wilson interval over its episodes), the worst seed, the pooled rate's Wilson interval,
    mean return, length and time / oracle, and the failures summed."""
    rates = [r["success_rate"] for r in per_seed]
    worst = min(per_seed, key=lambda r: r["success_rate"])
    episodes = sum(r["episodes"] for r in per_seed)
    successes = round(sum(r["success_rate"] * r["episodes"] for r in per_seed))
    outcomes: Counter[str] = Counter()
    for r in per_seed:
        outcomes.update(r.get("outcomes") or {})
    ratios = [r["time_vs_oracle"] for r in per_seed if r.get("time_vs_oracle") is not None]
    times = [r["mean_time_to_mark_s"] for r in per_seed if r["mean_time_to_mark_s"]]
    return {
        "env": per_seed[0]["env"],
        "policy": f"{algo}, {len(per_seed)} seed{'s' if len(per_seed) > 1 else ''}",
        "algo": algo,
        "training_seeds": [r.get("training_seed") for r in per_seed],
        "episodes": per_seed[0]["episodes"],
        "seeds": per_seed[0]["seeds"],
        "success_rate": float(np.mean(rates)),
        "success_ci95": list(
            mean_interval(rates) if len(rates) > 1 else per_seed[0]["success_ci95"]
        ),
        "success_by_seed": rates,
        "worst_seed": worst.get("training_seed"),
        "worst_seed_success_rate": worst["success_rate"],
        "pooled_success_ci95": list(wilson_interval(successes, episodes)),
        "mean_return": float(np.mean([r["mean_return"] for r in per_seed])),
        "mean_length": float(np.mean([r["mean_length"] for r in per_seed])),
        "mean_time_to_mark_s": float(np.mean(times)) if times else None,
        "time_to_mark_episodes": _sum_counts(per_seed, "time_to_mark_episodes"),
        "time_vs_oracle": float(np.mean(ratios)) if ratios else None,
        "time_vs_oracle_episodes": _sum_counts(per_seed, "time_vs_oracle_episodes"),
        "worst_time_vs_oracle": max(ratios) if ratios else None,
        "outcomes": dict(outcomes.most_common()),
        "wall_time_s": sum(r["wall_time_s"] for r in per_seed),
    }


def _sum_counts(rows: list[dict], key: str) -> int | None:
    """The sum of ``key`` over ``rows``; None where a row lacks it (older results)."""
    counts = [r.get(key) for r in rows]
    return None if any(c is None for c in counts) else sum(counts)


def format_over_seeds(result: dict) -> str:
    """One line: the learnt policy's mean over seeds, its interval, the worst seed and each
    seed's rate."""
    low, high = result["success_ci95"]
    by_seed = ", ".join(
        f"{seed}: {100 * rate:.0f}%"
        for seed, rate in zip(result["training_seeds"], result["success_by_seed"], strict=True)
    )
    ratio = result.get("time_vs_oracle")
    oracle = ""
    if ratio is not None:
        oracle = f"; time / oracle {ratio:.2f} (worst seed {result['worst_time_vs_oracle']:.2f})"
    n = len(result["success_by_seed"])
    interval = "95% interval of the mean over seeds" if n > 1 else "95% Wilson interval"
    return (
        f"{result['env']} {result.get('algo', 'ppo').upper()} over {n} training "
        f"seed{'s' if n > 1 else ''}: mean "
        f"{100 * result['success_rate']:.1f}% ({interval} "
        f"{100 * low:.0f}-{100 * high:.0f}%), worst seed {result['worst_seed']} "
        f"{100 * result['worst_seed_success_rate']:.0f}% (by seed: {by_seed}){oracle}"
    )


def format_failures(outcomes: dict[str, int] | None) -> str:
    """``"capsized 3, timed out 2"``: the failures of a result, most frequent first."""
    failures = {k: v for k, v in (outcomes or {}).items() if k != "success"}
    return ", ".join(f"{kind} {count}" for kind, count in failures.items()) or "-"


def episodes_label(result: dict) -> str:
    """``"100"``, or ``"5 x 100"`` for a result over training seeds (its failures are the
    sum over every seed's episodes)."""
    seeds = result.get("success_by_seed")
    return f"{len(seeds)} x {result['episodes']}" if seeds else str(result["episodes"])


def _timed_by_oracle(env: str) -> bool:
    try:
        return spec_of(env).timed_by_oracle
    except ValueError:  # an id of no bbgym family (a results file of another package)
        return True


def format_table(results: list[dict]) -> str:
    """The results as a markdown table, a row each. The time columns are left out where no
    row has a value (the ball envs keep no time to a mark) and "time / oracle" where the
    env's family is not ``timed_by_oracle``; a mean of fewer than :data:`FEW_EPISODES`
    finished episodes shows their count ("1.80 (2 ep.)")."""
    columns: dict[str, tuple[str, Any]] = {
        "env": ("---", lambda r: r["env"]),
        "policy": ("---", lambda r: r["policy"]),
        "episodes": ("---:", episodes_label),
        "success (95% CI)": (
            "---",
            lambda r: (
                f"{100 * r['success_rate']:.0f}% "
                f"({100 * r['success_ci95'][0]:.0f}-{100 * r['success_ci95'][1]:.0f}%)"
            ),
        ),
        "mean return": ("---:", lambda r: f"{r['mean_return']:.2f}"),
        "mean length": ("---:", lambda r: f"{r['mean_length']:.1f}"),
        "time to mark": (
            "---:",
            lambda r: (
                _with_count(f"{r['mean_time_to_mark_s']:.1f} s", r.get("time_to_mark_episodes"))
                if r.get("mean_time_to_mark_s")
                else "-"
            ),
        ),
        "time / oracle": (
            "---:",
            lambda r: (
                _with_count(f"{r['time_vs_oracle']:.2f}", r.get("time_vs_oracle_episodes"))
                if r.get("time_vs_oracle") is not None
                else "-"
            ),
        ),
        "failures": ("---", lambda r: format_failures(r.get("outcomes"))),
        "wall time": ("---:", lambda r: f"{r['wall_time_s']:.0f} s"),
    }
    cells = {name: [cell(r) for r in results] for name, (_, cell) in columns.items()}
    dropped = {
        name for name in ("time to mark", "time / oracle") if all(c == "-" for c in cells[name])
    }
    if results and not any(_timed_by_oracle(r["env"]) for r in results):
        dropped.add("time / oracle")
    names = [name for name in columns if name not in dropped]
    lines = [
        "| " + " | ".join(names) + " |",
        "|" + "|".join(columns[name][0] for name in names) + "|",
    ]
    for i in range(len(results)):
        lines.append("| " + " | ".join(cells[name][i] for name in names) + " |")
    return "\n".join(lines)


def parse_policies(text: str) -> list[str]:
    """An argparse ``type``: comma-separated policy names, each one of :data:`POLICIES`."""
    names = [name.strip() for name in text.split(",") if name.strip()]
    unknown = sorted(set(names) - set(POLICIES))
    if unknown or not names:
        raise argparse.ArgumentTypeError(
            f"unknown policies {unknown or [text]}; known: {', '.join(POLICIES)}"
        )
    return names


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--env", required=True, type=env_id, help="a bbgym env id")
    add_aliased(
        parser,
        "--policies",
        "--policy",
        type=parse_policies,
        default="random,scripted",
        help=f"comma-separated, of: {', '.join(POLICIES)}",
    )
    parser.add_argument("--model", type=Path, default=None, help="saved PPO or SAC model (.zip)")
    parser.add_argument("--episodes", type=positive_int, default=100, help="episodes per policy")
    parser.add_argument("--seed", type=int, default=0, help="seed of the first episode")
    parser.add_argument("--out", type=Path, default=Path("runs/eval"), help="output folder")
    parser.add_argument(
        "--overwrite", action="store_true", help="replace <out>/<env>.json and .md where they exist"
    )


def needs(args: argparse.Namespace) -> list[tuple[str, str]]:
    """``(module, extra)`` the run needs: for a saved model's policy the ``train`` extra
    (stable-baselines3's ``.zip``) or the ``torchrl`` extra (a ``.pt`` of ``--engine
    torchrl``)."""
    return model_needs(args.policies, args.model)


def model_needs(policies: list[str], model: Path | None) -> list[tuple[str, str]]:
    """The extra a saved model's policy needs: ``torchrl`` for a ``.pt`` policy of
    ``bbgym train --engine torchrl``, none for a ``.npz`` of ``--engine rejax`` (NumPy
    evaluates it), else ``train`` (stable-baselines3); none where no policy in
    ``policies`` is a saved model."""
    if not set(policies) & set(LEARNT) or Path(model or "").suffix == ".npz":
        return []
    return extra_needs("torchrl" if Path(model or "").suffix == ".pt" else "train")


def run(args: argparse.Namespace) -> int:
    names = args.policies
    written = [args.out / f"{args.env}.json", args.out / f"{args.env}.md"]
    existing = [str(path) for path in written if path.exists()]
    if existing and not args.overwrite:
        raise UsageError(
            f"--out {args.out}: {' and '.join(existing)} exist(s); pass --overwrite to "
            "replace, or another --out"
        )
    learnt = [name for name in names if name in LEARNT]
    if learnt and args.model is None:
        raise UsageError(
            f"{as_passed(args, 'policies', '--policies')} {learnt[0]} needs --model (a saved "
            "stable-baselines3 model .zip)"
        )
    try:
        results = [evaluate(args.env, name, args.episodes, args.seed, args.model) for name in names]
    except ValueError as err:
        raise UsageError(str(err)) from None
    oracle = None
    if spec_of(args.env).timed_by_oracle:
        by_name = dict(zip(names, results, strict=True))
        oracle = by_name.get("scripted") or evaluate(
            args.env, "scripted", args.episodes, args.seed, None
        )
        for result in results:
            add_time_vs_oracle(result, oracle)
    table = format_table(results)
    print(table)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / f"{args.env}.json").write_text(json.dumps(results, indent=2) + "\n")
    (args.out / f"{args.env}.md").write_text(table + "\n")
    print(f"wrote {args.out / (args.env + '.json')} and {args.out / (args.env + '.md')}")
    hidden = [] if oracle is None or any(r is oracle for r in results) else [oracle]
    print(total_line(results, process_seconds(), hidden))
    return 0


def process_seconds() -> float | None:
    """Seconds since this process started (Linux's ``/proc``), or None where unknown.

    Returns:
        The process's wall time so far: Python's start and imports included.
    """
    try:
        with open("/proc/self/stat") as stat, open("/proc/uptime") as uptime:
            started = int(stat.read().rsplit(")", 1)[1].split()[19])
            now = float(uptime.read().split()[0])
        return now - started / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, AttributeError):
        return None


def total_line(
    results: list[dict], total_s: float | None, unlisted: list[dict] | None = None
) -> str:
    """The command's whole wall time beside what the table's "wall time" column holds.

    Args:
        results: the table's rows (each with its ``wall_time_s``).
        total_s: the process's seconds so far (:func:`process_seconds`), or None.
        unlisted: runs not in the table (the scripted policy run for "time / oracle").

    Returns:
        ``"total wall time 31 s: ..."``, or the policies' part alone where the total is
        unknown.
    """
    rows = sum(r["wall_time_s"] for r in results)
    parts = f"the table's policies {rows:.0f} s (making their envs and policies included)"
    hidden = sum(r["wall_time_s"] for r in unlisted or [])
    if hidden:
        parts += f", the scripted policy for time / oracle {hidden:.0f} s"
    if total_s is None:
        return f"wall time: {parts}"
    rest = max(total_s - rows - hidden, 0.0)
    return (
        f"total wall time {total_s:.0f} s: {parts}, and {rest:.0f} s starting Python, "
        "importing and writing"
    )
