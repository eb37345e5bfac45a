"""Developer tool: what the torch backend's compile costs and what it buys (the compile
figures of docs/pages/speed.md and speed-torch.md).

    python scripts/bench_compile.py [--modes static dynamic] [--sizes 64 1024] [--numpy]

For each batch size in turn: the first step's time (where every part of the step compiles)
and the graphs Dynamo traced for it, and how far 40 compiled steps are from eager torch;
then the first step of a second env of the first size (does it reuse the graphs?). Then
the steps/s of every env, best of ``--repeats`` 2-second loops, interleaved (and, with
``--numpy``, the NumPy backend at the same sizes), so a busy machine slows them alike.
Mode ``static`` is bbgym's ``torch.compile(..., dynamic=False)``; ``dynamic`` overrides it
with ``dynamic=True`` (a batch dimension symbolic from the first compile), to measure
whether one graph could serve every batch size, and compiles copies of the step's code
objects (Dynamo keeps graphs per code object: the two modes' envs would otherwise share one
mode's graphs). The modes' compiled observations and rewards are compared bit for bit. Run
it twice with the same ``TORCHINDUCTOR_CACHE_DIR`` to see a cold and then a warm compile
cache (the cache's keys include torch's thread count).
"""

from __future__ import annotations

import argparse
import json
import time
import types

import gymnasium as gym
import numpy as np
import torch
from torch._dynamo.utils import counters

import bbgym  # noqa: F401  (registers the envs)


def make(env_id: str, n: int, **backend: object) -> gym.vector.VectorEnv:
    return gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point", **backend)


def run(env: gym.vector.VectorEnv, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Observations and rewards of ``actions`` from a seeded reset."""
    env.reset(seed=1)
    out = [env.step(a)[:2] for a in actions]
    return np.array([o for o, _ in out]), np.array([r for _, r in out])


_COPIES: dict = {}


def own_code(fn: object) -> object:
    """``fn`` (a function or bound method) running a copy of its code object, one copy per
    original shared by every env, so a second mode gets graphs of its own."""
    func = getattr(fn, "__func__", fn)
    code = func.__code__
    if code not in _COPIES:
        _COPIES[code] = code.replace(co_name=f"{code.co_name}_dynamic")
    copy = types.FunctionType(
        _COPIES[code], func.__globals__, func.__name__, func.__defaults__, func.__closure__
    )
    return types.MethodType(copy, fn.__self__) if hasattr(fn, "__self__") else copy


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default="BeachballSail-v0")
    parser.add_argument("--dtype", default="float64", choices=("float64", "float32"))
    parser.add_argument(
        "--modes", nargs="+", default=["static", "dynamic"], choices=("static", "dynamic")
    )
    parser.add_argument("--sizes", type=int, nargs="+", default=[64, 1024])
    parser.add_argument("--numpy", action="store_true", help="time the NumPy backend too")
    parser.add_argument("--repeats", type=int, default=3, help="timed loops, the best kept")
    parser.add_argument("--torch-threads", type=int, default=2)
    args = parser.parse_args()
    torch.set_num_threads(args.torch_threads)
    torch_backend = {"backend": "torch", "dtype": args.dtype}
    result: dict = {"args": vars(args), "first_step_s": {}, "graphs": {}, "max_diff": {}}
    envs, saved = {}, {}
    actions = {n: np.random.default_rng(n).uniform(-1, 1, (300, n, 2)) for n in args.sizes}
    real_compile = torch.compile
    for mode in args.modes:
        # each env's parts are compiled when its first step runs, under this torch.compile
        if mode == "dynamic":
            torch.compile = lambda fn, **kw: real_compile(own_code(fn), **{**kw, "dynamic": True})
        else:
            torch.compile = real_compile
        for n in [*args.sizes, args.sizes[0]]:
            name = f"{mode} N={n}" + (" (second env)" if f"{mode} N={n}" in envs else "")
            env = make(args.env, n, **torch_backend)
            env.reset(seed=1)
            graphs, start = counters["stats"]["unique_graphs"], time.perf_counter()
            env.step(actions[n][0])
            result["first_step_s"][name] = round(time.perf_counter() - start, 1)
            result["graphs"][name] = counters["stats"]["unique_graphs"] - graphs
            compiled = run(env, actions[n][:40])
            saved[f"{mode}_obs{n}"], saved[f"{mode}_reward{n}"] = compiled
            eager = run(make(args.env, n, **torch_backend, compile=False), actions[n][:40])
            result["max_diff"][name] = max(
                float(np.max(np.abs(c - e))) for c, e in zip(compiled, eager, strict=True)
            )
            print(
                f"{name}: first step {result['first_step_s'][name]} s, "
                f"{result['graphs'][name]} graphs, "
                f"max |compiled - eager| {result['max_diff'][name]}",
                flush=True,
            )
            if not name.endswith("(second env)"):
                envs[name] = (env, actions[n])
    torch.compile = real_compile
    if len(args.modes) == 2:
        result["modes_bit_identical"] = all(
            np.array_equal(saved[k], saved[k.replace("static", "dynamic", 1)])
            for k in saved
            if k.startswith("static")
        )
    if args.numpy:
        envs.update({f"numpy N={n}": (make(args.env, n), actions[n]) for n in args.sizes})
    rates: dict[str, float] = {}
    for env, _ in envs.values():
        env.reset(seed=2)
    for _ in range(args.repeats):
        for name, (env, acts) in envs.items():
            done, start = 0, time.perf_counter()
            while time.perf_counter() - start < 2.0:
                env.step(acts[done % len(acts)])
                done += 1
            rate = done * env.num_envs / (time.perf_counter() - start)
            rates[name] = max(rates.get(name, 0.0), round(rate))
    result["steps_per_s"] = rates
    print(json.dumps(result), flush=True)


if __name__ == "__main__":
    main()
