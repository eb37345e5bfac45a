"""The ``bbgym`` command (also ``python -m bbgym``): one console entry point with a
subcommand for each job.

    bbgym train --env ENV_ID                    train PPO or SAC from the env's preset
    bbgym evaluate --env ENV_ID                 compare policies over seeded episodes
    bbgym baseline --env ENV_ID                 train, evaluate, plot and record in one run
    bbgym record --env ENV_ID --policy scripted an animation of an episode
    bbgym play --env ENV_ID                     play from the keyboard
    bbgym polar                                 the dinghy's polar diagram
    bbgym bench                                 steps per second against CartPole
    bbgym demo                                  one scripted sailing episode, as a GIF
    bbgym fuzz                                  fuzz every env through its public API

``ENV_ID`` is any id an env family registers (``bbgym --help`` lists them; the families'
specs, :mod:`bbgym.spec`, declare them). ``bbgym <command> --help`` lists each command's
options with their defaults. Every command
module has ``add_arguments(parser)`` and ``run(args)``; the argument parsing stays light
(no torch, pygame or matplotlib import) so ``--help`` works on a core install, and a
command that needs an extra says which one.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import Any

COMMANDS: dict[str, str] = {
    "train": "train PPO (stable-baselines3, or Ray RLlib) on an env from its preset",
    "evaluate": "evaluate policies over the same seeded episodes; write a results table",
    "baseline": "train PPO, evaluate it beside random and scripted play, write a run folder",
    "record": "an animation (GIF or MP4) of an episode of any policy",
    "play": "play an env from the keyboard (pygame window)",
    "polar": "compute and plot the dinghy's polar diagram from the physics",
    "bench": "steps per second and memory of every env, as ratios to CartPole",
    "demo": "one scripted episode of an env (default: the first sailing one), as a GIF",
    "fuzz": "fuzz every env through its public API (random valid arguments and actions)",
}
"""Subcommand -> one-line help; the module ``bbgym.cli.<name>`` implements it."""


class UsageError(Exception):
    """A bad combination of arguments, found after parsing: the command's usage is printed
    with the message and the exit status is 2, as argparse does for its own errors."""


class MissingExtra(Exception):
    """A command needs an optional dependency that is not installed."""

    def __init__(self, extra: str, module: str) -> None:
        super().__init__(
            f"this command needs {module!r}, which is in bbgym's {extra!r} extra: "
            f'pip install "bbgym[{extra}]" (from a checkout: pip install -e ".[{extra}]")'
        )


def require(module: str, extra: str) -> None:
    """Raise :class:`MissingExtra` if ``module`` cannot be imported."""
    import importlib.util

    if importlib.util.find_spec(module) is None:
        raise MissingExtra(extra, module)


class HelpFormatter(argparse.RawDescriptionHelpFormatter, argparse.ArgumentDefaultsHelpFormatter):
    """Keeps the command's docstring as written and shows every option's default."""


def bbgym_env_ids() -> list[str]:
    """The env ids bbgym's families register, in their specs' order."""
    import bbgym  # noqa: F401  (registers the ids)
    from bbgym.spec import env_ids

    return env_ids()


def env_id(text: str) -> str:
    """An argparse ``type``: an env id a bbgym family registers, or an error listing them."""
    if text not in bbgym_env_ids():
        raise argparse.ArgumentTypeError(
            f"unknown env id {text!r}; bbgym's ids: {', '.join(bbgym_env_ids())}"
        )
    return text


def _number(text: str, cast: type, minimum: float, strict: bool) -> Any:
    """``text`` as ``cast`` (int or float), finite and >= ``minimum`` (> where ``strict``),
    or argparse's error saying what was expected."""
    import math

    try:
        value = cast(text)
    except ValueError:
        kind = "an integer" if cast is int else "a number"
        raise argparse.ArgumentTypeError(f"expected {kind}, got {text!r}") from None
    bound = f"{'>' if strict else '>='} {minimum:g}"
    if not math.isfinite(value) or value < minimum or (strict and value == minimum):
        finite = "finite and " if cast is float else ""
        raise argparse.ArgumentTypeError(f"must be {finite}{bound}, got {text}")
    return value


def positive_int(text: str) -> int:
    """An argparse ``type``: an integer >= 1."""
    return _number(text, int, 1, strict=False)


def nonnegative_int(text: str) -> int:
    """An argparse ``type``: an integer >= 0."""
    return _number(text, int, 0, strict=False)


def positive_float(text: str) -> float:
    """An argparse ``type``: a finite number > 0."""
    return _number(text, float, 0.0, strict=True)


def build_parser() -> argparse.ArgumentParser:
    """The ``bbgym`` parser with every subcommand."""
    from bbgym import __version__

    parser = argparse.ArgumentParser(
        prog="bbgym",
        description=__doc__.split("\n\n")[0].replace("\n", " "),
        epilog="Run 'bbgym <command> --help' for a command's options.",
    )
    parser.add_argument("--version", action="version", version=f"bbgym {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, summary in COMMANDS.items():
        module = importlib.import_module(f"bbgym.cli.{name}")
        sub = commands.add_parser(
            name,
            help=summary,
            description=module.__doc__,
            formatter_class=HelpFormatter,
        )
        module.add_arguments(sub)
        sub.set_defaults(_run=module.run, _parser=sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``bbgym`` with ``argv`` (default ``sys.argv[1:]``); return the exit status."""
    parser = build_parser()
    args = parser.parse_args(list(sys.argv[1:] if argv is None else argv))
    try:
        with show_bbgym_logs():
            status = args._run(args)
    except UsageError as err:
        args._parser.error(str(err))  # exits with status 2
    except MissingExtra as err:
        print(f"bbgym {args.command}: {err}", file=sys.stderr)
        return 3
    return int(status or 0)


@contextmanager
def show_bbgym_logs() -> Iterator[None]:
    """bbgym's INFO log lines (such as the torch backend's "compiling ...") on stderr while a
    command runs. Only the command does this: the library leaves logging to its user, and the
    handler goes again afterwards, so ``main()`` called in a process (the tests) leaves no
    handler behind on a stream that may since have been closed."""
    logger = logging.getLogger("bbgym")
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("bbgym: %(message)s"))
    level = logger.level
    logger.addHandler(handler)
    logger.setLevel(min(level or logging.INFO, logging.INFO))
    try:
        yield
    finally:
        logger.removeHandler(handler)
        logger.setLevel(level)


def script_main(command: str) -> int:
    """``scripts/<command>.py``: the same as ``bbgym <command>``."""
    return main([command, *sys.argv[1:]])
