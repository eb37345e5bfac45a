"""Developer tool: what inductor's settings (:data:`bbgym.backends.INDUCTOR_OPTIONS`) do to
the compiled torch step: its cold compile (the first step, an empty inductor cache) and its
steps/s, for each env and each setting, every run in a fresh process.

    python scripts/bench_inductor.py [--envs BeachballThrow-v1 ...] [--options
        "bbgym" "realize_opcount_threshold=30"] [--num-envs 4096] [--rounds 1]

An option is ``bbgym`` (the package's settings as they are), ``none`` (inductor's own
defaults) or ``key=value,key=value`` (inductor config names, Python literals such as
``22`` or ``False``) over inductor's defaults. Runs are interleaved (env by env, option
by option, ``--rounds`` times) so a busy machine slows them alike; each prints a JSON
line (with ``phases_s``: where the first step's time went, by Dynamo's timers), and the
table at the end keeps each (env, option)'s best rate and its compile times. float32,
one torch thread per run by default (``--torch-threads``), each env's default
``step_graph``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

RUN = r"""
import ast, json, sys, time
import gymnasium as gym
import torch
import bbgym
from bbgym import backends

env_id, option, num_envs, threads, seconds = sys.argv[1:6]
torch.set_num_threads(int(threads))
if option != "bbgym":
    pairs = [] if option == "none" else [kv.split("=") for kv in option.split(",")]
    backends.INDUCTOR_OPTIONS = {k: ast.literal_eval(v) for k, v in pairs}
env = gym.make_vec(env_id, num_envs=int(num_envs), vectorization_mode="vector_entry_point",
                   backend="torch", dtype="float32")
env.action_space.seed(0)
actions = [env.action_space.sample() for _ in range(64)]
env.reset(seed=0)
start = time.perf_counter()
env.step(actions[0])
first = time.perf_counter() - start
env.step(actions[1])
rate = 0.0
for _ in range(3):
    done, start = 0, time.perf_counter()
    while time.perf_counter() - start < float(seconds):
        env.step(actions[done % len(actions)])
        done += 1
    rate = max(rate, done * int(num_envs) / (time.perf_counter() - start))
# Where the first step's time went, from Dynamo's own timers (seconds; nested: inductor's
# kernel code generation is inside its lowering to a module, which is inside the total).
timers = torch._dynamo.utils.compilation_time_metrics
phases = {name: round(sum(timers.get(key, [0.0])), 1) for name, key in [
    ("dynamo_tracing", "bytecode_tracing"), ("inductor", "compile_fx_inner"),
    ("inductor_lowering", "GraphLowering.run"), ("kernel_codegen", "Scheduler.codegen"),
    ("waiting_for_cc", "async_compile.wait")]}
print(json.dumps({"env": env_id, "option": option, "first_step_s": round(first, 1),
                  "rate": round(rate), "phases_s": phases}))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--envs", nargs="+", default=["BeachballSail-v1", "BeachballThrow-v1"])
    parser.add_argument("--options", nargs="+", default=["bbgym", "none"])
    parser.add_argument("--num-envs", type=int, default=4096)
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--torch-threads", type=int, default=1)
    parser.add_argument("--seconds", type=float, default=2.0, help="each timed loop's length")
    args = parser.parse_args()
    rows: dict[tuple[str, str], dict] = {}
    for _ in range(args.rounds):
        for env_id in args.envs:
            for option in args.options:
                with tempfile.TemporaryDirectory() as cache:  # a cold compile each time
                    done = subprocess.run(
                        [
                            sys.executable,
                            "-c",
                            RUN,
                            env_id,
                            option,
                            str(args.num_envs),
                            str(args.torch_threads),
                            str(args.seconds),
                        ],
                        capture_output=True,
                        text=True,
                        check=True,
                        env={**os.environ, "TORCHINDUCTOR_CACHE_DIR": cache},
                    )
                row = json.loads(done.stdout.strip().splitlines()[-1])
                print(json.dumps(row), flush=True)
                kept = rows.setdefault((env_id, option), {"rate": 0, "first_step_s": []})
                kept["rate"] = max(kept["rate"], row["rate"])
                kept["first_step_s"].append(row["first_step_s"])
    print(f"\n| env | inductor options | first step (cold compile) | steps/s, N={args.num_envs} |")
    print("|---|---|---:|---:|")
    for (env_id, option), kept in rows.items():
        firsts = ", ".join(f"{s:.1f} s" for s in kept["first_step_s"])
        print(f"| {env_id} | {option} | {firsts} | {kept['rate']:,} |")


if __name__ == "__main__":
    main()
