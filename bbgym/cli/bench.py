"""Benchmark the bbgym envs against Gymnasium's CartPole, all measured in one run.

    bbgym bench [--quick] [--backends] [--training] [--multi-agent] [--device DEVICE]
        [--out runs/bench] [--seconds S] [--repeats R]
    bbgym bench --scenes [--no-compile]

Prints a markdown table and writes it (``bench.md``) and the raw numbers (``bench.json``)
to ``--out``:

* single env steps/s (``gym.make``, actions sampled before the timed loop), beside
  CartPole-v1, and the ratio;
* native vector env steps/s (``gym.make_vec(..., vectorization_mode="vector_entry_point")``)
  at N = 1, 64, 1024, 4096, beside Gymnasium's native vector CartPole at the same N (for
  the throw envs a step is a whole throw, so these are throws/s);
* stable-baselines3 PPO training throughput (MlpPolicy, 8 envs, the bbgym envs through
  :mod:`bbgym.sb3`, CartPole through SB3's DummyVecEnv; same settings for all), if
  stable-baselines3 is installed;
* ``--training`` (the ``torchrl`` extra): TorchRL PPO's training throughput
  (``bbgym train --engine torchrl``, each env's preset) on ``--device``, timesteps per
  second of collecting and learning after the first batch (which compiles), beside
  stable-baselines3's PPO on CartPole;
* ``--multi-agent`` (or ``--race``; the family's extra: PettingZoo): each family of many
  agents (:func:`bbgym.spec.multi_agent_specs`: the race), in agent-steps per second
  (boat-steps): its PettingZoo env of the spec's agents beside CartPole's single env, and
  its fleet vector env of N / agents episodes beside CartPole's native vector env at the
  same N; with ``--backends`` the fleet on torch too (each of ``--dtypes``, at the
  backend rows' N, on ``--device``), with its first step's time (the compile);
* ``--scenes``: the course's spring system (:mod:`bbgym.scenes`, ``sproing``, its
  three integrators' copies of the grid) at 1,024, 4,096 and 16,384 particles, on NumPy
  and torch float64 (eager, and compiled unless ``--no-compile``), in particle-steps a
  second (the three copies' particles times the steps: flat across the sizes where the
  cost is linear), beside CartPole's native vector env at N = the particles stepped, with
  the first step's time (the compile); and the SPH dam break (``dam-break``) at 1,024 to
  65,536 particles, its neighbours by the uniform grid (NumPy, torch eager and compiled)
  and, at 1,024 and 4,096, by every pair (NumPy), in steps/s with each step's cost over
  the smallest size's: the grid's grows like the particles, every pair's like their square;
* peak memory that a vector env of N = 4096 allocates while stepping (tracemalloc);
* the backends of the native vector envs (``--backends``, needs torch): torch float64 and
  float32, compiled, at N = 1024, 4096, 65536 (and NumPy at 65536), with the compile time
  (the first step: it compiles every part, the autoreset's too) and the bytes of the env's
  state, beside CartPole at the same N (best of ``--repeats`` loops each);
  ``--dtypes`` picks their dtypes;
  ``--step-graph parts one`` times the torch step compiled as its parts and as one graph
  side by side (``step_graph``, :data:`bbgym.backends.STEP_GRAPHS`; by default each env
  as it compiles by default).
  torch runs with ``--torch-threads`` threads (default 2), pinned for every row, the PPO
  rows included;
* ``--jax`` (the ``jax`` extra): the same rows on the JAX backend (each of ``--dtypes``,
  one ``jax.jit`` program a step, its first step the compile), beside torch's and
  CartPole's at the same N; on ``--device cuda`` with JAX arrays in and out where the
  ``jax`` extra (with ``jax[cuda12]``) is installed;
* ``--device cuda``: the GPU check in one command. The torch rows alone, on the GPU with
  tensors in and out (``output="torch"``, the actions made on the device before the timed
  loop, the device synchronized before the clock stops), at N = 4096, 65536 and 2^20,
  beside CartPole's NumPy vector env at the same N on the CPU, and the ``--training``
  rows on the GPU (16384 envs, rollouts of 32 steps, minibatches of 65536); the torch
  rows come both ways, parts and one graph (what decides ``step_graph``'s default on a
  GPU). A device
  torch does not have here is refused, naming ``--device``.

Timed loops are capped at ``--seconds`` each; single-env loops are repeated ``--repeats``
times (best kept).
``--quick`` shrinks everything so the test suite can run the script.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import platform
import time
import tracemalloc
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import bbgym  # noqa: F401  (registers the envs)
from bbgym import backends
from bbgym._extras import extra_needs
from bbgym.backends import STEP_GRAPHS
from bbgym.cli import add_aliased, check_device, positive_float, positive_int, require_all
from bbgym.cli import env_id as env_id_type
from bbgym.spec import MultiAgentSpec, multi_agent_spec_of, multi_agent_specs, newest_ids, spec_of

REFERENCE = "CartPole-v1"

GPU_ENVS = (4096, 65536, 2**20)
"""The batch sizes of ``--device cuda``: up to about 10^6 envs, where a GPU fills."""


SPH_SIZES = (1024, 4096, 16384, 65536)
"""The ``--scenes`` SPH rows' particles (the dam break, neighbours by the grid)."""
SPH_ALL_PAIRS = (1024, 4096)
"""The sizes that also test every pair: at 16,384 one ``(N, N)`` float64 array is 2 GB."""


SCENE_SIZES = (32, 64, 128)
"""The ``--scenes`` rows' grid sides: 1,024, 4,096 and 16,384 particles (times the
three integrators' copies)."""


def per_second(env_id: str) -> str:
    """The unit of a row's rate where an env step is not a plain step (``" throws/s"``)."""
    if env_id == REFERENCE:
        return ""
    if env_id.startswith("scene "):
        return " particle-steps/s"
    agents = multi_agent_spec_of(env_id)
    if agents is not None:  # a PettingZoo id: the steps of every agent, one by one
        return f" {agents.step_unit}/s"
    unit = spec_of(env_id).step_unit
    return "" if unit == "steps" else f" {unit}/s"


def time_single(env_id: str, steps: int, seconds: float, seed: int) -> float:
    """Env-steps per second of one env (``gym.make``, with its wrappers)."""
    env = gym.make(env_id)
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(steps)]
    env.reset(seed=seed)
    for action in actions[:20]:  # warm-up
        if any(env.step(action)[2:4]):
            env.reset()
    env.reset(seed=seed)
    done = 0
    start = time.perf_counter()
    for action in actions:
        _, _, terminated, truncated, _ = env.step(action)
        done += 1
        if terminated or truncated:
            env.reset()
        if done % 16 == 0 and time.perf_counter() - start > seconds:
            break
    elapsed = time.perf_counter() - start
    env.close()
    return done / elapsed


def time_agents(
    spec: MultiAgentSpec, episodes: int, steps: int, seconds: float, seed: int, **backend: Any
) -> dict:
    """Agent-steps per second (``rate``) of a family of many agents (``spec.agents`` an
    episode, seeded random actions): its PettingZoo env (``episodes`` 0) or ``episodes``
    episodes as its fleet vector env (the spec's first vector env class, on ``backend``'s
    keywords; its first step, which compiles on torch, is ``warmup_s`` and not timed)."""
    import numpy as np

    rng = np.random.default_rng(seed)
    n = max(episodes, 1) * spec.agents
    fleet = parallel = None
    fleet_size = {spec.agents_argument: spec.agents}
    if episodes:
        fleet_class = spec.load(spec.vector_env_classes[0])
        fleet = fleet_class(episodes, **fleet_size, **backend)
        size = fleet.single_action_space.shape
    else:
        parallel = spec.load(spec.parallel_env)(**fleet_size)
        size = parallel.action_space(parallel.possible_agents[0]).shape
    actions = rng.uniform(-1.0, 1.0, (min(steps, 256), n, *size)).astype(np.float32)
    if fleet is not None and backend.get("output") == "torch":  # made on the device, untimed
        actions = fleet.xp.asarray(actions, device=fleet.backend.device)
    (fleet or parallel).reset(seed=seed)
    warmup = time.perf_counter()
    if fleet is not None:
        fleet.step(actions[0])
    warmup = time.perf_counter() - warmup
    done, start = 0, time.perf_counter()
    while done < steps and (done % 16 or time.perf_counter() - start < seconds):
        action = actions[done % len(actions)]
        if fleet is not None:
            fleet.step(action)
        else:
            if not parallel.agents:
                parallel.reset()
            parallel.step(
                {
                    a: action[i]
                    for i, a in enumerate(parallel.possible_agents)
                    if a in parallel.agents
                }
            )
        done += 1
    if fleet is not None and fleet.backend.device != "cpu":
        import torch

        torch.cuda.synchronize()
    return {"rate": done * n / (time.perf_counter() - start), "warmup_s": warmup}


def time_vector(
    env_id: str, num_envs: int, steps: int, seconds: float, seed: int, **backend: Any
) -> float:
    """Env-steps per second (``num_envs`` per vector step) of a native vector env."""
    return time_backend(env_id, num_envs, steps, seconds, seed, **backend)["rate"]


def time_backend(
    env_id: str,
    num_envs: int,
    steps: int,
    seconds: float,
    seed: int,
    repeats: int = 1,
    **backend: Any,
) -> dict[str, float]:
    """Steps/s of a native vector env on a backend (best of ``repeats`` timed loops), its
    first step's time (on torch: the compile time of every part of the step, the
    autoreset's included) and the bytes of its state."""
    env = gym.make_vec(
        env_id, num_envs=num_envs, vectorization_mode="vector_entry_point", **backend
    )
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(max(steps, 2))]
    device = backend.get("device", "cpu")
    if backend.get("output") == "torch":  # tensors in, as an on-device learner gives them
        import torch

        actions = [torch.as_tensor(a, device=device) for a in actions]
    if backend.get("output") == "jax":  # JAX arrays on the device, as a JAX learner's
        import jax

        place = env.unwrapped.backend.jax_device
        actions = [jax.device_put(a.astype(np.float32), place) for a in actions]
    env.reset(seed=seed)
    start = time.perf_counter()
    out = env.step(actions[0])  # compiles
    _synchronize(device, out)
    first_step = time.perf_counter() - start
    env.step(actions[1])
    rate = 0.0
    for _ in range(repeats):
        done = 0
        start = time.perf_counter()
        for action in actions:
            out = env.step(action)
            done += 1
            if time.perf_counter() - start > seconds:
                break
        _synchronize(device, out)  # a device's queued steps are done before the clock stops
        rate = max(rate, done * num_envs / (time.perf_counter() - start))
    state_bytes = 0
    state = getattr(env.unwrapped, "state", None)
    if state is not None:
        from bbgym.envs.functional import tree_leaves

        state_bytes = sum(int(getattr(leaf, "nbytes", 0)) for leaf in tree_leaves(state))
    env.close()
    return {"rate": rate, "warmup_s": first_step, "state_mb": state_bytes / 2**20}


def _synchronize(device: str, out: Any = None) -> None:
    """Wait for a device's queued work: JAX's outputs ready, or torch's CUDA stream."""
    if out is not None and backends.is_jax_array(out[0]):
        out[0].block_until_ready()
    elif device.startswith("cuda"):
        import torch

        torch.cuda.synchronize(device)


GRAPH_LABELS = {"auto": "", "parts": ", parts", "one": ", one graph"}
"""The torch rows' kind names by ``--step-graph`` (the default says nothing)."""


def backend_rows(args: argparse.Namespace) -> list[dict[str, Any]]:
    """The backend rows: CartPole, NumPy and torch (float64, float32) at each N; the torch
    rows on ``--device`` (off the CPU, with tensors in and out: ``output="torch"``)."""
    rows: list[dict[str, Any]] = []
    on_device = {} if args.device == "cpu" else {"device": args.device, "output": "torch"}
    jax_device = {} if args.device == "cpu" else {"device": args.device, "output": "jax"}
    where = "" if args.device == "cpu" else f" {args.device}"
    for n in args.backend_envs:
        steps = max(3, args.steps // n)
        reference = max(
            time_vector(REFERENCE, n, steps, args.seconds, args.seed) for _ in range(args.repeats)
        )
        rows.append({"env": REFERENCE, "kind": f"N={n}", "rate": reference, "ratio": 1.0})
        print(f"{REFERENCE} N={n}: {reference:,.0f}/s", flush=True)
        for env_id in args.envs:
            # NumPy beside torch at the larger N, on the CPU only: at a GPU's 2^20 envs
            # a NumPy step takes seconds (it ran out a GPU lease once).
            numpy_row = n > max(args.num_envs) and args.device == "cpu"
            kinds = [("numpy float64", {})] if numpy_row else []
            kinds += [
                (
                    f"torch {d}{where}" + GRAPH_LABELS[graph],
                    {
                        "backend": "torch",
                        "dtype": d,
                        "compile": args.compile,
                        "step_graph": graph,
                        **on_device,
                    },
                )
                for d in args.dtypes
                for graph in args.step_graph
                if args.backends
            ]
            kinds += [
                (
                    f"jax {d}{where}",
                    {"backend": "jax", "dtype": d, "compile": args.compile, **jax_device},
                )
                for d in args.dtypes
                if args.jax
            ]
            for kind, backend in kinds:
                r = time_backend(env_id, n, steps, args.seconds, args.seed, args.repeats, **backend)
                rows.append(
                    {"env": env_id, "kind": f"N={n} {kind}", **r, "ratio": r["rate"] / reference}
                )
                print(
                    f"{env_id} N={n} {kind}: {r['rate']:,.0f}/s, warm-up {r['warmup_s']:.1f} s",
                    flush=True,
                )
    return rows


def vector_memory_mb(env_id: str, num_envs: int, steps: int, seed: int) -> float:
    """Peak memory allocated (tracemalloc: Python objects and NumPy arrays) by making,
    resetting and stepping a native vector env."""
    tracemalloc.start()
    env = gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point")
    env.action_space.seed(seed)
    env.reset(seed=seed)
    for _ in range(steps):
        env.step(env.action_space.sample())
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    env.close()
    return peak / 2**20


def ppo_throughput(env_id: str, timesteps: int, n_steps: int, seed: int) -> float | None:
    """Timesteps per second of ``PPO("MlpPolicy", ...).learn`` with 8 envs (None without
    stable-baselines3)."""
    try:
        from stable_baselines3 import PPO
        from stable_baselines3.common.env_util import make_vec_env
    except ImportError:
        return None
    if env_id == REFERENCE:
        env = make_vec_env(env_id, n_envs=8, seed=seed)
    else:
        from bbgym.sb3 import make_sb3_vec_env

        env = make_sb3_vec_env(env_id, n_envs=8, seed=seed)
    model = PPO("MlpPolicy", env, n_steps=n_steps, seed=seed, device="cpu", verbose=0)
    start = time.perf_counter()
    model.learn(total_timesteps=timesteps)
    elapsed = time.perf_counter() - start
    env.close()
    return model.num_timesteps / elapsed


def torchrl_training_rows(args: argparse.Namespace, reference: float | None) -> list[dict]:
    """TorchRL PPO's training throughput (:func:`bbgym.torchrl.train_ppo`, each env's
    preset ``torchrl`` section) on ``--device`` with ``N`` envs: timesteps per second of
    collecting and learning after the first batch (which compiles), over
    ``--training-batches`` batches, beside stable-baselines3's PPO on CartPole (8 envs, the
    CPU) where that was timed."""
    import tempfile

    from bbgym import torchrl
    from bbgym.config import env_preset, load_torchrl

    rows = []
    for env_id in args.envs:
        path, env_kwargs = env_preset(env_id)
        settings = {**load_torchrl(path), **args.training_settings}
        batch = settings["num_envs"] * settings["n_steps"]
        settings.update(
            total_timesteps=batch * (args.training_batches + 1),
            eval_every_timesteps=10**12,
            eval_episodes=1,
        )
        with tempfile.TemporaryDirectory() as out:
            summary = torchrl.train_ppo(
                env_id,
                settings,
                out=Path(out),
                seed=args.seed,
                device=args.device,
                env_kwargs=env_kwargs,
                log=lambda line: None,
            )
        rate = summary["steady_timesteps_per_s"]
        share = summary["update_time_s"] / summary["train_time_s"]  # learning, not collecting
        rows.append(
            {
                "env": env_id,
                "kind": f"TorchRL PPO N={settings['num_envs']}",
                "rate": rate,
                "ratio": rate / reference if reference else None,
                "first_batch_s": summary["first_batch_s"],
                "update_share": share,
            }
        )
        print(
            f"{env_id} TorchRL PPO on {args.device}: {rate:,.0f} timesteps/s after the "
            f"first batch ({summary['first_batch_s']:.1f} s)",
            flush=True,
        )
    return rows


def machine_info() -> dict[str, Any]:
    return {
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "python": platform.python_version(),
        "cpu_count": os.cpu_count(),
        "numpy": np.__version__,
        "gymnasium": gym.__version__,
        **torch_info(),
        **jax_info(),
    }


def jax_info() -> dict[str, Any]:
    """The installed jax's version (read without importing it), or nothing."""
    from importlib import metadata

    try:
        return {"jax": metadata.version("jax")}
    except metadata.PackageNotFoundError:
        return {}


def torch_info() -> dict[str, Any]:
    try:
        import torch
    except ImportError:
        return {}
    info = {"torch": torch.__version__, "torch_threads": torch.get_num_threads()}
    if torch.cuda.is_available():
        info["gpu"] = torch.cuda.get_device_name(0)
    return info


def prepare_scene(name: str, params: dict[str, Any], backend: str, compile: bool) -> dict[str, Any]:
    """A scene's step on ``backend`` (compiled or eager), its state after a first step, that
    step's time (the compile) and the state's bytes."""
    from bbgym.backends import compiled, resolve_backend
    from bbgym.scenes import get_scene
    from bbgym.scenes.scene import namespace

    scene = get_scene(name)
    p = scene.make_params(params)
    xp = namespace(backend)
    state = scene.initial(p, xp)
    step = lambda s: scene.step(p, s, xp)  # noqa: E731
    if backend == "torch":
        step = compiled(step, resolve_backend("torch", dtype="float64", compile=compile))
    start = time.perf_counter()
    state = step(state)
    first = time.perf_counter() - start
    state_mb = sum(int(getattr(leaf, "nbytes", 0)) for leaf in state) / 2**20
    return {"step": step, "state": state, "warmup_s": first, "state_mb": state_mb}


def time_scene(
    name: str, params: dict[str, Any], backend: str, compile: bool, seconds: float, repeats: int
) -> dict[str, float]:
    """Particle-steps per second of a particle scene (its particles, in every row of its
    batch, times its steps a second; best of ``repeats`` loops of up to ``seconds``) and
    its first step's time and the bytes of its state."""
    run = prepare_scene(name, params, backend, compile)
    step, state = run["step"], run["state"]
    particles = state.x_m.shape[0] * state.x_m.shape[1]
    rate = 0.0
    for _ in range(repeats):
        done, start = 0, time.perf_counter()
        while done < 2 or time.perf_counter() - start < seconds:
            state = step(state)
            done += 1
        rate = max(rate, done * particles / (time.perf_counter() - start))
    return {"rate": rate, "warmup_s": run["warmup_s"], "state_mb": run["state_mb"]}


def scene_rows(args: argparse.Namespace) -> list[dict[str, Any]]:
    """The spring scene at each of :data:`SCENE_SIZES` on NumPy and torch float64 (eager;
    compiled too unless ``--no-compile``), beside CartPole's native vector env at N = the
    particles it steps."""
    rows: list[dict[str, Any]] = []
    kinds = [("numpy", "numpy", False), ("torch float64", "torch", False)]
    if args.compile:
        kinds.append(("torch float64 compiled", "torch", True))
    for size in (4, 8) if args.quick else SCENE_SIZES:
        n = 3 * size * size  # the scene's three integrators' grids
        reference = time_vector(REFERENCE, n, max(2, args.steps // n), args.seconds, args.seed)
        rows.append({"env": REFERENCE, "kind": f"N={n:,}", "rate": reference, "ratio": 1.0})
        for label, backend, compile in kinds:
            r = time_scene("sproing", {"size": size}, backend, compile, args.seconds, args.repeats)
            kind = f"{size * size:,} particles x 3, {label}"
            rows.append({"env": "scene sproing", "kind": kind, **r, "ratio": r["rate"] / reference})
            print(
                f"scene sproing {kind}: {r['rate']:,.0f} particle-steps/s, "
                f"first step {r['warmup_s']:.1f} s",
                flush=True,
            )
    return rows


def sph_rows(args: argparse.Namespace) -> list[dict[str, Any]]:
    """The SPH dam break (``dam-break``) at each of :data:`SPH_SIZES` particles, its
    neighbours by the uniform grid on NumPy and torch float64 (eager; compiled too unless
    ``--no-compile``) and by every pair on NumPy at :data:`SPH_ALL_PAIRS`: steps/s, the
    kinds of one size timed in turn, ``--repeats`` rounds, the best of each kept. Each row's
    ``cost`` is its time per step over its kind's at the smallest size: the grid's grows
    like the particles, all pairs' like their square."""
    sizes = (64, 256) if args.quick else SPH_SIZES
    pairs = sizes if args.quick else SPH_ALL_PAIRS
    kinds = [("grid", "numpy", False), ("grid", "torch", False)]
    if args.compile:
        kinds.append(("grid", "torch", True))
    kinds.append(("all", "numpy", False))
    rows: list[dict[str, Any]] = []
    first: dict[str, float] = {}
    for n in sizes:
        runs = []
        for search, backend, compile in kinds:
            if search == "all" and n not in pairs:
                continue
            label = f"{search}, {backend}" + (" float64" if backend == "torch" else "")
            label += " compiled" if compile else ""
            run = prepare_scene(
                "dam-break", {"particles": n, "neighbour_search": search}, backend, compile
            )
            runs.append((label, run, 0.0))
        for _ in range(args.repeats):  # interleaved: a slow spell of the machine hits all
            for k, (label, run, best) in enumerate(runs):
                done, start = 0, time.perf_counter()
                while done < 2 or time.perf_counter() - start < args.seconds:
                    run["state"] = run["step"](run["state"])
                    done += 1
                runs[k] = (label, run, max(best, done / (time.perf_counter() - start)))
        for label, run, steps_per_s in runs:
            first.setdefault(label, steps_per_s)
            row = {
                "env": "scene dam-break",
                "kind": f"{n:,} particles, {label}",
                "particles": n,
                "neighbours": label,
                "steps_per_s": steps_per_s,
                "rate": steps_per_s * n,
                "cost": first[label] / steps_per_s,
                "warmup_s": run["warmup_s"],
                "state_mb": run["state_mb"],
            }
            rows.append(row)
            print(
                f"scene dam-break {row['kind']}: {steps_per_s:,.2f} steps/s, "
                f"first step {run['warmup_s']:.1f} s",
                flush=True,
            )
            del run["state"]
    return rows


def measure(args: argparse.Namespace) -> dict[str, Any]:
    if args.scenes:  # the scenes' rows alone
        return {
            "rows": [],
            "backend_rows": scene_rows(args),
            "sph_rows": sph_rows(args),
            "memory_mb": {},
            "machine": machine_info(),
        }
    if args.device != "cpu":  # the GPU check: the torch rows alone, one short run
        # The step rows first: they are printed as they come, so a run cut short by a
        # lease's end still has the figures the targets name.
        backend = backend_rows(args)
        reference = ppo_throughput(REFERENCE, args.ppo_timesteps, args.ppo_n_steps, args.seed)
        rows = []
        if reference is not None:
            rows.append({"env": REFERENCE, "kind": "PPO 8 envs", "rate": reference, "ratio": 1.0})
        rows += torchrl_training_rows(args, reference)
        if args.multi_agent:
            rows += [r for spec in multi_agent_specs() for r in agents_backend_rows(spec, args)]
        return {"rows": rows, "backend_rows": backend, "memory_mb": {}, "machine": machine_info()}
    best = lambda fn, *a: max(fn(*a) for _ in range(args.repeats))  # noqa: E731
    rows: list[dict[str, Any]] = []

    reference = best(time_single, REFERENCE, args.steps, args.seconds, args.seed)
    rows.append({"env": REFERENCE, "kind": "single", "rate": reference, "ratio": 1.0})
    for env_id in args.envs:
        rate = best(time_single, env_id, args.steps, args.seconds, args.seed)
        rows.append({"env": env_id, "kind": "single", "rate": rate, "ratio": rate / reference})

    for n in args.num_envs:
        vector_steps = max(2, args.steps // n)
        # Vector loops run once: a throw env's step at N=4096 takes seconds.
        reference = time_vector(REFERENCE, n, vector_steps, args.seconds, args.seed)
        rows.append({"env": REFERENCE, "kind": f"vector N={n}", "rate": reference, "ratio": 1.0})
        for env_id in args.envs:
            rate = time_vector(env_id, n, vector_steps, args.seconds, args.seed)
            row = {"env": env_id, "kind": f"vector N={n}", "rate": rate}
            rows.append({**row, "ratio": rate / reference})

    ppo_reference = ppo_throughput(REFERENCE, args.ppo_timesteps, args.ppo_n_steps, args.seed)
    if ppo_reference is not None:
        rows.append({"env": REFERENCE, "kind": "PPO 8 envs", "rate": ppo_reference, "ratio": 1.0})
        for env_id in args.envs:
            rate = ppo_throughput(env_id, args.ppo_timesteps, args.ppo_n_steps, args.seed)
            rows.append(
                {"env": env_id, "kind": "PPO 8 envs", "rate": rate, "ratio": rate / ppo_reference}
            )

    if args.training:
        rows += torchrl_training_rows(args, ppo_reference)
    if args.multi_agent:
        rows += [r for spec in multi_agent_specs() for r in agents_rows(spec, args)]

    memory = {
        env_id: vector_memory_mb(env_id, args.memory_envs, 2, args.seed) for env_id in args.envs
    }
    backend = backend_rows(args) if args.backends or args.jax else []
    return {"rows": rows, "backend_rows": backend, "memory_mb": memory, "machine": machine_info()}


def agents_rows(spec: MultiAgentSpec, args: argparse.Namespace) -> list[dict[str, Any]]:
    """A family of many agents' rows (:func:`time_agents`): its PettingZoo env beside
    CartPole's single env, and its fleet vector env of ``N / agents`` episodes beside
    CartPole's native vector env at the same N (agent by agent: an agent's step is a
    sub-env's step); with ``--backends`` :func:`agents_backend_rows` too."""
    best = lambda fn, *a: max(fn(*a) for _ in range(args.repeats))  # noqa: E731
    reference = best(time_single, REFERENCE, args.steps, args.seconds, args.seed)
    rate = max(
        time_agents(spec, 0, args.steps, args.seconds, args.seed)["rate"]
        for _ in range(args.repeats)
    )
    kind = f"PettingZoo, {spec.agents} {spec.agent_name}s"
    rows = [{"env": spec.env_id, "kind": kind, "rate": rate, "ratio": rate / reference}]
    for n in args.num_envs:
        episodes = max(n // spec.agents, 1)
        size = episodes * spec.agents
        steps = max(2, args.steps // size)
        reference = time_vector(REFERENCE, size, steps, args.seconds, args.seed)
        rate = time_agents(spec, episodes, steps, args.seconds, args.seed)["rate"]
        kind = f"fleet N={size} ({episodes} {spec.episode_name}{'s' if episodes > 1 else ''})"
        rows.append({"env": spec.env_id, "kind": kind, "rate": rate, "ratio": rate / reference})
    return rows + (agents_backend_rows(spec, args) if args.backends else [])


def agents_backend_rows(spec: MultiAgentSpec, args: argparse.Namespace) -> list[dict[str, Any]]:
    """A family of many agents' fleet on the torch backend (each of ``--dtypes``, compiled
    unless ``--quick``, on ``--device``) at the backend rows' N agents, beside CartPole's
    NumPy vector env at the same N, with the first step's time (the compile)."""
    on_device = {} if args.device == "cpu" else {"device": args.device, "output": "torch"}
    where = "" if args.device == "cpu" else f" {args.device}"
    rows: list[dict[str, Any]] = []
    for n in args.backend_envs:
        episodes = max(n // spec.agents, 1)
        size, steps = episodes * spec.agents, max(3, args.steps // n)
        reference = time_vector(REFERENCE, size, steps, args.seconds, args.seed)
        for dtype in args.dtypes:
            backend = {"backend": "torch", "dtype": dtype, "compile": args.compile, **on_device}
            runs = [
                time_agents(spec, episodes, steps, args.seconds, args.seed, **backend)
                for _ in range(args.repeats)
            ]
            # the best rate; the first run's warm-up, the one that compiled
            r = {"rate": max(run["rate"] for run in runs), "warmup_s": runs[0]["warmup_s"]}
            kind = f"fleet N={size} ({episodes} {spec.episode_name}s) torch {dtype}{where}"
            rows.append({"env": spec.env_id, "kind": kind, **r, "ratio": r["rate"] / reference})
            print(
                f"{spec.env_id} {kind}: {r['rate']:,.0f} {spec.step_unit}/s, "
                f"warm-up {r['warmup_s']:.1f} s",
                flush=True,
            )
    return rows


def format_table(result: dict[str, Any], args: argparse.Namespace) -> str:
    lines = (
        [
            "| env | kind | steps/s | ratio to CartPole-v1 (same kind) |",
            "|---|---|---:|---:|",
        ]
        if result["rows"]
        else []
    )
    for r in result["rows"]:
        unit = "" if "PPO" in r["kind"] else per_second(r["env"])
        ratio = "-" if r["ratio"] is None else f"{r['ratio']:.4f}"
        lines.append(f"| {r['env']} | {r['kind']} | {r['rate']:,.0f}{unit} | {ratio} |")
    if result.get("backend_rows"):
        lines += [
            "",
            "| env | N, backend | steps/s | ratio to CartPole-v1 (same N) | first step "
            "(compile) | state |",
            "|---|---|---:|---:|---:|---:|",
        ]
        for r in result["backend_rows"]:
            unit = per_second(r["env"])
            extra = f"{r['warmup_s']:.1f} s | {r['state_mb']:.1f} MB" if "warmup_s" in r else " | "
            lines.append(
                f"| {r['env']} | {r['kind']} | {r['rate']:,.0f}{unit} | "
                f"{r['ratio']:.4f} | {extra} |"
            )
    if result.get("sph_rows"):
        lines += [
            "",
            "| scene | particles | neighbours, backend | steps/s | particle-steps/s | "
            "cost of a step (x the smallest size's) | first step (compile) |",
            "|---|---:|---|---:|---:|---:|---:|",
        ]
        lines += [
            f"| {r['env']} | {r['particles']:,} | {r['neighbours']} | "
            f"{r['steps_per_s']:,.2f} | {r['rate']:,.0f} | {r['cost']:.1f} | "
            f"{r['warmup_s']:.1f} s |"
            for r in result["sph_rows"]
        ]
    if result["memory_mb"]:
        lines += [
            "",
            f"| env | peak memory of the vector env, N={args.memory_envs} |",
            "|---|---:|",
        ]
        lines += [f"| {env_id} | {mb:.1f} MB |" for env_id, mb in result["memory_mb"].items()]
    m = result["machine"]
    lines += [
        "",
        f"machine: {m['platform']}, {m['cpu_count']} CPUs, python {m['python']}, "
        f"numpy {m['numpy']}, gymnasium {m['gymnasium']}, torch {m.get('torch', '-')} "
        f"({m.get('torch_threads', '-')} threads)" + (f", {m['gpu']}" if m.get("gpu") else ""),
        f"settings: {args.steps} steps per loop, loops capped at {args.seconds} s, best of "
        f"{args.repeats}; PPO: MlpPolicy, 8 envs, n_steps {args.ppo_n_steps}, "
        f"{args.ppo_timesteps} timesteps"
        + (
            f"; TorchRL PPO: the preset's settings, {args.training_batches} batches after the "
            f"first, on {args.device}"
            if args.training
            else ""
        ),
    ]
    return "\n".join(lines)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--quick", action="store_true", help="tiny sizes (the test suite)")
    parser.add_argument("--out", type=Path, default=Path("runs/bench"), help="output folder")
    parser.add_argument(
        "--steps", type=positive_int, default=20000, help="env-steps per timed loop"
    )
    parser.add_argument(
        "--seconds", type=positive_float, default=2.0, help="cap of each timed loop"
    )
    parser.add_argument("--repeats", type=positive_int, default=2, help="repeats, the best is kept")
    parser.add_argument("--seed", type=int, default=0, help="seed of the envs and actions")
    parser.add_argument("--backends", action="store_true", help="add the torch backend rows")
    parser.add_argument(
        "--jax",
        action="store_true",
        help="add the JAX backend rows (the jax extra; with --device cuda where it is installed)",
    )
    parser.add_argument(
        "--torch-threads", type=positive_int, default=2, help="torch's thread count"
    )
    add_aliased(
        parser,
        "--envs",
        "--env",
        nargs="+",
        type=env_id_type,
        default=newest_ids(),
        help=f"the envs to time (default: the newest version of each, {' '.join(newest_ids())})",
    )
    parser.add_argument(
        "--no-compile",
        dest="compile",
        action="store_false",
        help="torch rows eager (no torch.compile)",
    )
    parser.add_argument(
        "--step-graph",
        nargs="+",
        choices=STEP_GRAPHS,
        default=None,
        help="how the torch rows compile the step: auto (as each env "
        "compiles unasked), as its parts, as one graph, or several "
        "side by side (default: auto; with --device cuda parts and "
        "one)",
    )
    parser.add_argument(
        "--dtypes",
        nargs="+",
        choices=("float64", "float32"),
        default=["float64", "float32"],
        help="the torch rows' dtypes (default: float64 float32)",
    )
    parser.add_argument(
        "--training",
        action="store_true",
        help="add TorchRL PPO's training throughput (the torchrl extra; always with --device cuda)",
    )
    parser.add_argument(
        "--multi-agent",
        "--race",
        dest="multi_agent",
        action="store_true",
        help="add the rows of the families of many agents (the race; their extra: PettingZoo)",
    )
    parser.add_argument(
        "--scenes",
        action="store_true",
        help="only the course's spring and SPH scenes, on NumPy and torch (the torch extra)",
    )
    parser.add_argument(
        "--device",
        default="cpu",
        help="the torch rows' device; off the CPU (cuda) only those rows run, "
        f"at N up to {GPU_ENVS[-1]:,}, tensors kept on the device "
        "(default: cpu)",
    )


def _sizes(args: argparse.Namespace) -> None:
    """The batch sizes and budgets of the timed loops (tiny with ``--quick``)."""
    args.envs = tuple(args.envs)
    args.num_envs = (1, 64, 1024, 4096)
    args.backend_envs = (1024, 4096, 65536)
    args.memory_envs = 4096
    args.ppo_timesteps, args.ppo_n_steps = 2048, 256
    args.training_batches, args.training_settings = 4, {}
    if args.step_graph is None:
        args.step_graph = ["parts", "one"] if args.device != "cpu" else ["auto"]
    if args.device != "cpu":
        args.backends = args.training = True
        args.jax = args.jax or importlib.util.find_spec("jax") is not None
        args.backend_envs = GPU_ENVS
        # Many envs per batch: a GPU's steps are cheap, its launches are not.
        args.training_settings = {"num_envs": 16384, "n_steps": 32, "minibatch_size": 65536}
    if args.quick:
        args.steps, args.seconds, args.repeats = 40, 0.2, 1
        args.num_envs = (1, 8)
        args.memory_envs = 64
        args.ppo_timesteps, args.ppo_n_steps = 64, 8
        args.backend_envs = (8,)
        args.compile = False
        args.training_batches = 1
        args.training_settings = {
            "num_envs": 8,
            "n_steps": 4,
            "minibatch_size": 16,
            "n_epochs": 1,
            "compile_step": False,
        }


def needs(args: argparse.Namespace) -> list[tuple[str, str]]:
    """``(module, extra)`` the run needs: the ``torch`` extra for ``--backends``, the
    ``torchrl`` extra for ``--training`` or a ``--device`` (the stable-baselines3 PPO rows
    are timed only where it is installed)."""
    multi = (
        [n for s in multi_agent_specs() for n in extra_needs(s.extra)] if args.multi_agent else []
    )
    if args.scenes:
        return extra_needs("torch")
    jax = extra_needs("jax") if args.jax else []
    if args.training or args.device != "cpu":
        return extra_needs("torchrl") + jax + multi
    return (extra_needs("torch") if args.backends else []) + jax + multi


def run(args: argparse.Namespace) -> int:
    _sizes(args)
    require_all(needs(args))
    if args.device != "cpu":
        check_device(args.device, "--device")
    try:
        import torch

        torch.set_num_threads(args.torch_threads)  # pinned: every torch row, PPO included
    except ImportError:
        pass
    start = time.perf_counter()
    result = measure(args)
    table = format_table(result, args)
    print(table)
    print(f"total {time.perf_counter() - start:.0f} s")
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "bench.md").write_text(table + "\n")
    (args.out / "bench.json").write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {args.out / 'bench.md'} and {args.out / 'bench.json'}")
    return 0
