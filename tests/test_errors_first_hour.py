"""Errors a newcomer meets in the first hour name what the newcomer typed (issue 52, item 7).

``gym.make("BeachballSail-v2", wind_sped_range=(3, 6))`` used to raise ``SailTask.__init__()
got an unexpected keyword argument ...`` (an internal class, no suggestion), to which
``gym.make`` appended the version's 900 characters of preset arguments; ``bbgym scene
--lst`` printed the top-level usage; an unknown scene listed 29 names without the nearest;
``bbgym evaluate --policy`` worked only as an abbreviation of ``--policies``.
"""

from __future__ import annotations

import gymnasium as gym
import pytest

from bbgym import cli
from bbgym.spec import UnknownArgumentError, env_ids

VECTOR_MODES = ("vector_entry_point", "sync", "async")


def preset_names(env_id: str) -> list[str]:
    """The names of the kwargs ``env_id`` is registered with (which the user did not pass)."""
    return list(gym.spec(env_id).kwargs)


def assert_no_preset(message: str, env_id: str, suggested: str) -> None:
    assert "was raised from the environment creator" not in message, message
    assert "with kwargs" not in message, message
    for name in preset_names(env_id):
        if name != suggested:
            assert repr(name) not in message, (name, message)


def test_a_misspelt_argument_names_the_id_and_the_nearest_argument():
    with pytest.raises(TypeError) as raised:
        gym.make("BeachballSail-v2", wind_sped_range=(3, 6))
    message = str(raised.value)
    assert message == (
        "BeachballSail-v2 got an unknown argument 'wind_sped_range'; "
        "did you mean 'wind_speed_range'?"
    )
    assert isinstance(raised.value, UnknownArgumentError)
    assert "SailTask" not in message
    assert_no_preset(message, "BeachballSail-v2", "wind_speed_range")


@pytest.mark.parametrize("env_id", env_ids())
def test_every_id_names_the_misspelt_argument_without_its_presets(env_id):
    assert len(env_ids()) >= 11  # Sail v0-v2, Throw v0-v1, Curve v0-v2, Topple v0-v2
    with pytest.raises(TypeError) as raised:
        gym.make(env_id, wind_sped_range=(3, 6))
    message = str(raised.value)
    assert message.startswith(f"{env_id} got an unknown argument 'wind_sped_range'"), message
    assert "did you mean 'wind_speed_range'?" in message
    assert "its arguments" not in message  # a near one is named, not the list
    assert_no_preset(message, env_id, "wind_speed_range")


@pytest.mark.parametrize("mode", VECTOR_MODES)
@pytest.mark.parametrize("env_id", ["BeachballSail-v2", "BeachballCurve-v2", "BeachballTopple-v2"])
def test_make_vec_names_the_misspelt_argument_in_every_mode(env_id, mode):
    with pytest.raises(UnknownArgumentError) as raised:
        gym.make_vec(env_id, num_envs=2, vectorization_mode=mode, wind_sped_range=(3, 6))
    message = str(raised.value)
    assert message == (
        f"{env_id} got an unknown argument 'wind_sped_range'; did you mean 'wind_speed_range'?"
    )
    assert_no_preset(message, env_id, "wind_speed_range")


def test_a_vector_env_argument_is_suggested_and_accepted():
    with pytest.raises(UnknownArgumentError, match=r"'bakend'; did you mean 'backend'\?"):
        gym.make_vec(
            "BeachballSail-v0", num_envs=2, vectorization_mode="vector_entry_point", bakend="numpy"
        )
    with pytest.raises(UnknownArgumentError, match=r"'render_mod'; did you mean 'render_mode'\?"):
        gym.make("BeachballTopple-v0", render_mod="rgb_array")
    venv = gym.make_vec(
        "BeachballSail-v0",
        num_envs=2,
        vectorization_mode="vector_entry_point",
        backend="numpy",
        max_episode_steps=5,
    )
    assert venv.num_envs == 2
    venv.close()
    env = gym.make("BeachballSail-v2", wind_speed_range=(3, 6), render_mode="rgb_array")
    assert env.unwrapped.task is not None
    env.close()


def test_an_argument_near_none_lists_the_arguments():
    with pytest.raises(UnknownArgumentError) as raised:
        gym.make("BeachballCurve-v1", zzz=1)
    message = str(raised.value)
    assert message.startswith("BeachballCurve-v1 got an unknown argument 'zzz'; its arguments: ")
    assert "did you mean" not in message
    for name in ("render_mode", "ball", "wind_speed_range", "hit_bonus"):
        assert name in message
    assert "(and for its native vector env: max_episode_steps, backend," in message


def test_the_error_survives_gymnasiums_re_raise():
    """``gym.make`` re-raises an env creator's ``TypeError`` as ``type(e)(f"{e} was raised
    from the environment creator for {id} with kwargs ({...})")``: the error keeps its own
    message (and stays a TypeError)."""
    error = UnknownArgumentError("BeachballSail-v2 got an unknown argument 'x'")
    again = type(error)(
        f"{error} was raised from the environment creator for BeachballSail-v2 with kwargs "
        "({'sail_model': 'cambered', 'x': 1})"
    )
    assert str(again) == "BeachballSail-v2 got an unknown argument 'x'"
    assert isinstance(again, TypeError)


def run_cli(capsys, argv: list[str]) -> str:
    """``bbgym argv``'s stderr, where it exits with status 2."""
    with pytest.raises(SystemExit) as exit_info:
        cli.main(argv)
    assert exit_info.value.code == 2
    return capsys.readouterr().err


TOP_USAGE = "usage: bbgym [-h] [--version] COMMAND"


def test_an_unknown_option_gets_the_subcommands_usage_and_the_nearest_option(capsys):
    err = run_cli(capsys, ["scene", "--lst"])
    assert err.startswith("usage: bbgym scene"), err
    assert TOP_USAGE not in err
    assert "bbgym scene: error: unrecognized arguments: --lst (did you mean --list?)" in err


def test_an_unknown_option_of_train_gets_trains_usage(capsys):
    err = run_cli(capsys, ["train", "--env", "BeachballSail-v0", "--algo", "ppo"])
    assert err.startswith("usage: bbgym train"), err
    assert TOP_USAGE not in err
    assert "bbgym train: error: unrecognized arguments: --algo ppo" in err


def test_an_unknown_option_before_the_command_gets_the_top_usage(capsys):
    err = run_cli(capsys, ["--verbose", "scene", "magnus"])
    assert err.startswith(TOP_USAGE), err
    assert "bbgym: error: unrecognized arguments: --verbose" in err


def test_an_unknown_scene_names_the_nearest(capsys):
    err = run_cli(capsys, ["scene", "magnos"])
    assert "usage: bbgym scene" in err
    assert "unknown scene 'magnos': did you mean 'magnus'? The scenes: push, arrow," in err
    err = run_cli(capsys, ["scene", "qqqq"])
    assert "unknown scene 'qqqq'; the scenes: push, arrow," in err
    assert "did you mean" not in err


def test_get_scene_names_the_nearest():
    from bbgym.scenes import get_scene

    with pytest.raises(KeyError, match="unknown scene 'sproing-3': did you mean 'sproing-3d'"):
        get_scene("sproing-3")


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["evaluate", "--env", "BeachballSail-v0", "--polic", "random"],
            "unrecognized arguments: --polic (did you mean --policy?) random",
        ),
        (
            ["evaluate", "--env", "BeachballSail-v0", "--episode", "3"],
            "unrecognized arguments: --episode (did you mean --episodes?) 3",
        ),
        (
            ["bench", "--env", "CartPole-v1"],
            "argument --env: 'CartPole-v1' is a registered Gymnasium env but not one of bbgym's",
        ),
        (
            ["evaluate", "--env", "BeachballSail-v0", "--policy", "ppo"],
            "bbgym evaluate: error: --policy ppo needs --model",
        ),
        (
            ["evaluate", "--env", "BeachballSail-v0", "--policies", "ppo"],
            "bbgym evaluate: error: --policies ppo needs --model",
        ),
        (
            ["evaluate", "--env", "BeachballSail-v0", "--policy", "bogus"],
            "argument --policy: unknown policies ['bogus']",
        ),
        (
            ["record", "--env", "BeachballSail-v0", "--policies", "ppo"],
            "bbgym record: error: --policies ppo needs --model",
        ),
        (
            ["record", "--env", "BeachballSail-v0", "--policies", "bogus"],
            "argument --policies: invalid choice: 'bogus'",
        ),
        (["record", "--env", "BeachballSail-v0"], "one of the arguments --policy is required"),
        (
            ["evaluate", "--env", "BeachballSail-v0", "--policy", "ppo", "--policies", "random"],
            "argument --policies: not allowed with argument --policy",
        ),
    ],
)
def test_options_are_spelt_in_full_and_named_as_typed(capsys, argv, message):
    assert message in run_cli(capsys, argv)


def test_policy_and_policies_are_one_option():
    parser = cli.build_parser()
    for command, dest in (("evaluate", "policies"), ("record", "policy")):
        for spelling in ("--policy", "--policies"):
            args = parser.parse_args([command, "--env", "BeachballSail-v0", spelling, "random"])
            expected = ["random"] if dest == "policies" else "random"
            assert getattr(args, dest) == expected, (command, spelling)
            assert cli.as_passed(args, dest, "--x") == spelling
    args = parser.parse_args(["bench", "--env", "BeachballSail-v0"])
    assert args.envs == ["BeachballSail-v0"]
    args = parser.parse_args(["evaluate", "--env", "BeachballSail-v0"])
    assert args.policies == ["random", "scripted"]
    assert cli.as_passed(args, "policies", "--policies") == "--policies"


@pytest.mark.parametrize(
    ("env_id", "argument", "value"),
    [
        ("BeachballSail-v2", "backend", "torch"),
        ("BeachballThrow-v1", "dtype", "float32"),
        ("BeachballTopple-v2", "output", "torch"),
    ],
)
def test_a_vector_env_argument_given_to_make_points_to_make_vec(env_id, argument, value):
    """It used to be the task class's ``TypeError`` with the preset's kwargs appended."""
    with pytest.raises(UnknownArgumentError) as raised:
        gym.make(env_id, **{argument: value})
    message = str(raised.value)
    assert (
        f"got {argument!r}, an argument of its native vector env only: gym.make_vec(id, num_envs=N"
        in message
    )
    assert "Task" not in message
    assert_no_preset(message, env_id, argument)
