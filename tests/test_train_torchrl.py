"""``bbgym train --engine torchrl``: PPO from TorchRL's losses on the env's torch backend.
The run folder's files and evaluation log, the same policy from the same seed (another
from another), the saved policy evaluated by ``bbgym evaluate``, the reward scaling against
its definition, the preset's ``torchrl`` section checked, and errors that name the
argument."""

from __future__ import annotations

import json

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
    return bbgym_torchrl.train_ppo(ENV, {**SMALL, **settings}, out=out, seed=seed,
                                   env_kwargs=SHORT, log=lambda line: None)  # fmt: skip


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


def test_return_scaler_divides_by_the_std_of_the_discounted_return():
    gamma = 0.9
    scaler = bbgym_torchrl.ReturnScaler(2, gamma, torch.device("cpu"))
    reward = torch.tensor([[1.0, 2.0, -1.0, 0.5], [0.0, 3.0, 1.0, 1.0]]).unsqueeze(-1)
    done = torch.zeros_like(reward, dtype=torch.bool)
    done[0, 1] = True  # env 0's episode ends at its second step: its return restarts
    scaled = scaler(reward, done)
    returns = np.array([[1.0, 2.9, -1.0, -0.4], [0.0, 3.0, 3.7, 4.33]])
    assert scaled.numpy() == pytest.approx(reward.numpy() / returns.std(), rel=1e-6)
    # A second batch updates the statistics as if both had come at once.
    more = torch.ones(2, 2, 1)
    scaled = scaler(more, torch.zeros_like(more, dtype=torch.bool))
    later = [-0.4 * gamma + 1, -0.4 * gamma**2 + gamma + 1, 4.33 * gamma + 1,
             4.33 * gamma**2 + gamma + 1]  # fmt: skip
    both = np.concatenate([returns.ravel(), later])
    assert scaled.numpy() == pytest.approx(1.0 / both.std(), rel=1e-6)


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
    argv = ["train", "--env", ENV, "--engine", "torchrl", "--preset", str(config),
            "--timesteps", "100", "--seed", "3", "--out", str(out)]  # fmt: skip
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
    argv = ["baseline", "--env", ENV, "--engine", "torchrl", "--preset", str(config),
            "--timesteps", "64", "--episodes", "2", "--seeds", "1", "--out", str(out)]  # fmt: skip
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
    path = tables.record_baseline(out, "bbgym baseline --engine torchrl", note="tiny",
                                  results=tmp_path / "results")  # fmt: skip
    assert path.name == f"{ENV}-torchrl-ppo.json"
    row, _ = tables.baseline_row(path)
    assert row.startswith(f"| {ENV}, PPO (torchrl) | ")
