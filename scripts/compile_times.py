"""Developer tool: how long a native vector env's first ``step()`` takes on the torch or
JAX backend for each env id, with a cold compile cache and with a warm one, each run a
fresh process.

    python scripts/compile_times.py [--backend torch] [--envs BeachballThrow-v0 ...]
        [--num-envs 4] [--dtype float64] [--torch-threads 2] [--other-threads 1]
        [--out docs/results/speed/compile.json]
    python scripts/compile_times.py --backend jax [--envs ...] [--num-envs 4]
        [--dtype float32] [--out docs/results/speed/compile-jax.json]

For each env: a new empty compile cache folder (a temporary folder: torch's
``TORCHINDUCTOR_CACHE_DIR``, JAX's ``BBGYM_JAX_CACHE``), one process that makes
``gym.make_vec(env_id, num_envs=..., backend=...)``, resets it and times its first step
(cold), then a second process with the same folder (warm) and, on torch with
``--other-threads``, a third with the same folder under another torch thread count (warm
across thread counts). Each run prints a JSON line: make and reset's seconds, the first
step's, the second step's and what the cache did: on torch the graphs Dynamo traced and
inductor's and AOTAutograd's cache counters (a hit, a miss, or a bypass: a graph the cache
refused); on JAX its persistent cache's hits and misses (a miss: a program compiled and
written to the folder), the programs compiled in the process and the folder's entries.
The rows, the command and the machine go to ``--out``. On torch every registered id takes
2-8 minutes on the 2-core machine (most of it the cold compile), so pass ``--envs`` for a
quick look; on JAX an id takes some 10-20 s.
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
from importlib import metadata
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
SPEED = ROOT / "docs/results/speed"

BACKENDS = ("torch", "jax")
DEFAULT_DTYPE = {"torch": "float64", "jax": "float32"}
DEFAULT_OUT = {"torch": SPEED / "compile.json", "jax": SPEED / "compile-jax.json"}
CACHE_VARIABLE = {"torch": "TORCHINDUCTOR_CACHE_DIR", "jax": "BBGYM_JAX_CACHE"}
"""The environment variable that points each backend's compile cache at a folder
(``bbgym.backends.JAX_CACHE_VARIABLE`` for JAX)."""

RUN = r"""
import json, os, sys, time
import gymnasium as gym
import bbgym

env_id, num_envs, dtype, backend, threads = sys.argv[1:6]
if backend == "torch":
    import torch
    from torch._dynamo.utils import counters

    if threads != "default":
        torch.set_num_threads(int(threads))
else:  # jax: its persistent cache's events, counted as torch's counters count inductor's
    from collections import Counter
    import jax

    events = Counter()
    jax.monitoring.register_event_listener(lambda event, **_: events.update([event]))
start = time.perf_counter()
env = gym.make_vec(env_id, num_envs=int(num_envs), vectorization_mode="vector_entry_point",
                   backend=backend, dtype=dtype)
env.reset(seed=0)
made = time.perf_counter() - start
actions = [env.action_space.sample() for _ in range(2)]
times = []
for a in actions:
    start = time.perf_counter()
    env.step(a)  # NumPy arrays out (the default output): the step has finished on return
    times.append(time.perf_counter() - start)
row = {
    "make_and_reset_s": round(made, 3),
    "first_step_s": round(times[0], 2),
    "second_step_s": round(times[1], 5),
}
if backend == "torch":
    row.update({
        "step_graph": env.unwrapped.step_graph,
        "torch_threads": torch.get_num_threads(),
        "graphs": counters["stats"]["unique_graphs"],
        "inductor_cache": {k: v for k, v in counters["inductor"].items() if "cache" in k},
        "aot_autograd_cache": {
            k: v for k, v in counters["aot_autograd"].items() if "cache" in k
        },
    })
else:
    # JAX counts a miss only where it writes the program to the folder, which it does for
    # programs that took over jax_persistent_cache_min_compile_time_secs (1 s) to compile:
    # the step. Every request the cache did not serve, the reset's small eager ops
    # included, is a program compiled in this process.
    asked = events["/jax/compilation_cache/compile_requests_use_cache"]
    hits = events["/jax/compilation_cache/cache_hits"]
    misses = events["/jax/compilation_cache/cache_misses"]
    folder = os.environ["BBGYM_JAX_CACHE"]  # the run's folder: its entries show JAX used it
    row.update({
        "jax_cache": {"compilation_cache_hit": hits, "compilation_cache_miss": misses},
        "programs_compiled": asked - hits,
        "jax_cache_entries": len(os.listdir(folder)) if os.path.isdir(folder) else 0,
    })
print(json.dumps(row))
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
    """One fresh process timing ``env_id``'s first step on ``args.backend`` with its compile
    cache at ``cache``.

    Args:
        env_id: the env id.
        cache: the compile cache folder of the run (:data:`CACHE_VARIABLE`).
        args: the command's arguments (``backend``, ``num_envs``, ``dtype``, ``timeout``).
        threads: the torch thread count, or ``"default"`` (always, on JAX).

    Returns:
        The run's JSON line as a dict, or ``{"error": ...}`` where it failed.
    """
    env = {**os.environ, CACHE_VARIABLE[args.backend]: cache, "BBGYM_QUIET": "1"}
    # JAX reads this into jax_compilation_cache_dir, which bbgym then keeps: the run would
    # use the user's folder instead of the empty one.
    env.pop("JAX_COMPILATION_CACHE_DIR", None)
    command = [sys.executable, "-c", RUN, env_id, str(args.num_envs), args.dtype]
    command += [args.backend, threads]
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


def machine(backend: str = "torch") -> dict[str, Any]:
    """The machine and versions the times were taken on.

    Args:
        backend: ``"torch"`` or ``"jax"``: whose versions to name.

    Returns:
        Platform, processor, Python and CPU count, with torch's version and default thread
        count, or jax's and jaxlib's versions (read without importing jax).
    """
    info: dict[str, Any] = {
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "python": platform.python_version(),
        "cpu_count": os.cpu_count(),
    }
    if backend == "jax":
        for package in ("jax", "jaxlib"):
            try:
                info[package] = metadata.version(package)
            except metadata.PackageNotFoundError:
                info[package] = None
        return info
    import torch

    return {**info, "torch": torch.__version__, "torch_threads_default": torch.get_num_threads()}


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """The command's arguments, with each backend's defaults filled in.

    Args:
        argv: the command line's arguments (``sys.argv[1:]`` when None).

    Returns:
        The arguments; ``dtype``, ``out`` and ``torch_threads`` resolved for the backend.
        A torch thread option with ``--backend jax`` exits with an error naming it.
    """
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--backend", choices=BACKENDS, default="torch")
    parser.add_argument("--envs", nargs="+", help="env ids (default: every registered id)")
    parser.add_argument("--num-envs", type=int, default=4)
    parser.add_argument(
        "--dtype",
        choices=("float64", "float32"),
        help="default: float64 for torch, float32 for jax",
    )
    parser.add_argument("--torch-threads", help="an int, or 'default' (torch only)")
    parser.add_argument("--other-threads", help="also a warm run under this thread count")
    parser.add_argument("--timeout", type=float, default=900.0, help="seconds a run may take")
    parser.add_argument(
        "--out",
        type=Path,
        help="default: docs/results/speed/compile.json, compile-jax.json for jax",
    )
    args = parser.parse_args(argv)
    if args.backend == "jax":
        for flag in ("--torch-threads", "--other-threads"):
            if getattr(args, flag[2:].replace("-", "_")) is not None:
                parser.error(f"{flag}: torch's thread count, and --backend jax runs no torch")
    args.dtype = args.dtype or DEFAULT_DTYPE[args.backend]
    args.out = args.out or DEFAULT_OUT[args.backend]
    args.torch_threads = args.torch_threads or "default"
    return args


def main(argv: list[str] | None = None) -> int:
    """Time every env's cold and warm first step and write the JSON file.

    Args:
        argv: the command line's arguments (``sys.argv[1:]`` when None).

    Returns:
        0, or 1 where a run failed.
    """
    args = parse_args(argv)
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
    report = {"command": command.strip(), "machine": machine(args.backend), "rows": rows}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=1) + "\n")
    print(f"wrote {args.out}")
    return int(failed)


if __name__ == "__main__":
    sys.exit(main())
