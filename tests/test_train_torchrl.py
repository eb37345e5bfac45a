"""``bbgym train --engine torchrl``: PPO from TorchRL's losses on the env's torch backend.
The run folder's files and evaluation log, the same policy from the same seed (another
from another), the saved policy evaluated by ``bbgym evaluate``, the reward scaling against
its definition, the preset's ``torchrl`` section checked, errors that name the argument,
and parity with stable-baselines3's PPO: from the same weights and rollout, the same
update, and the same advantages with truncations bootstrapped."""

from __future__ import annotations

import json

import gymnasium as gym
import numpy as np
import pytest

torch = pytest.importorskip("torch")
pytest.importorskip("torchrl")
pytest.importorskip("array_api_compat")

from bbgym import torchrl as bbgym_torchrl  # noqa: E402
from bbgym.cli import main  # noqa: E402
from bbgym.config import TORCHRL_DEFAULTS, env_preset, load_torchrl  # noqa: E402
from bbgym.spec import env_ids  # noqa: E402

ENV = "BeachballSail-v1"
SMALL = {
    **TORCHRL_DEFAULTS,
    "num_envs": 8,
    "n_steps": 8,
    "minibatch_size": 32,
    "n_epochs": 2,
    "total_timesteps": 128,  # two batches of 8 x 8
    "eval_every_timesteps": 64,
    "eval_episodes": 3,
    "normalize_reward": True,
    "compile_step": False,  # eager: seconds, not a minute of compiling
}
SHORT = {"max_episode_steps": 20}


def train(out, seed=0, **settings):
    """A two-batch run."""
    torch.set_num_threads(1)
    return bbgym_torchrl.train_ppo(
        ENV, {**SMALL, **settings}, out=out, seed=seed, env_kwargs=SHORT, log=lambda line: None
    )


def weights(path):
    return torch.load(path, weights_only=True)["state_dict"]


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("torchrl") / "seed0"
    return out, train(out)


def test_run_folder_has_policies_summary_and_evaluation_log(small_run):
    out, summary = small_run
    assert summary["timesteps"] == 128 and summary["engine"] == "torchrl"
    assert summary["algo"] == "ppo" and summary["device"] == "cpu"
    assert json.loads((out / "train.json").read_text())["timesteps"] == 128
    assert 0.0 < summary["update_time_s"] < summary["train_time_s"]
    with np.load(out / "eval" / "evaluations.npz") as log:
        # At 64 timesteps (the period) and at the end: 3 episodes each, stable-baselines3's
        # layout (baseline's learning curves read it).
        assert log["timesteps"].tolist() == [64, 128]
        assert log["results"].shape == (2, 3) and log["ep_lengths"].shape == (2, 3)
        assert np.isfinite(log["results"]).all()
        assert ((log["ep_lengths"] >= 1) & (log["ep_lengths"] <= 20)).all()
        best = int(np.argmax(log["results"].mean(axis=1)))
        assert summary["best_model_timesteps"] == log["timesteps"][best]
        assert summary["best_mean_return"] == pytest.approx(log["results"][best].mean())
    saved = torch.load(out / "model.pt", weights_only=True)
    assert saved["format"] == bbgym_torchrl.POLICY_FORMAT and saved["timesteps"] == 128
    assert saved["env_id"] == ENV and saved["net_arch"] == SMALL["net_arch"]
    assert not list(out.rglob(".*.partial*")), "every file written whole"


def test_same_seed_same_policy_other_seed_other(small_run, tmp_path):
    out, _ = small_run
    again = tmp_path / "again"
    train(again)
    first, second = weights(out / "model.pt"), weights(again / "model.pt")
    assert all(torch.equal(first[k], second[k]) for k in first)
    other = tmp_path / "other"
    train(other, seed=1)
    third = weights(other / "model.pt")
    assert not torch.equal(first["mean.0.weight"], third["mean.0.weight"])


def test_training_changes_the_policy_from_its_initial_weights(small_run):
    """The gradient steps ran: the weights moved from their orthogonal start, and the
    log standard deviation from log_std_init."""
    out, _ = small_run
    trained = weights(out / "model.pt")
    torch.manual_seed(0)  # the initial weights as train_ppo draws them, first after seeding
    start = bbgym_torchrl.GaussianPolicyNet(
        trained["mean.0.weight"].shape[1], 2, SMALL["net_arch"], SMALL["log_std_init"]
    ).state_dict()
    moved = (trained["mean.0.weight"] - start["mean.0.weight"]).abs().max()
    assert 0.0 < moved < 1.0
    assert not torch.equal(trained["log_std"], start["log_std"])


def test_saved_policy_evaluates_deterministically(small_run):
    """``bbgym evaluate --policies ppo --model model.pt``: the squashed mean, in bounds."""
    from bbgym.cli import evaluate

    out, _ = small_run
    net = bbgym_torchrl.load_policy(out / "model.pt")
    obs = torch.linspace(-1.0, 1.0, net.mean[0].in_features)
    action = net.act(obs)
    assert torch.equal(action, torch.tanh(net.mean(obs)))
    assert action.shape == (2,) and (action.abs() < 1.0).all()
    first = evaluate.evaluate(ENV, "ppo", 2, 0, out / "model.pt")
    second = evaluate.evaluate(ENV, "ppo", 2, 0, out / "model.pt")
    assert first["mean_return"] == second["mean_return"]
    assert np.isfinite(first["mean_return"]) and first["mean_length"] >= 1


def test_an_unsquashed_policy_acts_with_its_clipped_mean_and_saves_so(tmp_path):
    """``squash_output: false``: the deterministic action is the mean clipped to the
    bounds (stable-baselines3's PPO without squashing), and the saved file says so; a file
    saved before the setting existed loads as the squashing policy it was."""
    train(tmp_path, squash_output=False)
    net = bbgym_torchrl.load_policy(tmp_path / "model.pt")
    assert not net.squash
    obs = torch.linspace(-1.0, 1.0, net.mean[0].in_features)
    assert torch.equal(net.act(obs), net.mean(obs))  # inside the bounds: the mean itself
    with torch.no_grad():
        net.mean[-1].bias.copy_(torch.tensor([3.0, -3.0]))
    assert net.act(obs).tolist() == [1.0, -1.0]
    payload = torch.load(tmp_path / "model.pt", weights_only=True)
    del payload["squash"]
    torch.save(payload, tmp_path / "old.pt")
    assert bbgym_torchrl.load_policy(tmp_path / "old.pt").squash


def test_state_dependent_exploration_holds_its_noise_and_matches_its_distribution():
    """gSDE (``use_sde``): the noise matrix is held for ``sde_sample_freq`` steps (the same
    observation gives the same action), its spread is the policy's ``scale`` (the
    variance ``features**2 @ exp(log_std)**2``), and the logged log-probability is the
    ``TanhNormal``'s that PPO's ratio uses."""
    from torchrl.modules import TanhNormal

    torch.manual_seed(0)
    n = 20_000
    net = bbgym_torchrl.GaussianPolicyNet(5, 2, [16, 16], -1.0, state_dependent=True)
    explore = bbgym_torchrl.CorrelatedExploration(net, n, sample_freq=4)
    obs = torch.linspace(-1.0, 1.0, 5).expand(n, 5)
    steps = [explore(obs) for _ in range(5)]
    for step in steps[1:4]:
        assert torch.equal(step[2], steps[0][2])  # the action: the noise held for 4 steps
    assert not torch.equal(steps[4][2], steps[0][2])  # then drawn anew
    loc, scale, action, log_prob = steps[0]
    noise = torch.atanh(action.double()) - loc.double()
    assert noise.std(dim=0).numpy() == pytest.approx(scale[0].numpy(), rel=0.03)
    assert noise.mean(dim=0).abs().max() < 4 * scale[0].max() / n**0.5
    assert torch.allclose(log_prob, TanhNormal(loc, scale).log_prob(action))
    features = net.features(obs[:1]).detach()
    variance = (features**2 @ net.log_std.detach().exp() ** 2)[0]
    assert scale[0].numpy() == pytest.approx(torch.sqrt(variance + 1e-6).numpy(), rel=1e-6)


def test_a_gsde_run_saves_its_state_dependent_policy(tmp_path):
    train(tmp_path, use_sde=True, sde_sample_freq=4)
    net = bbgym_torchrl.load_policy(tmp_path / "model.pt")
    assert net.state_dependent and net.log_std.shape == (SMALL["net_arch"][-1], 2)
    with np.load(tmp_path / "eval" / "evaluations.npz") as log:
        assert np.isfinite(log["results"]).all()


def test_a_gsde_run_draws_its_noise_at_each_rollouts_first_step(tmp_path, monkeypatch):
    """As stable-baselines3 does: at a rollout's first step (after the update, from the
    updated policy) and every ``sde_sample_freq`` steps from it, whatever calls the
    collector made before (it probes the policy once as it starts)."""
    draws, step = [], [0]
    original = bbgym_torchrl.CorrelatedExploration.forward

    def forward(self, observation):
        before = self.matrices
        out = original(self, observation)
        if self.matrices is not before:
            draws.append(step[0])
        step[0] += 1
        return out

    monkeypatch.setattr(bbgym_torchrl.CorrelatedExploration, "forward", forward)
    train(tmp_path, use_sde=True, sde_sample_freq=4)  # 2 rollouts of 8 steps
    # call 0 is the collector's probe; the rollouts' steps are calls 1-8 and 9-16
    assert draws == [0, 1, 5, 9, 13]


def test_return_scaler_is_stable_baselines3_vecnormalize_on_the_rewards():
    """Step by step, each reward divided by the spread of the discounted returns so far and
    clipped to +-10, ``VecNormalize(norm_obs=False, norm_reward=True)``'s numbers."""
    pytest.importorskip("stable_baselines3")
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    gamma = 0.9
    rng = np.random.default_rng(3)
    reward = rng.normal(0.0, 2.0, size=(3, 60)).astype(np.float32)  # as its buffers hold them
    reward[1, 55] = -400.0  # a capsize-sized reward: the clip
    done = rng.random((3, 60)) < 0.05

    class Scripted(gym.Env):
        observation_space = gym.spaces.Box(-1.0, 1.0, (1,))
        action_space = gym.spaces.Box(-1.0, 1.0, (1,))

        def __init__(self, row: int) -> None:
            self.row, self.t = row, 0

        def reset(self, *, seed=None, options=None):
            return np.zeros(1, dtype=np.float32), {}

        def step(self, action):
            r, d = reward[self.row, self.t], done[self.row, self.t]
            self.t += 1
            return np.zeros(1, dtype=np.float32), float(r), bool(d), False, {}

    vec = VecNormalize(
        DummyVecEnv([lambda i=i: Scripted(i) for i in range(3)]),
        norm_obs=False,
        norm_reward=True,
        gamma=gamma,
    )
    vec.reset()
    expected = np.stack([vec.step(np.zeros((3, 1)))[1] for _ in range(60)], axis=1)

    scaler = bbgym_torchrl.ReturnScaler(3, gamma, torch.device("cpu"))
    as_batch = torch.tensor(reward, dtype=torch.float64).unsqueeze(-1)
    done_batch = torch.tensor(done).unsqueeze(-1)
    # two batches of 30 steps: the statistics carry over from one to the next
    scaled = torch.cat(
        [
            scaler(as_batch[:, :30], done_batch[:, :30]),
            scaler(as_batch[:, 30:], done_batch[:, 30:]),
        ],
        dim=1,
    )
    assert scaled.squeeze(-1).numpy() == pytest.approx(expected, rel=1e-6)  # its float32
    assert scaled[1, 55, 0] == -10.0  # clipped
    assert (scaled.abs() < 10.0).sum() == 179  # and nothing else


def test_every_env_preset_has_valid_torchrl_settings():
    """``bbgym train --env ID --engine torchrl`` works for every id with its own preset."""
    for env_id in env_ids():
        path, _ = env_preset(env_id)
        settings = load_torchrl(path)
        batch = settings["num_envs"] * settings["n_steps"]
        assert batch % settings["minibatch_size"] == 0, env_id  # whole minibatches


@pytest.mark.parametrize(
    ("line", "named"),
    [
        ("num_envs: 0", "torchrl.num_envs"),
        ("gamma: 1.5", "torchrl.gamma"),
        ("net_arch: [64, -1]", "torchrl.net_arch"),
        ("learning_rate: fast", "torchrl.learning_rate"),
        ("dtype: float16", "torchrl.dtype"),
        ("squash_output: 1", "torchrl.squash_output"),
        ("frames: 10", "unknown torchrl settings ['frames']"),
    ],
)
def test_bad_torchrl_settings_are_named(tmp_path, line, named):
    preset = tmp_path / "p.yaml"
    preset.write_text(f"env_id: {ENV}\ntorchrl:\n  {line}\n")
    with pytest.raises(ValueError, match=named.replace("[", r"\[").replace("]", r"\]")):
        load_torchrl(preset)


def test_cli_errors_name_the_argument(tmp_path, capsys):
    preset = tmp_path / "p.yaml"
    preset.write_text(f"env_id: {ENV}\nenv: {{}}\nppo: {{}}\n")
    for argv, named in [
        (["--resume"], "--resume is for --engine sb3"),
        (["--device", "nonsense"], "--device 'nonsense': not a torch device"),
        (["--device", "mps"], "--device mps: cpu or cuda"),
        (["--preset", str(preset)], f"--preset: {preset}: no torchrl section"),
    ]:
        with pytest.raises(SystemExit):
            main(["train", "--env", ENV, "--engine", "torchrl", "--out", str(tmp_path), *argv])
        assert named in capsys.readouterr().err
    assert not (tmp_path / "train.json").exists()


def test_a_file_that_is_no_torchrl_policy_is_refused(tmp_path):
    bogus = tmp_path / "model.pt"
    torch.save({"format": "something else"}, bogus)
    with pytest.raises(ValueError, match="--model .*not a policy saved by bbgym's TorchRL PPO"):
        bbgym_torchrl.load_policy(bogus)
    bogus.write_bytes(b"PK\x03\x04 not a torch file")
    with pytest.raises(ValueError, match="--model .*not a policy saved by bbgym's TorchRL PPO"):
        bbgym_torchrl.load_policy(bogus)


def small_preset(path):
    """BeachballSail-v1's preset with :data:`SMALL` as its ``torchrl`` section."""
    import yaml

    from bbgym.config import CONFIG_DIR

    preset = yaml.safe_load((CONFIG_DIR / "beachball_sail_v1.yaml").read_text())
    preset["torchrl"] = {k: v for k, v in SMALL.items() if k != "total_timesteps"}
    path.write_text(yaml.safe_dump(preset))
    return path


def test_train_command_with_the_torchrl_engine(tmp_path, capsys):
    config = small_preset(tmp_path / "sail.yaml")
    out = tmp_path / "run"
    argv = [
        "train",
        "--env",
        ENV,
        "--engine",
        "torchrl",
        "--preset",
        str(config),
        "--timesteps",
        "100",
        "--seed",
        "3",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    printed = capsys.readouterr().out
    assert "100 timesteps round up to 128: whole batches of num_envs 8 x n_steps 8" in printed
    assert f"{ENV}: PPO trained 128 timesteps (asked 100)" in printed
    assert "(model.pt, best_model.pt, train.json with the full summary, eval/)" in printed
    summary = json.loads((out / "train.json").read_text())
    assert summary["seed"] == 3 and summary["torch_threads"] == 1
    assert summary["versions"]["torchrl"] and summary["config"] == str(config)
    assert (out / "config.yaml").read_text() == config.read_text()


def test_baseline_with_the_torchrl_engine(tmp_path):
    """``bbgym baseline --engine torchrl``: each seed trained by TorchRL's PPO, its
    ``best_model.pt`` evaluated beside random and scripted play, the results file named
    apart from stable-baselines3's."""
    pytest.importorskip("matplotlib")
    config = small_preset(tmp_path / "sail.yaml")
    out = tmp_path / "run"
    argv = [
        "baseline",
        "--env",
        ENV,
        "--engine",
        "torchrl",
        "--preset",
        str(config),
        "--timesteps",
        "64",
        "--episodes",
        "2",
        "--seeds",
        "1",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    seed0 = out / "seed0"
    assert json.loads((seed0 / "train.json").read_text())["engine"] == "torchrl"
    results = json.loads((out / "results.json").read_text())
    assert [r["policy"] for r in results] == ["random", "scripted", "ppo, 1 seed"]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["engine"] == "torchrl" and summary["evaluated_model"] == "best_model.pt"
    assert summary["timesteps"] == 64 and summary["n_envs"] == SMALL["num_envs"]
    for name in ("learning_curve.png", "episode.gif"):
        assert (out / name).stat().st_size > 0, name

    from test_docs import tables

    (tmp_path / "results" / "baselines").mkdir(parents=True)
    path = tables.record_baseline(
        out, "bbgym baseline --engine torchrl", note="tiny", results=tmp_path / "results"
    )
    assert path.name == f"{ENV}-torchrl-ppo.json"
    row, _ = tables.baseline_row(path)
    assert row.startswith(f"| {ENV}, PPO (torchrl) | ")


# -- parity with stable-baselines3's PPO: the same learning from the same data -------------

SB3_PPO = {
    "n_steps": 32,
    "batch_size": 64,
    "n_epochs": 4,
    "learning_rate": 3e-3,
    "clip_range": 0.2,
    "ent_coef": 0.0,
    "vf_coef": 0.5,
    "max_grad_norm": 0.5,
    "gamma": 0.99,
    "gae_lambda": 0.95,
    "use_sde": True,
    "sde_sample_freq": 4,
}


def sb3_kwargs(white_noise):
    """SB3 PPO's arguments: gSDE with tanh squashing (Sail's preset), or white noise with
    no squashing (SB3's default policy), its standard deviation 1 so that many samples
    fall outside the action bounds."""
    if white_noise:
        return {**SB3_PPO, "use_sde": False}, {"log_std_init": 0.0, "net_arch": [32, 32]}
    return SB3_PPO, {"log_std_init": -2.0, "net_arch": [32, 32], "squash_output": not white_noise}


def sb3_and_learner(n_envs, white_noise=False):
    """An SB3 PPO (:func:`sb3_kwargs`, 32x32) and a :class:`PPOLearner` with the same
    settings whose policy and value nets hold SB3's initial weights."""
    sb3 = pytest.importorskip("stable_baselines3")
    from stable_baselines3.common.env_util import make_vec_env

    torch.manual_seed(0)
    venv = make_vec_env(ENV, n_envs=n_envs, seed=0, env_kwargs=SHORT)
    kwargs, policy_kwargs = sb3_kwargs(white_noise)
    model = sb3.PPO("MlpPolicy", venv, seed=0, **kwargs, policy_kwargs=policy_kwargs)
    shared = (
        "learning_rate",
        "clip_range",
        "ent_coef",
        "vf_coef",
        "max_grad_norm",
        "gamma",
        "gae_lambda",
        "use_sde",
        "sde_sample_freq",
        "n_epochs",
    )
    settings = {
        **SMALL,
        **{k: kwargs[k] for k in shared},
        "net_arch": [32, 32],
        "log_std_init": policy_kwargs["log_std_init"],
        "minibatch_size": SB3_PPO["batch_size"],
        "squash_output": not white_noise,
    }
    env = bbgym_torchrl.BbgymTorchRLEnv(ENV, n_envs, compile_step=False, seed=0, **SHORT)
    learner = bbgym_torchrl.PPOLearner(env, settings)
    policy = model.policy
    pi, vf = policy.mlp_extractor.policy_net, policy.mlp_extractor.value_net
    learner.net.load_state_dict(
        {
            "mean.0.weight": pi[0].weight,
            "mean.0.bias": pi[0].bias,
            "mean.2.weight": pi[2].weight,
            "mean.2.bias": pi[2].bias,
            "mean.4.weight": policy.action_net.weight,
            "mean.4.bias": policy.action_net.bias,
            "log_std": policy.log_std,
        }
    )
    learner.advantage.value_network.module.load_state_dict(
        {
            "0.weight": vf[0].weight,
            "0.bias": vf[0].bias,
            "2.weight": vf[2].weight,
            "2.bias": vf[2].bias,
            "4.weight": policy.value_net.weight,
            "4.bias": policy.value_net.bias,
        }
    )
    return model, learner, env


@pytest.mark.parametrize("white_noise", [False, True], ids=["gsde-squashed", "white-unsquashed"])
def test_an_update_learns_what_stable_baselines3_ppo_learns_from_the_same_rollout(white_noise):
    """From SB3's initial weights and one rollout SB3 collected, :meth:`PPOLearner.learn`
    over SB3's own minibatches (the same order) ends with the weights SB3's ``PPO.train``
    ends with: TorchRL's ``ClipPPOLoss`` with these settings is SB3's objective, value
    loss, advantage normalization, gradient clipping and Adam, to float32 rounding; with
    gSDE and tanh squashing (``squash_output``), and with white noise unsquashed, whose
    samples beyond the bounds (the env clips them) keep their Gaussian log-probability."""
    from tensordict import TensorDict

    torch.set_num_threads(1)
    model, learner, env = sb3_and_learner(n_envs=4, white_noise=white_noise)
    _, callback = model._setup_learn(SB3_PPO["n_steps"] * 4, None)
    model.collect_rollouts(model.env, callback, model.rollout_buffer, SB3_PPO["n_steps"])
    buffer = model.rollout_buffer
    n = buffer.buffer_size * buffer.n_envs
    flat = TensorDict(
        {  # SB3's layout: env by env (swap_and_flatten)
            "observation": buffer.swap_and_flatten(buffer.observations),
            "action": buffer.swap_and_flatten(buffer.actions),
            "action_log_prob": buffer.swap_and_flatten(buffer.log_probs)[:, 0],
            "advantage": buffer.swap_and_flatten(buffer.advantages),
            "value_target": buffer.swap_and_flatten(buffer.returns),
        },
        batch_size=[n],
    ).apply(lambda x: torch.as_tensor(x, dtype=torch.float32))
    np.random.seed(123)  # noqa: NPY002  (SB3 draws its minibatch order from NumPy's global generator)
    model.train()
    np.random.seed(123)  # noqa: NPY002
    size = SB3_PPO["batch_size"]
    for _ in range(SB3_PPO["n_epochs"]):
        order = torch.as_tensor(np.random.permutation(n))  # noqa: NPY002
        for begin in range(0, n, size):
            learner.learn(flat[order[begin : begin + size]])
    env.close()
    policy = model.policy
    moved = (learner.net.mean[-1].weight - policy.action_net.weight.detach()).abs().max()
    assert moved < 1e-5  # where SB3's update itself moved it by over 1e-3:
    start = policy_at_start(model, white_noise)
    assert (policy.action_net.weight.detach() - start).abs().max() > 1e-3
    value = learner.advantage.value_network.module[-1].weight
    assert (value - policy.value_net.weight.detach()).abs().max() < 1e-5
    assert (learner.net.log_std - policy.log_std.detach()).abs().max() < 1e-5
    assert model.logger.name_to_value["train/clip_fraction"] > 0.0  # the clip did act
    if white_noise:  # some samples fell outside [-1, 1]: the unsquashed case is exercised
        assert (flat["action"].abs() > 1.0).any()


def policy_at_start(model, white_noise):
    """The action layer's weights SB3's PPO starts from (the same seed's construction)."""
    kwargs, policy_kwargs = sb3_kwargs(white_noise)
    clone = type(model)("MlpPolicy", model.env, seed=0, **kwargs, policy_kwargs=policy_kwargs)
    return clone.policy.action_net.weight.detach()


def test_advantages_are_stable_baselines3_gae_with_truncations_bootstrapped():
    """TorchRL's ``GAE`` over a collected batch (episodes of 20 steps: truncations) equals
    SB3's ``RolloutBuffer.compute_returns_and_advantage`` given what SB3's PPO stores: a
    truncated step's reward plus gamma times the value of its final observation, and the
    episode starts."""
    from stable_baselines3.common.buffers import RolloutBuffer
    from torchrl.collectors import Collector

    torch.set_num_threads(1)
    model, learner, env = sb3_and_learner(n_envs=4)
    steps = 48
    collector = Collector(
        env,
        learner.explorer(4),
        frames_per_batch=4 * steps,
        total_frames=4 * steps,
        device=env.device,
        auto_register_policy_transforms=False,
    )
    batch = next(iter(collector))
    collector.shutdown()
    env.close()
    truncated = batch["next", "truncated"][..., 0]
    assert truncated.sum() >= 4 and not batch["next", "terminated"].any()
    with torch.no_grad():
        learner.advantage(batch)
        critic = learner.advantage.value_network.module
        value = critic(batch["observation"])[..., 0].double()
        final_value = critic(batch["next", "observation"])[..., 0].double()
    gamma, done = SB3_PPO["gamma"], batch["next", "done"][..., 0]
    reward = batch["next", "reward"][..., 0].double() + gamma * final_value * truncated
    starts = torch.zeros_like(done)
    starts[:, 1:] = done[:, :-1]
    buffer = RolloutBuffer(
        steps,
        model.observation_space,
        model.action_space,
        gamma=gamma,
        gae_lambda=SB3_PPO["gae_lambda"],
        n_envs=4,
    )
    buffer.rewards[:] = reward.T.numpy()
    buffer.values[:] = value.T.numpy()
    buffer.episode_starts[:] = starts.T.numpy()
    buffer.compute_returns_and_advantage(final_value[:, -1], done[:, -1].numpy())
    ours = batch["advantage"][..., 0].T.double().numpy()
    assert ours == pytest.approx(buffer.advantages, abs=1e-5)
    assert np.abs(buffer.advantages).max() > 0.1
