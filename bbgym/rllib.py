"""Scale-out PPO training with Ray RLlib's new API stack (RLModule, Learner, EnvRunner).

Needs the ``rllib`` extra (``ray[rllib]`` and torch); ``import bbgym`` never imports ray,
this module imports it inside its functions only.

    from bbgym.rllib import train

    summary = train(env_id, iterations=50, num_env_runners=4, out="runs/rllib")

Every env runner steps one of bbgym's native vector envs: RLlib's ``SingleAgentEnvRunner``
builds its envs with ``gym.make_vec(config.env, num_envs=..., vectorization_mode=
config.gym_env_vectorize_mode, **config.env_config)``, and :func:`ppo_config` sets that mode
to ``VectorizeMode.VECTOR_ENTRY_POINT``, so the registered ``vector_entry_point`` (the
family's :attr:`~bbgym.spec.EnvSpec.vector_env_class`) is what runs, not a
``SyncVectorEnv`` of single envs. The env runners are separate processes, possibly on
other machines, which have not imported bbgym: :func:`ppo_config` names the env
``"bbgym:<env id>"``, the ``module:id`` form with which Gymnasium itself imports
``bbgym`` (and so registers its ids) in whatever process makes the env. That needs no
Ray state, so a checkpoint restored by a fresh driver, on a fresh cluster, finds its envs
too. (:func:`register_envs` covers
configs written by hand with the plain ids.)

One module on purpose, though it is past 600 lines: it is the whole adapter to one optional
dependency, in the order a run goes (the env for the runners, the PPO config from a preset,
starting Ray, the training loop and its summary, loading a checkpoint and acting), and every
part meets Ray's API: split, each piece would import ray's internals on its own and hide
the one place that tracks Ray's releases. No function in it is past 80 lines.
"""

from __future__ import annotations

import contextlib
import functools
import json
import math
import os
import time
import warnings
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import gymnasium as gym
import numpy as np

# (Importing any bbgym module runs bbgym/__init__.py, which registers the ids.)
from bbgym._files import write_text_atomic
from bbgym.config import env_preset, load_training, preset_files

if TYPE_CHECKING:  # ray is an optional dependency
    from ray.rllib.algorithms.ppo import PPOConfig
    from ray.rllib.core.rl_module.rl_module import RLModule

CHECKPOINT_DIR = "checkpoint"
SUMMARY_FILE = "rllib.json"


def _require_ray() -> None:
    """Fail with the fix rather than a bare ``ModuleNotFoundError`` deep in a call."""
    try:
        import ray.rllib  # noqa: F401
    except ImportError as e:
        from bbgym._extras import install_hint

        raise ImportError(
            f"bbgym.rllib needs Ray RLlib and torch (the 'rllib' extra): {install_hint('rllib')}"
        ) from e


def _check_env_id(env_id: str) -> None:
    files = preset_files()
    if env_id not in files:
        raise ValueError(f"env_id must be one of {sorted(files)}, got {env_id!r}")


def _make_env(env_id: str, env_config: Mapping[str, Any]) -> gym.Env | gym.vector.VectorEnv:
    """The env creator :func:`register_envs` registers: a native vector env when RLlib asks
    for ``num_envs`` (``VECTOR_ENTRY_POINT`` mode), else one single env (``sync`` mode, which
    calls the creator once per sub-env). A module-level function (bound with
    ``functools.partial``) pickles by reference, so unpickling it in an env runner imports
    this module, hence the ``bbgym`` package, which registers the ids there."""
    kwargs = dict(env_config)
    num_envs = kwargs.pop("num_envs", None)
    if num_envs is None:
        return gym.make(env_id, **kwargs)
    return gym.make_vec(
        env_id,
        num_envs=int(num_envs),
        vectorization_mode=gym.VectorizeMode.VECTOR_ENTRY_POINT,
        **kwargs,
    )


def register_envs() -> list[str]:
    """Register bbgym's env ids with Ray Tune's env registry and return them.

    Only needed for configs written by hand as ``config.environment(env_id)``
    (:func:`ppo_config` uses ``"bbgym:<id>"``, which needs nothing). RLlib's env runner looks
    a string env up in that registry first, which Ray stores in the cluster (so every worker,
    on every node, sees it); the creator is :func:`_make_env`, whose import in the worker
    registers the ids with Gymnasium there. Call it in the driver after (or before)
    ``ray.init``: the registry flushes to a cluster started later. Each new driver (job)
    must call it again, since the registry is kept per job.
    """
    _require_ray()
    from ray.tune.registry import register_env

    for env_id in preset_files():
        register_env(env_id, functools.partial(_make_env, env_id))
    return list(preset_files())


def preset_env_kwargs(env_id: str, preset: str | Path | None = None) -> dict[str, Any]:
    """The env kwargs of ``env_id``'s preset, as the SB3 training builds them
    (:func:`bbgym.config.env_preset`)."""
    _check_env_id(env_id)
    return env_preset(env_id, preset)[1]


def _positive(name: str, value: Any, minimum: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an int >= {minimum}, got {value!r}")
    return int(value)


def ppo_config(
    env_id: str,
    *,
    num_env_runners: int = 1,
    num_envs_per_env_runner: int | None = None,
    seed: int | None = 0,
    env_kwargs: Mapping[str, Any] | None = None,
    preset: str | Path | None = None,
    train_batch_size: int | None = None,
    minibatch_size: int | None = None,
    num_epochs: int | None = None,
    lr: float | None = None,
    gamma: float | None = None,
    net_arch: list[int] | None = None,
    rollout_fragment_length: int | str = "auto",
    **training: Any,
) -> PPOConfig:
    """A CPU-only PPO config on RLlib's new API stack for ``env_id``, from its preset.

    The preset's ``ppo`` section (stable-baselines3's arguments) maps where RLlib has the
    same knob, so both engines start from the same tuning: ``learning_rate`` -> ``lr`` (a
    ``lin_`` schedule gives its initial value), ``gamma``, ``gae_lambda`` -> ``lambda_``,
    ``clip_range`` -> ``clip_param``, ``ent_coef`` -> ``entropy_coeff``, ``n_epochs`` ->
    ``num_epochs``, ``batch_size`` -> ``minibatch_size``, ``max_grad_norm`` -> ``grad_clip``
    (global norm), ``n_steps * train.n_envs`` -> ``train_batch_size_per_learner``,
    ``policy_kwargs.net_arch`` -> ``fcnet_hiddens`` with separate policy and value networks
    and tanh (SB3's ``MlpPolicy``). SB3 has no KL penalty, so neither has this
    (``use_kl_loss=False``); gSDE, ``squash_output``, ``log_std_init`` and the preset's
    ``normalize_reward`` have no RLlib counterpart and are left out. Keyword arguments
    override the preset; further ones (``**training``) go to ``PPOConfig.training`` as
    they are (``entropy_coeff=0.01``).

    ``env_kwargs`` update the preset's env kwargs (``max_episode_steps`` among them sets the
    native vector env's time limit). ``num_envs_per_env_runner`` defaults to the preset's
    ``n_envs``: each runner keeps the batch its vector env is fast at, and more runners
    sample more per iteration only if ``train_batch_size`` grows with them (the fragment
    each env steps per iteration, ``rollout_fragment_length="auto"``, shrinks instead).
    """
    _require_ray()
    _check_env_id(env_id)
    runners = _positive("num_env_runners", num_env_runners, minimum=0)
    ppo, train_settings = _ppo_preset(env_id, preset)
    envs = _positive(
        "num_envs_per_env_runner",
        train_settings["n_envs"] if num_envs_per_env_runner is None else num_envs_per_env_runner,
    )
    kwargs = {**preset_env_kwargs(env_id, preset), **dict(env_kwargs or {})}
    params = _ppo_training_params(
        ppo,
        train_settings["n_envs"],
        train_batch_size=train_batch_size,
        minibatch_size=minibatch_size,
        num_epochs=num_epochs,
        lr=lr,
        gamma=gamma,
    )
    params.update(training)
    if net_arch is None:
        net_arch = (ppo.get("policy_kwargs") or {}).get("net_arch")
    return _assemble_ppo_config(
        env_id,
        kwargs,
        num_env_runners=runners,
        num_envs_per_env_runner=envs,
        rollout_fragment_length=rollout_fragment_length,
        params=params,
        net_arch=net_arch,
        seed=seed,
    )


def _ppo_preset(env_id: str, preset: str | Path | None) -> tuple[dict[str, Any], dict[str, Any]]:
    """The ``ppo`` section and the ``train`` settings of ``env_id``'s preset (or of
    ``preset``); ``ValueError`` for a preset of another algorithm, which RLlib does not
    train here."""
    ppo, train_settings = load_training(env_id if preset is None else preset)
    if train_settings["algo"] != "ppo":
        algo = train_settings["algo"]
        raise ValueError(f"preset: RLlib trains PPO presets; this one trains {algo}")
    return ppo, train_settings


def _initial_value(value: Any) -> float:
    """A number, or a ``LinearSchedule``'s start (a preset's ``lin_`` value): RLlib takes a
    constant."""
    return float(getattr(value, "initial", value))


def _ppo_training_params(
    ppo: Mapping[str, Any],
    n_envs: int,
    *,
    train_batch_size: int | None,
    minibatch_size: int | None,
    num_epochs: int | None,
    lr: float | None,
    gamma: float | None,
) -> dict[str, Any]:
    """``PPOConfig.training``'s arguments: the preset's ``ppo`` section (SB3's names and
    defaults) mapped to RLlib's, as :func:`ppo_config` lists, where an argument given here
    does not override it; ``ValueError`` for a batch, minibatch or epoch count that is not
    a positive int, or a minibatch larger than the batch."""
    batch = train_batch_size
    if batch is None:
        batch = ppo.get("n_steps", 2048) * n_envs
    batch = _positive("train_batch_size", batch)
    if minibatch_size is None:
        minibatch_size = min(ppo.get("batch_size", 64), batch)
    minibatch = _positive("minibatch_size", minibatch_size)
    if minibatch > batch:
        raise ValueError(f"minibatch_size ({minibatch}) must be <= train_batch_size ({batch})")
    return {
        "lr": _initial_value(lr if lr is not None else ppo.get("learning_rate", 3e-4)),
        "gamma": float(gamma if gamma is not None else ppo.get("gamma", 0.99)),
        "lambda_": float(ppo.get("gae_lambda", 0.95)),
        "clip_param": _initial_value(ppo.get("clip_range", 0.2)),
        "entropy_coeff": float(ppo.get("ent_coef", 0.0)),
        "num_epochs": _positive(
            "num_epochs", ppo.get("n_epochs", 10) if num_epochs is None else num_epochs
        ),
        "minibatch_size": minibatch,
        "train_batch_size_per_learner": batch,
        "grad_clip": float(ppo.get("max_grad_norm", 0.5)),
        "grad_clip_by": "global_norm",
        "use_kl_loss": False,
    }


def _assemble_ppo_config(
    env_id: str,
    env_config: dict[str, Any],
    *,
    num_env_runners: int,
    num_envs_per_env_runner: int,
    rollout_fragment_length: int | str,
    params: dict[str, Any],
    net_arch: list[int] | None,
    seed: int | None,
) -> PPOConfig:
    """The ``PPOConfig`` of checked arguments: the new API stack, every env runner
    stepping a native vector env, everything on the CPU; the policy and value networks
    separate MLPs of ``net_arch`` (default two of 64) with tanh, as SB3's ``MlpPolicy``."""
    from ray.rllib.algorithms.ppo import PPOConfig
    from ray.rllib.core.rl_module.default_model_config import DefaultModelConfig

    model = DefaultModelConfig(
        fcnet_hiddens=list(net_arch or [64, 64]), fcnet_activation="tanh", vf_share_layers=False
    )
    return (
        PPOConfig()
        .api_stack(enable_rl_module_and_learner=True, enable_env_runner_and_connector_v2=True)
        # "bbgym:<id>": Gymnasium imports bbgym in the env runner before it looks the id up.
        # is_atari=False: RLlib would otherwise make an env in the driver to find out.
        # Every bbgym action space is Box(-1, 1) and every env clips its actions (NaN
        # raises), so RLlib's per-env unsquash-and-clip connector (0.3 of 0.7 s per 4096
        # Sail steps) would change nothing: off. The episodes keep the sampled actions.
        .environment(
            env=f"bbgym:{env_id}",
            env_config=env_config,
            is_atari=False,
            normalize_actions=False,
            clip_actions=False,
        )
        .env_runners(
            num_env_runners=num_env_runners,
            num_envs_per_env_runner=num_envs_per_env_runner,
            gym_env_vectorize_mode=gym.VectorizeMode.VECTOR_ENTRY_POINT,
            rollout_fragment_length=rollout_fragment_length,
            num_cpus_per_env_runner=1,
            num_gpus_per_env_runner=0,
        )
        .learners(num_learners=0, num_gpus_per_learner=0)
        .resources(num_gpus=0)
        .training(**params)
        .rl_module(model_config=model)
        .debugging(seed=seed)
    )


def _metric(results: Mapping[str, Any], *keys: str) -> float | None:
    """A finite number at ``results[k0][k1]...``, else None (RLlib leaves a key out, or
    reports NaN, until an episode has ended)."""
    value: Any = results
    for key in keys:
        if not isinstance(value, Mapping) or key not in value:
            return None
        value = value[key]
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


def _start_ray(
    address: str | None,
    num_cpus: int | None,
    num_env_runners: int,
    runtime_env: Mapping[str, Any] | None,
    log_to_driver: bool,
) -> bool:
    """Connect to (``address``) or start a Ray cluster; True when this call initialised Ray
    (so :func:`train` calls ``ray.shutdown()``, which stops a local cluster and only
    disconnects from one started with ``ray start``). Without ``address`` it connects to
    ``RAY_ADDRESS`` where that is set (a job submitted with ``ray job submit``), else starts
    a new local cluster of ``num_cpus`` CPUs (default: one per env runner, at least 1)
    rather than every core of the machine."""
    import ray

    if address is not None and num_cpus is not None:
        raise ValueError("num_cpus sizes a local cluster: leave it out with address")
    cpus = max(1, num_env_runners) if num_cpus is None else _positive("num_cpus", num_cpus)
    if cpus < num_env_runners:
        # Each env runner holds a CPU: the others would wait for one forever.
        raise ValueError(
            f"num_cpus ({cpus}) must be >= num_env_runners ({num_env_runners}): "
            "each env runner reserves one CPU"
        )
    if ray.is_initialized():
        return False
    options: dict[str, Any] = {
        "include_dashboard": False,
        "log_to_driver": log_to_driver,
        "runtime_env": dict(runtime_env) if runtime_env else None,
    }
    if address is None and os.environ.get("RAY_ADDRESS"):
        # A driver that `ray job submit` runs on a cluster: connect to it.
        ray.init(**options)
    elif address is None:
        # "local": a new cluster even where `ray start` left its address in
        # /tmp/ray/ray_current_cluster (ray.init() would connect to that one instead).
        ray.init(address="local", num_cpus=cpus, **options)
    else:
        ray.init(address=address, **options)
    return True


def train(
    env_id: str,
    *,
    iterations: int,
    num_env_runners: int = 1,
    num_envs_per_env_runner: int | None = None,
    seed: int = 0,
    out: str | Path | None = None,
    address: str | None = None,
    num_cpus: int | None = None,
    env_kwargs: Mapping[str, Any] | None = None,
    preset: str | Path | None = None,
    runtime_env: Mapping[str, Any] | None = None,
    log_to_driver: bool = False,
    learner_threads: int | None = 1,
    callback: Callable[[dict[str, Any]], None] | None = None,
    **overrides: Any,
) -> dict[str, Any]:
    """Train PPO with RLlib for ``iterations`` iterations; save and summarise the run.

    Starts a local Ray cluster (``address=None``; ``num_cpus`` CPUs, default one per env
    runner; where ``RAY_ADDRESS`` is set, as ``ray job submit`` does, it connects there) or
    connects to one (``address="auto"`` on a node of a cluster started with ``ray start``,
    ``"<head>:6379"``, or ``"ray://<head>:10001"`` through Ray Client); an already
    initialised Ray is used as it is. ``num_env_runners`` processes (0: sample in
    the driver) each step a native vector env of ``num_envs_per_env_runner`` envs; the
    learner updates in the driver, on the CPU. ``runtime_env`` goes to ``ray.init``
    (``{"pip": ["bbgym"]}`` or ``{"py_modules": [...]}`` where the nodes lack bbgym).
    ``learner_threads`` caps torch's threads in the driver while it trains (``None``: torch's
    default, every core): the minibatches of these small MLPs gain nothing from more, and
    threads that compete with env runners and other work for the cores slowed one update of
    the Sail preset from 0.28 s to 1.8 s on a loaded 2-core machine.
    ``callback`` receives each iteration's row of the summary's ``history`` (progress
    printing). The other keyword arguments (``train_batch_size``, ``minibatch_size``,
    ``num_epochs``, ``lr``, ``gamma``, ...) go to :func:`ppo_config`.

    Writes the checkpoint to ``<out>/checkpoint`` (``Algorithm.from_checkpoint`` restores
    it; :func:`load_rl_module` loads just the policy) and the summary to
    ``<out>/rllib.json``, which is also returned. ``ray.shutdown()`` follows only if this
    call initialised Ray: it stops the local cluster, or disconnects from a remote one (which
    keeps running); a Ray the caller initialised stays up.
    """
    _require_ray()
    import ray

    _check_env_id(env_id)
    iterations = _positive("iterations", iterations)
    num_env_runners = _positive("num_env_runners", num_env_runners, minimum=0)
    if learner_threads is not None:
        learner_threads = _positive("learner_threads", learner_threads)
    out = Path(out) if out is not None else Path("runs") / "rllib" / f"{env_id}-seed{seed}"
    # Build the config before Ray starts: a bad argument then costs no cluster.
    config = ppo_config(
        env_id,
        num_env_runners=num_env_runners,
        num_envs_per_env_runner=num_envs_per_env_runner,
        seed=seed,
        env_kwargs=env_kwargs,
        preset=preset,
        **overrides,
    )
    out.mkdir(parents=True, exist_ok=True)
    started = _start_ray(address, num_cpus, num_env_runners, runtime_env, log_to_driver)
    try:
        return _train_and_save(
            config,
            out,
            env_id=env_id,
            seed=seed,
            iterations=iterations,
            address=address,
            learner_threads=learner_threads,
            callback=callback,
        )
    finally:
        if started:
            ray.shutdown()


def _train_and_save(
    config: PPOConfig,
    out: Path,
    *,
    env_id: str,
    seed: int,
    iterations: int,
    address: str | None,
    learner_threads: int | None,
    callback: Callable[[dict[str, Any]], None] | None,
) -> dict[str, Any]:
    """:func:`train` once Ray is up: build the algorithm, train it ``iterations`` times with
    torch on ``learner_threads`` threads, save the checkpoint and the summary into ``out``
    and return the summary. The algorithm is stopped however this ends (its env runners are
    actors that would otherwise outlive the call on a cluster that stays up)."""
    algo = None
    try:
        with _torch_threads(learner_threads):
            cpus = _cluster_cpus(config.num_env_runners)
            begin = time.perf_counter()
            algo = config.build_algo()
            build_s = time.perf_counter() - begin
            history, results, wall = _train_iterations(algo, iterations, callback)
            checkpoint = Path(algo.save_to_path((out / CHECKPOINT_DIR).resolve()))
            summary = _run_summary(
                config,
                history,
                results,
                env_id=env_id,
                seed=seed,
                iterations=iterations,
                wall=wall,
                build_s=build_s,
                checkpoint=checkpoint,
                address=address,
                cpus=cpus,
            )
            write_text_atomic(out / SUMMARY_FILE, json.dumps(summary, indent=2) + "\n")
            return summary
    finally:
        if algo is not None:
            algo.stop()


@contextlib.contextmanager
def _torch_threads(threads: int | None) -> Iterator[None]:
    """torch's thread count set to ``threads`` (None: left as it is) inside the block, and
    what it was before restored after it: the caller's torch is not changed for good."""
    import torch

    before = torch.get_num_threads()
    try:
        if threads is not None:
            torch.set_num_threads(threads)
        yield
    finally:
        torch.set_num_threads(before)


def _cluster_cpus(num_env_runners: int) -> float:
    """The Ray cluster's CPUs, with a warning where they are fewer than the env runners
    (each holds one): only an autoscaler adding nodes then lets them all start."""
    import ray

    cpus = ray.cluster_resources().get("CPU", 0.0)
    if cpus < num_env_runners:
        warnings.warn(
            f"the cluster has {cpus:g} CPUs for {num_env_runners} env runners of one CPU "
            "each: training waits until enough CPUs join",
            stacklevel=4,  # the caller of train (past _train_and_save)
        )
    return cpus


def _train_iterations(
    algo: Any, iterations: int, callback: Callable[[dict[str, Any]], None] | None
) -> tuple[list[dict[str, Any]], dict[str, Any], float]:
    """Train ``algo`` for ``iterations`` iterations; return the history (one row an
    iteration, each passed to ``callback`` as it comes), the last iteration's results and
    the wall time."""
    from ray.rllib.utils.metrics import (
        ENV_RUNNER_RESULTS,
        EPISODE_RETURN_MEAN,
        NUM_ENV_STEPS_SAMPLED_LIFETIME,
    )

    history: list[dict[str, Any]] = []
    results: dict[str, Any] = {}
    begin = time.perf_counter()
    for i in range(iterations):
        results = algo.train()
        row = {
            "iteration": i + 1,
            "env_steps_sampled": int(
                _metric(results, ENV_RUNNER_RESULTS, NUM_ENV_STEPS_SAMPLED_LIFETIME)
                or _metric(results, NUM_ENV_STEPS_SAMPLED_LIFETIME)
                or 0
            ),
            "episode_return_mean": _metric(results, ENV_RUNNER_RESULTS, EPISODE_RETURN_MEAN),
            "time_s": time.perf_counter() - begin,
        }
        history.append(row)
        if callback is not None:
            callback(row)
    return history, results, time.perf_counter() - begin


def _run_summary(
    config: PPOConfig,
    history: list[dict[str, Any]],
    results: Mapping[str, Any],
    *,
    env_id: str,
    seed: int,
    iterations: int,
    wall: float,
    build_s: float,
    checkpoint: Path,
    address: str | None,
    cpus: float,
) -> dict[str, Any]:
    """The summary ``<out>/rllib.json`` holds: the run's settings, its last iteration's
    numbers, the times, where the checkpoint is, the cluster, and the history."""
    import ray
    import torch
    from ray.rllib.utils.metrics import ENV_RUNNER_RESULTS, NUM_EPISODES_LIFETIME

    last = history[-1]
    episodes = _metric(results, ENV_RUNNER_RESULTS, NUM_EPISODES_LIFETIME)
    return {
        "engine": "rllib",
        "env": env_id,
        "seed": seed,
        "iterations": iterations,
        "num_env_runners": config.num_env_runners,
        "num_envs_per_env_runner": config.num_envs_per_env_runner,
        "train_batch_size": config.train_batch_size_per_learner,
        "env_steps_sampled": last["env_steps_sampled"],
        "episodes": int(episodes) if episodes is not None else 0,
        "episode_return_mean": last["episode_return_mean"],
        "wall_time_s": wall,
        "build_time_s": build_s,
        "env_steps_per_s": last["env_steps_sampled"] / wall if wall > 0 else None,
        "checkpoint": str(checkpoint),
        "address": address or "local",
        "cluster_cpus": cpus,
        "learner_threads": torch.get_num_threads(),
        "ray_version": ray.__version__,
        "history": history,
    }


def load_rl_module(checkpoint: str | Path) -> RLModule:
    """The trained policy of an RLlib checkpoint, without Ray running: the learner's
    RLModule (``learner_group/learner/rl_module/default_policy``), for evaluation and play."""
    _require_ray()
    from ray.rllib.core import (
        COMPONENT_LEARNER,
        COMPONENT_LEARNER_GROUP,
        COMPONENT_RL_MODULE,
        DEFAULT_MODULE_ID,
    )
    from ray.rllib.core.rl_module.rl_module import RLModule

    path = Path(checkpoint).resolve()
    module_dir = path / COMPONENT_LEARNER_GROUP / COMPONENT_LEARNER / COMPONENT_RL_MODULE
    module_dir = module_dir / DEFAULT_MODULE_ID
    if not module_dir.is_dir():
        raise ValueError(f"checkpoint {checkpoint} has no RLModule at {module_dir}")
    return RLModule.from_checkpoint(module_dir)


def compute_action(
    module: RLModule, observation: Any, action_space: gym.spaces.Box, explore: bool = False
) -> np.ndarray:
    """The action ``module`` takes for one observation (or a batch), in ``action_space``.

    Does what RLlib's env runner does between its module and the env: the distribution's
    mean (``explore=False``) or a sample, then unsquashed from [-1, 1] to the space's bounds
    and clipped (``normalize_actions``, RLlib's default), since the Gaussian's raw output is
    unbounded.
    """
    import torch
    from ray.rllib.core.columns import Columns
    from ray.rllib.utils.spaces.space_utils import unsquash_action

    obs = np.asarray(observation, dtype=np.float32)
    single = obs.ndim == 1
    batch = torch.from_numpy(obs[None] if single else obs)
    with torch.no_grad():
        if explore:
            out = module.forward_exploration({Columns.OBS: batch})
            dist_cls = module.get_exploration_action_dist_cls()
        else:
            out = module.forward_inference({Columns.OBS: batch})
            dist_cls = module.get_inference_action_dist_cls()
        dist = dist_cls.from_logits(out[Columns.ACTION_DIST_INPUTS])
        if not explore:
            dist = dist.to_deterministic()
        action = dist.sample().numpy()
    action = unsquash_action(action, action_space).astype(action_space.dtype)
    return action[0] if single else action
