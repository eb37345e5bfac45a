"""bbgym's envs as TorchRL environments, on the env's own device (the ``torchrl`` extra).

    from bbgym.torchrl import BbgymTorchRLEnv

    env = BbgymTorchRLEnv(env_id, num_envs=1024, device="cpu", seed=0)
    rollout = env.rollout(300, break_when_any_done=False)   # a TensorDict [1024, 300]

The env is the native vector env on the torch backend with tensors in and out
(``backend="torch", output="torch"``): the step, the observations, rewards and ends and
the random numbers stay on ``device`` (a CUDA device for GPU-resident training), with no
NumPy round trip. It is batch-locked: its batch size is ``[num_envs]``.

TorchRL resets a finished env itself, between steps (``step_and_maybe_reset``, a
collector): ``_reset`` with a ``"_reset"`` mask restarts those envs alone
(:meth:`bbgym.envs.core.CoreVectorEnv.reset_envs`), so no step is spent on Gymnasium's
next-step autoreset. Keys: ``observation`` (float, the env's observation), ``action``
(bounded in [-1, 1]), ``reward`` (``[num_envs, 1]``), ``done``, ``terminated`` and
``truncated`` (``[num_envs, 1]``, bool) and ``is_success`` (bool, at an episode's end).
The step computes no other info (``info_keys=["is_success"]``; an ``info_keys`` among
the env's arguments overrides it).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

try:
    import torch
    from tensordict import TensorDict, TensorDictBase
    from torchrl.data import Bounded, Categorical, Composite, Unbounded
    from torchrl.envs import EnvBase
except ImportError as error:  # the fix, not a bare ModuleNotFoundError
    from bbgym._extras import install_hint

    raise ImportError(
        f"bbgym.torchrl needs TorchRL (the 'torchrl' extra): {install_hint('torchrl')}"
    ) from error

import bbgym  # noqa: F401  (registers the ids)
from bbgym.envs.core import CoreVectorEnv
from bbgym.spec import env_ids

DTYPES = {"float32": torch.float32, "float64": torch.float64}


class BbgymTorchRLEnv(EnvBase):
    """A bbgym env id's native vector env on the torch backend, as a batch-locked TorchRL
    ``EnvBase`` of ``num_envs`` envs on ``device``.

    ``dtype`` is the physics' float type (``"float32"`` or ``"float64"``; observations and
    rewards come in it), ``compile_step`` whether bbgym's step is ``torch.compile``d (the
    default; ``False`` runs it eagerly; the name is not ``compile``, which TorchRL's
    ``EnvBase`` takes for itself), ``seed`` the first reset's seed (env ``i`` is seeded
    ``seed + i``; :meth:`set_seed` reseeds), and ``env_kwargs`` the env's own arguments."""

    batch_locked = True

    def __init__(
        self,
        env_id: str,
        num_envs: int,
        *,
        device: str | torch.device = "cpu",
        dtype: str = "float32",
        compile_step: bool = True,
        seed: int | None = None,
        **env_kwargs: Any,
    ) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, int) or num_envs < 1:
            raise ValueError(f"num_envs must be a positive int, got {num_envs!r}")
        if dtype not in DTYPES:
            raise ValueError(f"dtype must be one of {sorted(DTYPES)}, got {dtype!r}")
        if env_id not in env_ids():
            raise ValueError(
                f"env_id {env_id!r} is not a bbgym env; bbgym's: {', '.join(env_ids())}"
            )
        device = torch.device(device)
        super().__init__(device=device, batch_size=torch.Size([num_envs]))
        self.env_id = env_id
        # The step computes no info but the success flag the batch carries (unless the
        # env's kwargs ask for others).
        env_kwargs.setdefault("info_keys", ["is_success"])
        self.vector_env = gym.make_vec(
            env_id,
            num_envs=num_envs,
            vectorization_mode="vector_entry_point",
            backend="torch",
            device=str(device),
            dtype=dtype,
            output="torch",
            compile=compile_step,
            **env_kwargs,
        )
        self.core: CoreVectorEnv = self.vector_env.unwrapped
        self._float = DTYPES[dtype]
        self._make_specs(num_envs)
        self._seed = seed

    def _make_specs(self, n: int) -> None:
        obs, act = self.core.single_observation_space, self.core.single_action_space
        self.observation_spec = Composite(
            observation=Bounded(
                low=torch.as_tensor(np.broadcast_to(obs.low, (n, *obs.shape)).copy()),
                high=torch.as_tensor(np.broadcast_to(obs.high, (n, *obs.shape)).copy()),
                shape=(n, *obs.shape),
                dtype=self._float,
                device=self.device,
            ),
            is_success=Categorical(2, shape=(n, 1), dtype=torch.bool, device=self.device),
            shape=(n,),
        )
        self.action_spec = Bounded(
            low=-1.0, high=1.0, shape=(n, *act.shape), dtype=self._float, device=self.device
        )
        self.reward_spec = Unbounded(shape=(n, 1), dtype=self._float, device=self.device)
        flag = Categorical(2, shape=(n, 1), dtype=torch.bool, device=self.device)
        self.done_spec = Composite(
            done=flag, terminated=flag.clone(), truncated=flag.clone(), shape=(n,)
        )

    def _reset(self, tensordict: TensorDictBase | None = None, **kwargs: Any) -> TensorDictBase:
        mask = None if tensordict is None else tensordict.get("_reset", None)
        if mask is None or not self.core.started:
            obs, _ = self.core.reset(seed=self._seed)
            self._seed = None  # later full resets continue each env's stream
        else:
            obs = self.core.reset_envs(mask.reshape(-1).cpu().numpy())
        false = torch.zeros((self.batch_size[0], 1), dtype=torch.bool, device=self.device)
        return TensorDict(
            {
                "observation": self._obs(obs),
                "is_success": false.clone(),
                "done": false,
                "terminated": false.clone(),
                "truncated": false.clone(),
            },
            batch_size=self.batch_size,
            device=self.device,
        )

    def _step(self, tensordict: TensorDictBase) -> TensorDictBase:
        obs, reward, terminated, truncated, info = self.core.step(tensordict.get("action"))
        terminated = terminated.reshape(-1, 1)
        truncated = truncated.reshape(-1, 1)
        success = info.get("is_success")
        success = (
            torch.zeros_like(terminated)
            if success is None
            else torch.as_tensor(success, device=self.device).reshape(-1, 1)
        )
        out = {
            "observation": self._obs(obs),
            "is_success": success.to(torch.bool),
            "reward": reward.to(self._float).reshape(-1, 1),
            "done": terminated | truncated,
            "terminated": terminated,
            "truncated": truncated,
        }
        return TensorDict(out, batch_size=self.batch_size, device=self.device)

    def _obs(self, obs: Any) -> torch.Tensor:
        return torch.as_tensor(obs, device=self.device).to(self._float)

    def _set_seed(self, seed: int | None) -> None:
        """The next full reset seeds env ``i`` with ``seed + i`` (TorchRL's ``set_seed``)."""
        self._seed = seed

    def close(self, *, raise_if_closed: bool = True) -> None:
        self.vector_env.close()
        super().close(raise_if_closed=raise_if_closed)


# -- PPO on the env's device (``bbgym train --engine torchrl``) ---------------------------

POLICY_FORMAT = "bbgym-torchrl-ppo-1"
"""The ``format`` entry of a saved policy (:func:`save_policy`), which :func:`load_policy`
checks."""


class GaussianPolicyNet(torch.nn.Module):
    """The policy: an MLP (tanh hidden layers) from the observation to the mean of a
    Gaussian, either squashed by tanh into [-1, 1] (``squash=True``, TorchRL's
    ``TanhNormal``; the deterministic action is ``tanh(mean)``) or not (``squash=False``,
    an ``IndependentNormal`` whose samples the env clips to [-1, 1], as stable-baselines3's
    PPO does without ``squash_output``; the deterministic action is the mean, clipped).
    Its standard deviation is stable-baselines3's, either one
    learnt vector independent of the state (white noise, ``state_dependent=False``), or
    that of generalized state-dependent exploration (gSDE, ``state_dependent=True``): the
    noise is the last hidden layer's features times a random matrix, so its variance is
    ``features**2 @ exp(log_std)**2`` (the features detached: the noise does not train
    them), and a collector that holds the matrix for several steps
    (:class:`CorrelatedExploration`) explores with smooth, repeatable changes."""

    def __init__(
        self,
        obs_dim: int,
        act_dim: int,
        net_arch: list[int],
        log_std_init: float,
        state_dependent: bool = False,
        squash: bool = True,
    ) -> None:
        super().__init__()
        self.squash = squash
        self.mean = mlp(obs_dim, act_dim, net_arch, final_gain=0.01)
        shape = (net_arch[-1], act_dim) if state_dependent else (act_dim,)
        self.log_std = torch.nn.Parameter(torch.full(shape, float(log_std_init)))

    @property
    def state_dependent(self) -> bool:
        return self.log_std.dim() == 2

    def features(self, observation: torch.Tensor) -> torch.Tensor:
        """The last hidden layer's output: gSDE's noise is linear in it."""
        return self.mean[:-1](observation)

    def loc_scale(self, features: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        loc = self.mean[-1](features)
        if not self.state_dependent:
            return loc, self.log_std.exp().expand_as(loc)
        variance = features.detach().square() @ self.log_std.exp().square()
        return loc, torch.sqrt(variance + 1e-6)  # stable-baselines3's epsilon

    def forward(self, observation: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        return self.loc_scale(self.features(observation))

    @property
    def distribution_class(self) -> type:
        """The action distribution over ``(loc, scale)``: TorchRL's ``TanhNormal`` where
        the policy squashes, else its ``IndependentNormal``."""
        from torchrl.modules import IndependentNormal, TanhNormal

        return TanhNormal if self.squash else IndependentNormal

    def bound(self, action: torch.Tensor) -> torch.Tensor:
        """A Gaussian sample (or the mean) as the action in [-1, 1]: tanh where the policy
        squashes; else the sample itself, which the env clips (the evaluation clips it)."""
        return torch.tanh(action) if self.squash else action

    def act(self, observation: torch.Tensor) -> torch.Tensor:
        """The deterministic action (evaluation): the mean, squashed or clipped."""
        return self.bound(self.mean(observation)).clamp(-1.0, 1.0)


class CorrelatedExploration(torch.nn.Module):
    """The collector's policy under gSDE: each env's noise is its own random matrix
    (entries normal with the policy's ``exp(log_std)``) applied to the features, the
    matrices drawn anew every ``sample_freq`` steps (stable-baselines3's
    ``sde_sample_freq``); the action and its log-probability under the policy's
    distribution go into the batch, as a ``ProbabilisticActor``'s would."""

    def __init__(self, net: GaussianPolicyNet, num_envs: int, sample_freq: int) -> None:
        super().__init__()
        self.net, self.num_envs, self.sample_freq = net, num_envs, sample_freq
        self.calls = 0
        self.matrices: torch.Tensor | None = None

    def reset_noise(self) -> None:
        """Draw new matrices at the next call, and every ``sample_freq`` calls from it:
        stable-baselines3 draws them at the start of each rollout, from the policy just
        updated (a collector's first call, which only probes the policy's outputs, would
        otherwise shift every later draw by one step, and a rollout's first steps would
        explore with noise drawn before the last update)."""
        self.calls = 0

    def forward(self, observation: torch.Tensor) -> tuple[torch.Tensor, ...]:
        with torch.no_grad():
            if self.calls % self.sample_freq == 0:
                std = self.net.log_std.exp()
                self.matrices = (
                    torch.randn((self.num_envs, *std.shape), dtype=std.dtype, device=std.device)
                    * std
                )
            self.calls += 1
            features = self.net.features(observation)
            loc, scale = self.net.loc_scale(features)
            noise = torch.bmm(features.unsqueeze(1), self.matrices).squeeze(1)
            action = self.net.bound(loc + noise)
            log_prob = self.net.distribution_class(loc, scale).log_prob(action)
        return loc, scale, action, log_prob


def mlp(in_dim: int, out_dim: int, net_arch: list[int], final_gain: float) -> torch.nn.Sequential:
    """Tanh hidden layers, orthogonally initialized as stable-baselines3's PPO does (gain
    sqrt(2) inside, ``final_gain`` on the output: 0.01 for the policy, 1 for the value)."""
    layers: list[torch.nn.Module] = []
    width = in_dim
    for hidden in net_arch:
        layers += [torch.nn.Linear(width, hidden), torch.nn.Tanh()]
        width = hidden
    layers.append(torch.nn.Linear(width, out_dim))
    for layer in layers:
        if isinstance(layer, torch.nn.Linear):
            last = layer is layers[-1]
            torch.nn.init.orthogonal_(layer.weight, gain=final_gain if last else 2**0.5)
            torch.nn.init.zeros_(layer.bias)
    return torch.nn.Sequential(*layers)


def save_policy(path: Path, net: GaussianPolicyNet, settings: dict[str, Any], meta: dict) -> None:
    """Write the policy ``net`` whole or not at all: its weights, its shape and ``meta``
    (env id, timesteps), loadable with ``torch.load(weights_only=True)``."""
    from bbgym._files import write_atomic

    payload = {
        "format": POLICY_FORMAT,
        "obs_dim": net.mean[0].in_features,
        "act_dim": net.mean[-1].out_features,
        "state_dependent": net.state_dependent,
        "squash": net.squash,
        "net_arch": list(settings["net_arch"]),
        "state_dict": {k: v.detach().cpu() for k, v in net.state_dict().items()},
        **meta,
    }
    write_atomic(Path(path), lambda tmp: torch.save(payload, tmp))


def load_policy(path: str | Path) -> GaussianPolicyNet:
    """A policy saved by :func:`save_policy` (``model.pt``, ``best_model.pt`` of a run of
    ``--engine torchrl``), on the CPU in float32, for evaluation (``net.act(obs)``)."""
    try:
        payload = torch.load(Path(path), map_location="cpu", weights_only=True)
    except Exception as error:  # a zip of SB3, a truncated file, ...
        raise ValueError(
            f"--model {path}: not a policy saved by bbgym's TorchRL PPO ({error})"
        ) from None
    if not isinstance(payload, dict) or payload.get("format") != POLICY_FORMAT:
        raise ValueError(
            f"--model {path}: not a policy saved by bbgym's TorchRL PPO (format {POLICY_FORMAT})"
        )
    # Files written before ``squash_output`` existed hold squashing policies.
    net = GaussianPolicyNet(
        payload["obs_dim"],
        payload["act_dim"],
        payload["net_arch"],
        0.0,
        payload["state_dependent"],
        payload.get("squash", True),
    )
    net.load_state_dict(payload["state_dict"])
    return net.eval()


class ReturnScaler:
    """Rewards divided by the running standard deviation of the discounted return, per env,
    and clipped to +-``clip``: stable-baselines3's ``VecNormalize(norm_obs=False,
    norm_reward=True)`` (RL Zoo's ``norm_reward``), step by step as it does, so that the
    scale the value function learns in stays near 1 whatever the env's reward units, and a
    rare large reward (a capsize's) counts for at most ``clip``, as there."""

    def __init__(
        self, num_envs: int, gamma: float, device: torch.device, clip: float = 10.0
    ) -> None:
        self.gamma, self.clip = gamma, clip
        self.returns = torch.zeros(num_envs, dtype=torch.float64, device=device)
        # stable-baselines3's RunningMeanStd starts at mean 0, variance 1 and a count of
        # 1e-4 (a prior that the first batch outweighs).
        self.count, self.mean, self.var = 1e-4, 0.0, 1.0

    def __call__(self, reward: torch.Tensor, done: torch.Tensor) -> torch.Tensor:
        """Scale ``reward`` ``[num_envs, T, 1]`` (``done`` alike): step ``t``'s rewards by
        the statistics of the returns up to and including step ``t``, as
        ``VecNormalize.step_wait`` does for each step of the vector env."""
        scales = torch.empty(reward.shape[1], dtype=torch.float64)
        for t in range(reward.shape[1]):
            self.returns = self.returns * self.gamma + reward[:, t, 0].to(torch.float64)
            self._update(self.returns)
            scales[t] = (self.var + 1e-8) ** 0.5
            self.returns = torch.where(done[:, t, 0], 0.0, self.returns)
        scales = scales.to(device=reward.device, dtype=reward.dtype).reshape(1, -1, 1)
        return (reward / scales).clamp(-self.clip, self.clip)

    def _update(self, returns: torch.Tensor) -> None:
        """Chan et al.'s parallel update of the running mean and variance by one step's
        returns (stable-baselines3's ``RunningMeanStd.update``)."""
        n = returns.numel()
        mean = float(returns.mean())
        var = float(returns.var(correction=0))
        total = self.count + n
        delta = mean - self.mean
        m2 = self.var * self.count + var * n + delta * delta * self.count * n / total
        self.mean += delta * n / total
        self.var = m2 / total
        self.count = total


def evaluate_policy(
    env_id: str, net: GaussianPolicyNet, episodes: int, seed: int, env_kwargs: dict[str, Any]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``episodes`` episodes of the deterministic policy on the NumPy backend's vector env
    of ``min(episodes, 50)`` envs seeded ``seed + i``, each env playing its share as
    stable-baselines3's ``evaluate_policy`` deals them; return each episode's return,
    length and success."""
    n = min(episodes, 50)
    targets = np.array([(episodes + i) // n for i in range(n)])
    env = gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point", **env_kwargs)
    returns, lengths, successes = [], [], []
    try:
        obs, _ = env.reset(seed=seed)
        counts = np.zeros(n, dtype=int)
        ret, length = np.zeros(n), np.zeros(n, dtype=int)
        restarting = np.zeros(n, dtype=bool)
        while (counts < targets).any():
            with torch.no_grad():
                action = net.act(torch.as_tensor(obs, dtype=torch.float32)).numpy()
            obs, reward, terminated, truncated, info = env.step(action)
            live = ~restarting  # next-step autoreset: this step restarted the others
            ret[live] += reward[live]
            length[live] += 1
            done = (terminated | truncated) & live
            success = np.asarray(info.get("is_success", np.zeros(n, dtype=bool)), dtype=bool)
            for i in np.flatnonzero(done & (counts < targets)):
                returns.append(float(ret[i]))
                lengths.append(int(length[i]))
                successes.append(bool(success[i]))
                counts[i] += 1
            ret[done], length[done] = 0.0, 0
            restarting = done
    finally:
        env.close()
    return np.array(returns), np.array(lengths), np.array(successes)


class PPOLearner:
    """PPO's learning side, from TorchRL's parts: the policy (:class:`GaussianPolicyNet` in
    a ``ProbabilisticActor`` with its ``TanhNormal`` or ``IndependentNormal``), the value
    MLP (a ``ValueOperator``), ``GAE`` for the advantages, ``ClipPPOLoss`` for the clipped
    objective and the value loss (advantages normalized per minibatch, as
    stable-baselines3 does) and Adam."""

    def __init__(self, env: BbgymTorchRLEnv, settings: dict[str, Any]) -> None:
        from tensordict.nn import TensorDictModule
        from torchrl.modules import ProbabilisticActor, ValueOperator
        from torchrl.objectives import ClipPPOLoss
        from torchrl.objectives.value import GAE

        self.settings = settings
        self.obs_dim = env.observation_spec["observation"].shape[-1]
        self.act_dim = env.action_spec.shape[-1]
        arch = settings["net_arch"]
        self.net = GaussianPolicyNet(
            self.obs_dim,
            self.act_dim,
            arch,
            settings["log_std_init"],
            settings["use_sde"],
            settings["squash_output"],
        )
        self.net.to(device=env.device, dtype=env._float)
        self.actor = ProbabilisticActor(
            TensorDictModule(self.net, in_keys=["observation"], out_keys=["loc", "scale"]),
            in_keys=["loc", "scale"],
            spec=env.action_spec,
            distribution_class=self.net.distribution_class,
            return_log_prob=True,
        )
        value_net = mlp(self.obs_dim, 1, arch, final_gain=1.0)
        critic = ValueOperator(
            value_net.to(device=env.device, dtype=env._float), in_keys=["observation"]
        )
        self.advantage = GAE(
            gamma=settings["gamma"],
            lmbda=settings["gae_lambda"],
            value_network=critic,
            average_gae=False,
        )
        self.loss = ClipPPOLoss(
            self.actor,
            critic,
            clip_epsilon=settings["clip_range"],
            entropy_bonus=settings["ent_coef"] > 0.0,
            entropy_coeff=settings["ent_coef"],
            critic_coeff=settings["vf_coef"],
            loss_critic_type="l2",
            normalize_advantage=True,
        )
        rate = settings["learning_rate"]
        self.rate = rate if callable(rate) else None  # a schedule over the budget
        initial = rate.initial if callable(rate) else float(rate)
        self.optimizer = torch.optim.Adam(self.loss.parameters(), lr=initial, eps=1e-5)

    def explorer(self, num_envs: int) -> Any:
        """The collector's policy: the actor's samples (white noise), or under gSDE
        :class:`CorrelatedExploration` holding each env's noise for ``sde_sample_freq``
        steps (:meth:`new_rollout` draws it anew)."""
        if not self.settings["use_sde"]:
            return self.actor
        from tensordict.nn import TensorDictModule

        self.exploration = CorrelatedExploration(
            self.net, num_envs, self.settings["sde_sample_freq"]
        )
        return TensorDictModule(
            self.exploration,
            in_keys=["observation"],
            out_keys=["loc", "scale", "action", "action_log_prob"],
        )

    exploration: CorrelatedExploration | None = None

    def new_rollout(self) -> None:
        """The next collected step starts a rollout: gSDE draws its noise there."""
        if self.exploration is not None:
            self.exploration.reset_noise()

    def update(self, batch: TensorDictBase, progress: float, order: torch.Generator) -> None:
        """Learn from one collected ``batch`` (``[num_envs, n_steps]``): its advantages,
        then ``n_epochs`` passes in shuffled minibatches, one clipped Adam step each.
        ``progress`` is the fraction of the budget done (a scheduled learning rate)."""
        settings = self.settings
        if self.rate is not None:
            for group in self.optimizer.param_groups:
                group["lr"] = self.rate(1.0 - progress)
        with torch.no_grad():
            self.advantage(batch)
        flat = batch.reshape(-1)
        size = settings["minibatch_size"]
        for _ in range(settings["n_epochs"]):
            permutation = torch.randperm(flat.numel(), generator=order).to(flat.device)
            for begin in range(0, flat.numel(), size):
                self.learn(flat[permutation[begin : begin + size]])

    def learn(self, minibatch: TensorDictBase) -> None:
        """One Adam step on ``minibatch`` (its advantages and value targets computed):
        the clipped objective plus the weighted value loss (and entropy bonus), the
        gradient's norm clipped to ``max_grad_norm``, as stable-baselines3's ``PPO.train``
        takes for each of its minibatches."""
        losses = self.loss(minibatch)
        total = losses["loss_objective"] + losses["loss_critic"]
        if "loss_entropy" in losses.keys():
            total = total + losses["loss_entropy"]
        self.optimizer.zero_grad(set_to_none=True)
        total.backward()
        torch.nn.utils.clip_grad_norm_(self.loss.parameters(), self.settings["max_grad_norm"])
        self.optimizer.step()

    def cpu_policy(self) -> GaussianPolicyNet:
        """A float32 copy of the policy on the CPU (the evaluation's)."""
        settings = self.settings
        copy = GaussianPolicyNet(
            self.obs_dim,
            self.act_dim,
            settings["net_arch"],
            0.0,
            settings["use_sde"],
            settings["squash_output"],
        )
        copy.load_state_dict({k: v.cpu().float() for k, v in self.net.state_dict().items()})
        return copy


class EvaluationLog:
    """The periodic evaluations of a run: the deterministic policy on ``episodes``
    episodes (:func:`evaluate_policy`, seeds ``seed + 10000 + i``), logged to
    ``<out>/eval/evaluations.npz`` in stable-baselines3's layout, the best mean return's
    policy saved as ``<out>/best_model.pt``."""

    def __init__(
        self,
        out: Path,
        env_id: str,
        seed: int,
        settings: dict[str, Any],
        env_kwargs: dict[str, Any],
        log: Any,
    ) -> None:
        self.out, self.env_id, self.seed = out, env_id, seed
        self.settings, self.env_kwargs, self.log = settings, env_kwargs, log
        self.entries: dict[str, list] = {
            "timesteps": [],
            "results": [],
            "ep_lengths": [],
            "successes": [],
        }
        self.best_mean_return, self.best_timesteps = -float("inf"), None
        self.time_s = 0.0
        (out / "eval").mkdir(parents=True, exist_ok=True)

    def evaluate(self, learner: PPOLearner, timesteps: int) -> None:
        import time

        from bbgym._files import write_atomic

        began = time.perf_counter()
        returns, lengths, successes = evaluate_policy(
            self.env_id,
            learner.cpu_policy(),
            self.settings["eval_episodes"],
            self.seed + 10_000,
            self.env_kwargs,
        )
        new = ([timesteps], [returns], [lengths], [successes])
        for key, values in zip(self.entries, new, strict=True):
            self.entries[key] += values
        write_atomic(self.out / "eval" / "evaluations.npz", self._save)
        mean_return = float(returns.mean())
        if mean_return > self.best_mean_return:  # the first of equals, as SB3 keeps
            self.best_mean_return, self.best_timesteps = mean_return, timesteps
            meta = {"env_id": self.env_id, "seed": self.seed, "timesteps": timesteps}
            save_policy(self.out / "best_model.pt", learner.net, self.settings, meta)
        self.time_s += time.perf_counter() - began
        self.log(
            f"{timesteps} timesteps: success {successes.mean():.0%}, mean return "
            f"{mean_return:.2f} over {len(returns)} episodes"
        )

    def _save(self, path: Path) -> None:
        with open(path, "wb") as f:
            np.savez(f, **{k: np.array(v) for k, v in self.entries.items()})


def train_ppo(
    env_id: str,
    settings: dict[str, Any],
    *,
    out: Path,
    seed: int = 0,
    device: str = "cpu",
    timesteps: int | None = None,
    env_kwargs: dict[str, Any] | None = None,
    log: Any = print,
) -> dict[str, Any]:
    """Train PPO with TorchRL's ``ClipPPOLoss`` and ``GAE`` on ``env_id``'s torch backend
    (:class:`BbgymTorchRLEnv`), env and policy on ``device``, with the ``torchrl`` section
    of a preset (:func:`bbgym.config.load_torchrl`); write the run folder ``out`` and
    return its summary (also ``<out>/train.json``).

    Each batch is ``num_envs x n_steps`` frames from TorchRL's ``Collector`` (which resets
    finished envs between steps), its rewards scaled where ``normalize_reward`` says
    (:class:`ReturnScaler`), learnt from by :meth:`PPOLearner.update`. Every
    ``eval_every_timesteps`` and at the end the policy is evaluated
    (:class:`EvaluationLog`); the last policy is ``<out>/model.pt``.

    Reproducible: ``seed`` seeds torch's generator (the policy's initial weights and its
    samples), the minibatch order and the envs (``seed + i``); with the same torch thread
    count, machine and ``device``, the same seed gives the same policy."""
    import json
    import time

    from torchrl.collectors import Collector

    from bbgym._files import write_text_atomic

    env_kwargs, out = dict(env_kwargs or {}), Path(out)
    out.mkdir(parents=True, exist_ok=True)
    n, n_steps = settings["num_envs"], settings["n_steps"]
    frames_per_batch = n * n_steps
    budget = timesteps or settings["total_timesteps"]
    batches = -(-budget // frames_per_batch)  # whole batches: rounded up
    if batches * frames_per_batch != budget:
        log(
            f"{budget} timesteps round up to {batches * frames_per_batch}: whole batches of "
            f"num_envs {n} x n_steps {n_steps}"
        )
    start = time.perf_counter()
    env = BbgymTorchRLEnv(
        env_id,
        n,
        device=device,
        dtype=settings["dtype"],
        compile_step=settings["compile_step"],
        seed=seed,
        **env_kwargs,
    )
    torch.manual_seed(seed)  # the policy's weights (drawn first) and its samples
    order = torch.Generator().manual_seed(seed)  # the minibatches' order
    learner = PPOLearner(env, settings)
    scaler = (
        ReturnScaler(n, settings["gamma"], env.device) if settings["normalize_reward"] else None
    )
    # A feed-forward policy needs no env transform (the collector asks whether to add
    # InitTracker, which marks episode starts for recurrent policies).
    collector = Collector(
        env,
        learner.explorer(n),
        frames_per_batch=frames_per_batch,
        total_frames=batches * frames_per_batch,
        device=env.device,
        auto_register_policy_transforms=False,
    )
    learner.new_rollout()
    evaluation = EvaluationLog(out, env_id, seed, settings, env_kwargs, log)
    every = settings["eval_every_timesteps"]

    frames, first_batch_s, update_time = 0, 0.0, 0.0
    for index, batch in enumerate(collector):
        if index == 0:
            first_batch_s = time.perf_counter() - start  # compiling the step included
        began = time.perf_counter()
        frames += batch.numel()
        if scaler is not None:
            batch["next", "reward"] = scaler(batch["next", "reward"], batch["next", "done"])
        learner.update(batch, index / batches, order)
        learner.new_rollout()
        update_time += time.perf_counter() - began
        if frames // every > (frames - batch.numel()) // every and frames < budget:
            evaluation.evaluate(learner, frames)
    collector.shutdown()
    evaluation.evaluate(learner, frames)
    save_policy(
        out / "model.pt",
        learner.net,
        settings,
        {"env_id": env_id, "seed": seed, "timesteps": frames},
    )
    wall = time.perf_counter() - start
    env.close()
    train_time = max(wall - evaluation.time_s, 1e-9)
    summary = {
        "env": env_id,
        "engine": "torchrl",
        "algo": "ppo",
        "device": str(env.device),
        "seed": seed,
        "timesteps": frames,
        "timesteps_requested": budget,
        "timesteps_trained": frames,
        "wall_time_s": wall,
        "train_time_s": train_time,
        "timesteps_per_s": frames / train_time,
        "first_batch_s": first_batch_s,
        # After the first batch (the step's compile, TorchRL's warm-up), evaluations apart:
        # the rate a longer run tends to.
        "steady_timesteps_per_s": (frames - frames_per_batch)
        / max(train_time - first_batch_s, 1e-9),
        # Of the training time: the learning (advantages and gradient steps); the rest is
        # collecting (the env and the policy's forward passes).
        "update_time_s": update_time,
        "eval_time_s": evaluation.time_s,
        "evaluations": len(evaluation.entries["timesteps"]),
        "last_eval_episodes": len(evaluation.entries["results"][-1]),
        "last_success_rate": float(np.mean(evaluation.entries["successes"][-1])),
        "model": str(out / "model.pt"),
        "best_model": str(out / "best_model.pt"),
        "best_model_timesteps": evaluation.best_timesteps,
        "best_mean_return": evaluation.best_mean_return,
        "settings": {k: (repr(v) if callable(v) else v) for k, v in settings.items()},
    }
    write_text_atomic(out / "train.json", json.dumps(summary, indent=2) + "\n")
    return summary
