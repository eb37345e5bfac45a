"""Training inside one compiled program: rejax's PPO or SAC and a bbgym env in one
``jax.jit``, several training seeds in one ``jax.vmap`` (the ``rejax`` extra).

    from bbgym.config import load_rejax
    from bbgym.rejax import train

    result = train(env_id, load_rejax(env_id), seeds=[0, 1, 2, 3, 4])
    result.policies[0]            # seed 0's final policy, a bbgym.mlp_policy.MLPPolicy

The env is :mod:`bbgym.jax_env`'s (gymnax's interface, which rejax takes as it takes
gymnax's own envs), so collecting, learning and evaluating are one XLA program: no Python
runs between steps. The settings are a preset's ``rejax`` section
(:data:`bbgym.config.REJAX_DEFAULTS`): ``algo``, the budget, the evaluations, and every
other key a setting of rejax's algorithm by rejax's own name.

Each ``eval_every_timesteps`` the program evaluates the deterministic policy (SAC: the
squashed mean; PPO: the clipped mean) on ``eval_episodes`` episodes: those that the
Gymnasium env starts for ``reset(seed=10000 + training seed)`` on that many envs
(:func:`bbgym.jax_env.vector_keys`), in the program's float type. Each evaluation is said
on stderr as the program reaches it (``jax.debug.callback``), and returns the policy it
evaluated: each seed's final policy and that of its best evaluation (the highest mean
return, as stable-baselines3's ``EvalCallback`` keeps it) come back as
:class:`~bbgym.mlp_policy.MLPPolicy`, which evaluates with NumPy alone.

What differs from the ``sb3`` engine's algorithms: rejax's SAC and PPO learn as gymnax
envs end, from ``done`` (a time limit cuts the return as a capsize does), and its SAC has
no n-step returns.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

try:
    import jax
    import jax.numpy as jnp
    import rejax
    from rejax.algos.algorithm import register_init
except ImportError as error:  # the fix, not a bare ModuleNotFoundError
    from bbgym._extras import install_hint

    raise ImportError(
        f"bbgym.rejax needs rejax and JAX (the 'rejax' extra): {install_hint('rejax')}"
    ) from error

from bbgym import backends, jax_env
from bbgym.config import REJAX_DEFAULTS
from bbgym.mlp_policy import MLPPolicy

EVAL_SEED_OFFSET = 10_000
"""Evaluation episodes use seeds far from the training ones (as the other engines do)."""


class _UniformReplayBuffer(rejax.buffers.ReplayBuffer):
    """rejax's replay buffer, sampled as stable-baselines3 samples its own: uniform indices
    with replacement. rejax's ``sample`` draws without replacement through
    ``jax.random.choice(..., p=...)``, a sort over the whole buffer at every update: with
    Sail-v1's 200,000 entries it took 45% of SAC's training time (40,000 steps, one seed:
    16.1 s against 8.9 s with a 20,000-entry buffer)."""

    def sample(self, num: int, rng: Any) -> Any:
        """``num`` transitions drawn uniformly, with replacement, from those stored.

        Args:
            num: the minibatch size.
            rng: a ``jax.random`` key.

        Returns:
            rejax's ``Minibatch`` of them.
        """
        index = jax.random.randint(rng, (num,), 0, jnp.maximum(self.num_entries, 1))
        return jax.tree.map(lambda column: column[index], self.data)


class _SAC(rejax.SAC):
    """rejax's SAC with ``_UniformReplayBuffer``; the algorithm is otherwise rejax's."""

    @register_init
    def initialize_replay_buffer(self, rng: Any) -> dict[str, Any]:
        """An empty ``_UniformReplayBuffer`` of ``buffer_size`` transitions.

        Args:
            rng: a ``jax.random`` key (unused: rejax's signature).

        Returns:
            ``{"replay_buffer": buffer}``, as rejax's initializers return their state.
        """
        buffer = _UniformReplayBuffer.empty(self.buffer_size, self.obs_space, self.action_space)
        return {"replay_buffer": buffer}


ALGORITHMS: dict[str, type] = {"ppo": rejax.PPO, "sac": _SAC}
"""``algo`` -> the rejax class: rejax's PPO, and its SAC sampled uniformly (``_SAC``)."""

SET_BY_BBGYM = ("env", "env_params", "eval_callback", "eval_freq", "total_timesteps")
"""rejax fields that bbgym sets itself (from the env and bbgym's own settings)."""


@dataclass
class TrainResult:
    """What :func:`train` returns.

    Attributes:
        policies: each training seed's final policy.
        best_policies: each seed's policy of its best evaluation (the highest mean
            return; its ``meta["timesteps"]`` says when).
        evaluations: each seed's evaluations: ``timesteps`` ``(n,)``, ``returns``,
            ``lengths`` and ``successes`` ``(n, eval_episodes)``.
        timesteps: the timesteps each seed trained (the budget rounded up to whole
            iterations of the algorithm).
        compile_time_s: seconds compiling the program.
        train_time_s: seconds running it (all seeds together).
        algorithm: the rejax settings the program ran with.
    """

    policies: dict[int, MLPPolicy]
    best_policies: dict[int, MLPPolicy]
    evaluations: dict[int, dict[str, np.ndarray]]
    timesteps: int
    compile_time_s: float
    train_time_s: float
    algorithm: dict[str, Any]


def algorithm_settings(settings: dict[str, Any]) -> dict[str, Any]:
    """The settings of a ``rejax`` section that go to rejax's algorithm (all but bbgym's).

    Args:
        settings: the section (:func:`bbgym.config.load_rejax`).

    Returns:
        rejax's keyword arguments, by rejax's names.

    Raises:
        ValueError: for a name that is not a setting of that rejax algorithm, naming it
            (``rejax.<name>``) and listing the algorithm's settings.
    """
    cls = ALGORITHMS[settings["algo"]]
    # Names the class's create() takes besides its fields.
    known = {f.name for f in dataclasses.fields(cls)} | {"agent_kwargs", "hidden_layer_sizes"}
    known -= set(SET_BY_BBGYM) | {"actor", "critic"}
    own = {k: v for k, v in settings.items() if k not in REJAX_DEFAULTS}
    unknown = sorted(set(own) - known)
    if unknown:
        raise ValueError(
            f"rejax.{unknown[0]}: not a setting of rejax's {cls.__name__} (or bbgym's "
            f"{sorted(REJAX_DEFAULTS)}); rejax's {cls.__name__} takes: {sorted(known)}"
        )
    return own


def make_algorithm(
    env_id: str,
    settings: dict[str, Any],
    timesteps: int | None = None,
    env_kwargs: dict[str, Any] | None = None,
) -> Any:
    """rejax's algorithm on ``env_id``'s :mod:`bbgym.jax_env` env, every argument a
    constant of the program (``vary=()``: it compiles and steps faster).

    Args:
        env_id: a bbgym id.
        settings: the ``rejax`` section of a preset.
        timesteps: the budget (None: the section's ``total_timesteps``).
        env_kwargs: the env's arguments (the preset's ``env``).

    Returns:
        The rejax algorithm (a pytree), with rejax's own evaluation in place: :func:`train`
        replaces it.
    """
    env, params = jax_env.make(env_id, dtype=settings["dtype"], vary=(), **dict(env_kwargs or {}))
    budget = settings["total_timesteps"] if timesteps is None else timesteps
    return ALGORITHMS[settings["algo"]].create(
        env=env,
        env_params=params,
        total_timesteps=budget,
        eval_freq=min(settings["eval_every_timesteps"], budget),
        skip_initial_evaluation=True,
        **algorithm_settings(settings),
    )


def trained_timesteps(algo: Any) -> int:
    """The timesteps rejax's ``train`` makes for ``algo``: whole iterations per
    evaluation, whole evaluation periods.

    Args:
        algo: a rejax PPO or SAC.

    Returns:
        Timesteps per training seed.
    """
    per_iteration = algo.num_envs * getattr(algo, "num_steps", 1)
    iterations = int(np.ceil(algo.eval_freq / per_iteration))
    evaluations = int(np.ceil(algo.total_timesteps / algo.eval_freq))
    return evaluations * iterations * per_iteration


def _squashed(algo: Any) -> bool:
    return isinstance(algo.actor, rejax.networks.SquashedGaussianPolicy)


def deterministic_action(algo: Any, train_state: Any) -> Callable[[Any], Any]:
    """The policy's deterministic action as a JAX function of one observation: SAC's
    squashed Gaussian mean, PPO's Gaussian mean clipped to the bounds (as
    :class:`~bbgym.mlp_policy.MLPPolicy` computes it).

    Args:
        algo: the rejax algorithm.
        train_state: its training state.

    Returns:
        ``obs -> action``.
    """
    low, high = algo.action_space.low, algo.action_space.high

    def act(obs: Any) -> Any:
        if getattr(algo, "normalize_observations", False):
            obs = algo.normalize_obs(train_state.obs_rms_state, obs)
        dist = algo.actor.apply(train_state.actor_ts.params, obs[None], method="_action_dist")
        mean = dist.loc[0]
        if _squashed(algo):
            return (high + low) / 2.0 + jnp.tanh(mean) * (high - low) / 2.0
        return jnp.clip(mean, low, high)

    return act


def _evaluator(seed: Any, env_keys: Any, report: Callable[..., None]) -> Callable[..., Any]:
    """rejax's ``eval_callback``: the deterministic policy on one episode per key of
    ``env_keys``, each run to its end (or the time limit) and not past it, and
    ``report(seed, timesteps, returns, successes)`` called from the program; it returns
    the episodes' returns, lengths and successes and the policy's leaves."""

    def evaluate(algo: Any, train_state: Any, rng: Any) -> tuple[Any, Any, Any, Any]:
        env, params = algo.env, algo.env_params
        act = deterministic_action(algo, train_state)
        max_steps = params.max_steps_in_episode

        def episode(env_key: Any) -> tuple[Any, Any, Any]:
            obs, state = env.reset_from_key(env_key, params)
            zero = jnp.zeros((), jnp.float32)

            def running(carry: tuple) -> Any:
                _, _, length, _, done, _ = carry
                return (length < max_steps) & ~done

            def step(carry: tuple) -> tuple:
                obs, state, length, total, _, _ = carry
                obs, state, reward, done, info = env.step(rng, state, act(obs), params)
                return obs, state, length + 1, total + reward, done, info["is_success"]

            start = (obs, state, jnp.int32(0), zero, jnp.bool_(False), jnp.bool_(False))
            _, _, length, total, _, success = jax.lax.while_loop(running, step, start)
            return total, length, success

        returns, lengths, successes = jax.vmap(episode)(env_keys)
        jax.debug.callback(report, seed, train_state.global_step, returns, successes)
        # The evaluated policy itself, so that the best one can be kept (a few thousand
        # floats an evaluation).
        return returns, lengths, successes, _policy_leaves(algo, train_state)

    return evaluate


def train(
    env_id: str,
    settings: dict[str, Any],
    seeds: Sequence[int],
    *,
    timesteps: int | None = None,
    env_kwargs: dict[str, Any] | None = None,
    log: Callable[[str], None] = backends.notice,
) -> TrainResult:
    """Train ``settings["algo"]`` on ``env_id`` for every seed of ``seeds`` in one compiled
    program (``jax.jit`` of ``jax.vmap`` over the seeds' keys), evaluating as it goes.

    Args:
        env_id: a bbgym id.
        settings: the ``rejax`` section of a preset (:func:`bbgym.config.load_rejax`).
        seeds: the training seeds: seed ``s`` starts from ``jax.random.PRNGKey(s)`` and is
            evaluated on the episodes of seed ``10000 + s``.
        timesteps: the budget per seed (None: the section's ``total_timesteps``).
        env_kwargs: the env's arguments (the preset's ``env``).
        log: where the compile and each evaluation are said (stderr by default).

    Returns:
        The policies, the evaluations and the times (:class:`TrainResult`).
    """
    seeds = [int(s) for s in seeds]
    algo = make_algorithm(env_id, settings, timesteps, env_kwargs)
    episodes = settings["eval_episodes"]
    eval_keys = jnp.stack([jax_env.vector_keys(EVAL_SEED_OFFSET + s, episodes) for s in seeds])
    rngs = jnp.stack([jax.random.PRNGKey(s) for s in seeds])
    seed_values = jnp.asarray(seeds, dtype=jnp.int32)
    total = trained_timesteps(algo)
    began = [time.perf_counter()]

    def report(seed: Any, step: Any, returns: Any, successes: Any) -> None:
        log(
            f"rejax {settings['algo'].upper()} on {env_id}, seed {int(seed)}: {int(step)}/"
            f"{total} timesteps, {time.perf_counter() - began[0]:.0f} s: success "
            f"{np.mean(successes):.0%}, mean return {np.mean(returns):.2f}"
        )

    def run(rng: Any, keys: Any, seed: Any) -> tuple[Any, Any]:
        return algo.replace(eval_callback=_evaluator(seed, keys, report)).train(rng)

    what = (
        f"rejax's {settings['algo'].upper()} training on {env_id} ({len(seeds)} seed(s) in "
        f"one program, {total} timesteps each)"
    )
    start = time.perf_counter()
    with backends.announced(f"compiling {what}", threshold_s=0.0):
        compiled = jax.jit(jax.vmap(run)).lower(rngs, eval_keys, seed_values).compile()
    compile_time = time.perf_counter() - start
    log(f"training: {what}; a line at each evaluation")
    began[0] = start = time.perf_counter()
    train_state, (returns, lengths, successes, evaluated) = compiled(rngs, eval_keys, seed_values)
    jax.block_until_ready(train_state)
    train_time = time.perf_counter() - start

    n_evals = returns.shape[1]
    steps = np.arange(1, n_evals + 1) * (total // n_evals)
    policies, best_policies, evaluations = {}, {}, {}
    for i, seed in enumerate(seeds):
        meta = {"env_id": env_id, "algo": settings["algo"], "seed": seed, "timesteps": total}
        final = jax.tree.map(lambda leaf, i=i: leaf[i], train_state)
        policies[seed] = export_policy(algo, final, meta)
        curve = {
            "timesteps": steps,
            "returns": np.asarray(returns[i], dtype=np.float64),
            "lengths": np.asarray(lengths[i]),
            "successes": np.asarray(successes[i], dtype=bool),
        }
        # As stable-baselines3's EvalCallback keeps it: the first evaluation with the
        # highest mean return.
        best = int(np.argmax(curve["returns"].mean(axis=1)))
        leaves = jax.tree.map(lambda leaf, i=i, best=best: leaf[i, best], evaluated)
        best_meta = {**meta, "timesteps": int(steps[best])}
        best_policies[seed] = _policy_from_leaves(algo, leaves, best_meta)
        evaluations[seed] = curve
    return TrainResult(
        policies=policies,
        best_policies=best_policies,
        evaluations=evaluations,
        timesteps=total,
        compile_time_s=compile_time,
        train_time_s=train_time,
        algorithm=_settings_record(algo, settings),
    )


def _settings_record(algo: Any, settings: dict[str, Any]) -> dict[str, Any]:
    """The rejax settings as JSON: the section's, with the algorithm's class and the
    activation rejax resolved."""
    record = {k: v for k, v in settings.items()}
    name = type(algo).__name__
    record["rejax_class"] = {"_SAC": "SAC, its buffer sampled uniformly"}.get(name, name)
    record["activation"] = _activation_name(algo.actor.activation)
    return record


def _activation_name(function: Callable) -> str:
    name = getattr(function, "__name__", str(function))
    return {"silu": "swish"}.get(name, name)


def export_policy(algo: Any, train_state: Any, meta: dict[str, Any]) -> MLPPolicy:
    """The deterministic policy of one seed's training state as a NumPy
    :class:`~bbgym.mlp_policy.MLPPolicy`.

    Args:
        algo: the rejax algorithm.
        train_state: one seed's training state.
        meta: what made it (written into the file).

    Returns:
        The policy.
    """
    return _policy_from_leaves(algo, _policy_leaves(algo, train_state), meta)


def _policy_leaves(algo: Any, train_state: Any) -> dict[str, Any]:
    """What a policy is made of: the actor's params and, where observations are
    normalized, the normalizer's mean and variance."""
    leaves = {"actor": train_state.actor_ts.params}
    if getattr(algo, "normalize_observations", False):
        leaves["obs_mean"] = train_state.obs_rms_state.mean
        leaves["obs_var"] = train_state.obs_rms_state.var
    return leaves


def _policy_from_leaves(algo: Any, leaves: dict[str, Any], meta: dict[str, Any]) -> MLPPolicy:
    params = leaves["actor"]["params"]
    features = params["features"]
    layers = [features[f"Dense_{i}"] for i in range(len(features))]
    layers.append(params["action_mean"])
    normalized = getattr(algo, "normalize_observations", False)
    space = algo.action_space
    shape = space.shape
    return MLPPolicy(
        kernels=tuple(np.asarray(layer["kernel"], dtype=np.float64) for layer in layers),
        biases=tuple(np.asarray(layer["bias"], dtype=np.float64) for layer in layers),
        activation=_activation_name(algo.actor.activation),
        squash=_squashed(algo),
        action_low=np.broadcast_to(np.asarray(space.low, np.float64), shape).copy(),
        action_high=np.broadcast_to(np.asarray(space.high, np.float64), shape).copy(),
        obs_mean=np.asarray(leaves["obs_mean"], np.float64) if normalized else None,
        obs_var=np.asarray(leaves["obs_var"], np.float64) if normalized else None,
        meta=meta,
    )
