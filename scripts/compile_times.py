"""Developer tool: how long the torch backend's first ``step()`` takes for each env id,
with a cold compile cache and with a warm one, each run a fresh process.

    python scripts/compile_times.py [--envs BeachballThrow-v0 ...] [--num-envs 4]
        [--dtype float64] [--torch-threads 2] [--other-threads 1]
        [--out docs/results/speed/compile.json]

For each env: a new empty ``TORCHINDUCTOR_CACHE_DIR`` (a temporary folder), one process
that makes ``gym.make_vec(env_id, num_envs=..., backend="torch")``, resets it and times its
first step (cold), then a second process with the same folder (warm) and, with
``--other-threads``, a third with the same folder under another torch thread count (warm
across thread counts). Each run prints a JSON line: the first step's seconds, the second
step's, the graphs Dynamo traced and inductor's and AOTAutograd's cache counters (a hit, a
miss, or a bypass: a graph the cache refused). The rows, the command and the machine go to
``--out``; every registered id takes 2-8 minutes on the 2-core machine (most of it the cold
compile), so pass ``--envs`` for a quick look.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent

RUN = r"""
import json, sys, time
import gymnasium as gym
import numpy as np
import torch
import bbgym
from torch._dynamo.utils import counters

env_id, num_envs, dtype, threads = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
if threads != "default":
    torch.set_num_threads(int(threads))
start = time.perf_counter()
env = gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point",
                   backend="torch", dtype=dtype)
env.reset(seed=0)
made = time.perf_counter() - start
actions = [env.action_space.sample() for _ in range(2)]
times = []
for a in actions:
    start = time.perf_counter()
    env.step(a)
    times.append(time.perf_counter() - start)
print(json.dumps({
    "make_and_reset_s": round(made, 3),
    "first_step_s": round(times[0], 2),
    "second_step_s": round(times[1], 5),
    "step_graph": env.unwrapped.step_graph,
    "torch_threads": torch.get_num_threads(),
    "graphs": counters["stats"]["unique_graphs"],
    "inductor_cache": {k: v for k, v in counters["inductor"].items() if "cache" in k},
    "aot_autograd_cache": {k: v for k, v in counters["aot_autograd"].items() if "cache" in k},
}))
"""


def registered_ids() -> list[str]:
    """Every env id bbgym registers.

    Returns:
        The ids, in registration order.
    """
    import gymnasium as gym

    import bbgym  # noqa: F401 (registers the ids)

    return [k for k in gym.registry if k.startswith("Beachball")]


def run_once(env_id: str, cache: str, args: argparse.Namespace, threads: str) -> dict[str, Any]:
    """One fresh process timing ``env_id``'s first torch step with inductor's cache at
    ``cache``.

    Args:
        env_id: the env id.
        cache: the ``TORCHINDUCTOR_CACHE_DIR`` of the run.
        args: the command's arguments (``num_envs``, ``dtype``, ``timeout``).
        threads: the torch thread count, or ``"default"``.

    Returns:
        The run's JSON line as a dict, or ``{"error": ...}`` where it failed.
    """
    env = {**os.environ, "TORCHINDUCTOR_CACHE_DIR": cache, "BBGYM_QUIET": "1"}
    command = [sys.executable, "-c", RUN, env_id, str(args.num_envs), args.dtype, threads]
    try:
        done = subprocess.run(
            command, env=env, cwd=ROOT, capture_output=True, text=True, timeout=args.timeout
        )
    except subprocess.TimeoutExpired:
        return {"error": f"timed out after {args.timeout} s"}
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    if done.returncode or not lines:
        return {"error": (done.stderr.strip().splitlines() or ["no output"])[-1]}
    return json.loads(lines[-1])


def machine() -> dict[str, Any]:
    """The machine and versions the times were taken on.

    Returns:
        Platform, processor, Python, CPU count, torch version and its default threads.
    """
    import torch

    return {
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "python": platform.python_version(),
        "cpu_count": os.cpu_count(),
        "torch": torch.__version__,
        "torch_threads_default": torch.get_num_threads(),
    }


def main(argv: list[str] | None = None) -> int:
    """Time every env's cold and warm first step and write the JSON file.

    Args:
        argv: the command line's arguments (``sys.argv[1:]`` when None).

    Returns:
        0, or 1 where a run failed.
    """
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--envs", nargs="+", help="env ids (default: every registered id)")
    parser.add_argument("--num-envs", type=int, default=4)
    parser.add_argument("--dtype", default="float64", choices=("float64", "float32"))
    parser.add_argument("--torch-threads", default="default", help="an int, or 'default'")
    parser.add_argument("--other-threads", help="also a warm run under this thread count")
    parser.add_argument("--timeout", type=float, default=900.0, help="seconds a run may take")
    parser.add_argument("--out", type=Path, default=ROOT / "docs/results/speed/compile.json")
    args = parser.parse_args(argv)
    rows, failed = [], False
    for env_id in args.envs or registered_ids():
        with tempfile.TemporaryDirectory(prefix="bbgym-compile-") as cache:
            row: dict[str, Any] = {"env_id": env_id, "num_envs": args.num_envs}
            row["dtype"] = args.dtype
            runs = [("cold", args.torch_threads), ("warm", args.torch_threads)]
            if args.other_threads:
                runs.append(("warm_other_threads", args.other_threads))
            for name, threads in runs:
                row[name] = run_once(env_id, cache, args, threads)
                failed |= "error" in row[name]
                print(json.dumps({"env_id": env_id, "run": name, **row[name]}), flush=True)
        rows.append(row)
    command = "python scripts/compile_times.py " + shlex.join(argv or sys.argv[1:])
    report = {"command": command.strip(), "machine": machine(), "rows": rows}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=1) + "\n")
    print(f"wrote {args.out}")
    return int(failed)


if __name__ == "__main__":
    sys.exit(main())
