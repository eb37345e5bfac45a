"""What ``bbgym --help`` says against what the commands do: the algorithms the presets
train, plain text (no RST markup from the module docstrings), env ids that are registered,
and defaults that are argparse's."""

from __future__ import annotations

import argparse
import re

import pytest

from bbgym import cli
from bbgym.config import load_training, preset_files, preset_path

PARSER = cli.build_parser()
(SUBPARSERS,) = [a for a in PARSER._actions if isinstance(a, argparse._SubParsersAction)]
COMMANDS = SUBPARSERS.choices


def preset_algorithms() -> set[str]:
    """Every algorithm a shipped preset trains."""
    names = {path.stem for path in preset_path("BeachballSail-v0").parent.glob("*.yaml")}
    return {load_training(preset_path(name))[1]["algo"] for name in names}


@pytest.mark.parametrize("command", ["train", "baseline"])
def test_the_training_commands_name_every_algorithm_the_presets_train(command):
    algorithms = preset_algorithms()
    assert algorithms >= {"ppo", "sac"}
    summary, description = cli.COMMANDS[command], COMMANDS[command].description
    for algo in algorithms:
        assert algo.upper() in summary, (command, algo, summary)
        assert algo.upper() in description, (command, algo)


@pytest.mark.parametrize("command", [None, *cli.COMMANDS])
def test_help_is_plain_text(command):
    text = PARSER.format_help() if command is None else COMMANDS[command].format_help()
    assert "``" not in text
    assert not re.search(r":(mod|func|class|attr|meth|data):`", text), text


def test_the_top_help_lists_bbgyms_registered_ids():
    import gymnasium as gym

    text = " ".join(PARSER.format_help().split())
    listed = re.search(r"ENV_ID: one of ([^.]*(?:\.[^ ][^.]*)*?)\. Run", text).group(1)
    ids = [name.strip() for name in listed.split(",")]
    assert ids == cli.bbgym_env_ids()
    assert all(name in gym.registry for name in ids)


def option_actions(parser: argparse.ArgumentParser) -> list[argparse.Action]:
    """The options the help shows (not an alias's hidden action, :func:`cli.add_aliased`)."""
    return [
        a
        for a in parser._actions
        if a.option_strings and a.dest != "help" and a.help is not argparse.SUPPRESS
    ]


@pytest.mark.parametrize("command", cli.COMMANDS)
def test_defaults_shown_are_argparse_defaults(command):
    """Each option's help shows ``(default: X)`` for argparse's default X, once; none shows
    ``None``; the usage lines of the description give the same defaults."""
    sub = COMMANDS[command]
    formatter = sub._get_formatter()
    text = sub.format_help()
    assert "(default: None)" not in text and "(default: False)" not in text
    for action in option_actions(sub):
        shown = formatter._get_help_string(action) % {"default": action.default}
        assert shown.count("default") <= 1 or "%(default)" in (action.help or ""), shown
        default = action.default
        if isinstance(default, (list, tuple)):
            assert all(str(item) in shown for item in default), (command, action.dest)
        elif default is not None and not isinstance(default, bool):
            assert f"(default: {default})" in shown, (command, action.dest)
    by_option = {s: a for a in option_actions(sub) for s in a.option_strings}
    for option, value in re.findall(r"\[(--[a-z-]+) ([^\]\s|<]+)\]", sub.description or ""):
        action = by_option.get(option)
        if action is not None and action.default is None:
            # An example value (--address auto) is fine; a number reads as the default.
            assert not re.fullmatch(r"[0-9.]+", value), (command, option, value)
        if action is None or value.isupper() or action.default is None:
            continue  # a metavar (ENV_ID, N) or an option without a fixed default
        default = action.default
        if isinstance(default, (int, float)) and not isinstance(default, bool):
            assert float(value) == float(default), (command, option, value, default)
        else:
            assert value == str(default), (command, option, value, default)


def test_every_env_default_is_a_registered_bbgym_id():
    for name, sub in COMMANDS.items():
        for action in option_actions(sub):
            if action.dest in ("env", "envs") and action.default is not None:
                defaults = action.default if action.dest == "envs" else [action.default]
                assert set(defaults) <= set(cli.bbgym_env_ids()), name
    assert preset_files()
