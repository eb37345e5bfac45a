"""Developer tool: the torch backend's step compiled as its parts (the default) or as one
graph (``step_graph="one"``), each with every info or with ``info_keys=["is_success"]``
(the figures of docs/pages/speed-torch-cpu.md, "The step as one graph").

    python scripts/bench_fused.py [--envs BeachballSail-v1 BeachballThrow-v0] [--sizes 4096]

For each env and batch size, in a fresh inductor cache (a temporary
``TORCHINDUCTOR_CACHE_DIR``, so a first step compiles what no earlier row compiled): each
variant's first step (the compile) and its steps/s (throws/s for the ball envs), best of
``--repeats`` loops of ``--seconds``, interleaved, and how far its observations and
rewards are from the parts'.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

os.environ["TORCHINDUCTOR_CACHE_DIR"] = tempfile.mkdtemp(prefix="bbgym-fused-")

import gymnasium as gym  # noqa: E402
import numpy as np  # noqa: E402
import torch  # noqa: E402

import bbgym  # noqa: E402, F401  (registers the envs)


def make(
    env_id: str, n: int, dtype: str, info_keys: list[str] | None, step_graph: str
) -> gym.vector.VectorEnv:
    return gym.make_vec(
        env_id,
        num_envs=n,
        vectorization_mode="vector_entry_point",
        backend="torch",
        dtype=dtype,
        output="torch",
        info_keys=info_keys,
        step_graph=step_graph,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--envs", nargs="+", default=["BeachballSail-v1", "BeachballThrow-v0"])
    parser.add_argument("--sizes", nargs="+", type=int, default=[4096])
    parser.add_argument("--dtype", default="float32")
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--torch-threads", type=int, default=2)
    args = parser.parse_args()
    torch.set_num_threads(args.torch_threads)
    print(
        f"torch {torch.__version__}, {args.torch_threads} threads, {args.dtype}, "
        f"cache {os.environ['TORCHINDUCTOR_CACHE_DIR']}"
    )
    for env_id in args.envs:
        for n in args.sizes:
            variants = {
                "parts": (None, "parts"),
                "parts, 1 info": (["is_success"], "parts"),
                "one graph": (None, "one"),
                "one graph, 1 info": (["is_success"], "one"),
            }
            envs = {name: make(env_id, n, args.dtype, *v) for name, v in variants.items()}
            shape = (n, *envs["parts"].single_action_space.shape)
            rng = np.random.default_rng(0)
            actions = [
                torch.as_tensor(rng.uniform(-1, 1, shape), dtype=getattr(torch, args.dtype))
                for _ in range(16)
            ]
            first, outs = {}, {}
            for name, env in envs.items():
                env.reset(seed=0)
                start = time.perf_counter()
                out = [env.step(actions[0])]
                first[name] = time.perf_counter() - start
                out += [env.step(a) for a in actions[1:]]
                outs[name] = out
            for name in list(envs)[1:]:
                worst = max(
                    float((a[k] - b[k]).abs().max())
                    for a, b in zip(outs["parts"], outs[name], strict=True)
                    for k in (0, 1)
                )
                print(
                    f"{env_id} N={n} {name}: max |difference| from parts {worst:.1e} "
                    "(observations, rewards)"
                )
                assert worst < 1e-4, name
            rates = {name: 0.0 for name in envs}
            for _ in range(args.repeats):
                for name, env in envs.items():
                    steps, start = 0, time.perf_counter()
                    while time.perf_counter() - start < args.seconds:
                        env.step(actions[steps % 16])
                        steps += 1
                    rates[name] = max(rates[name], steps * n / (time.perf_counter() - start))
            for name in envs:
                print(
                    f"{env_id} N={n} {name}: first step {first[name]:.1f} s, "
                    f"{rates[name]:,.0f} steps/s ({rates[name] / rates['parts']:.2f}x parts)"
                )
            for env in envs.values():
                env.close()


if __name__ == "__main__":
    main()
