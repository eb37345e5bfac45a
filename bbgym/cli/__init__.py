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
    bbgym scene NAME                            a demo of the course text, measured and drawn

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
import re
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import Any

COMMANDS: dict[str, str] = {
    "train": "train the preset's algorithm, PPO or SAC (stable-baselines3; PPO also on Ray "
    "RLlib), on an env",
    "evaluate": "evaluate policies over the same seeded episodes; write a results table",
    "baseline": "train the preset's PPO or SAC, evaluate it beside random and scripted play, "
    "write a run folder",
    "record": "an animation (GIF or MP4) of an episode of any policy",
    "play": "play an env from the keyboard (pygame window)",
    "polar": "compute and plot the dinghy's polar diagram from the physics",
    "bench": "steps per second and memory of every env, as ratios to CartPole",
    "demo": "one scripted episode of an env (default: the first sailing one), as a GIF",
    "fuzz": "fuzz every env through its public API (random valid arguments and actions)",
    "scene": "run a demo of the course text (a scene): its measures, and an animation",
}
"""Subcommand -> one-line help; the module ``bbgym.cli.<name>`` implements it."""


class UsageError(Exception):
    """A bad combination of arguments, found after parsing: the command's usage is printed
    with the message and the exit status is 2, as argparse does for its own errors."""


class MissingExtra(Exception):
    """A command needs optional dependencies that are not installed: the message names
    each missing module, its extra, and the pip command that installs them
    (:func:`bbgym._extras.install_hint`)."""

    def __init__(self, missing: dict[str, list[str]]) -> None:
        from bbgym._extras import missing_message

        self.missing = missing
        super().__init__(missing_message(missing))


def require(module: str, extra: str) -> None:
    """Raise :class:`MissingExtra` if ``module`` (of bbgym's ``extra``) cannot be imported."""
    require_all([(module, extra)])


def require_all(needs: Sequence[tuple[str, str]]) -> None:
    """Raise one :class:`MissingExtra` naming every module of ``needs``, pairs ``(module,
    extra)``, that cannot be imported."""
    from bbgym._extras import missing_modules

    missing = missing_modules(needs)
    if missing:
        raise MissingExtra(missing)


class HelpFormatter(argparse.RawDescriptionHelpFormatter, argparse.ArgumentDefaultsHelpFormatter):
    """Keeps the command's description as written and shows each option's default, where it
    has one and its help does not say it in words (not a flag's False, nor the None of an
    option whose help says what it defaults to)."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help or ""
        if action.default is None or isinstance(action.default, bool) or "default" in text:
            return action.help
        return super()._get_help_string(action)


_RST_ROLE = re.compile(r":[a-z]+:`~?([^`<]*?)\s*(?:<[^>]*>)?`")
_RST_LITERAL = re.compile(r"``(.+?)``", re.DOTALL)


def plain_text(doc: str) -> str:
    """A module docstring as plain text for ``--help``: RST literals (````x````) lose their
    backticks, cross-references (``:mod:`bbgym.spec```, ``:attr:`~bbgym.spec.EnvSpec.demo```)
    become their target's (last) name."""

    def role(match: re.Match[str]) -> str:
        target = match.group(1)
        shown = target.rsplit(".", 1)[-1] if match.group(0).find("`~") >= 0 else target
        return shown

    return _RST_LITERAL.sub(r"\1", _RST_ROLE.sub(role, doc))


def bbgym_env_ids() -> list[str]:
    """The env ids bbgym's families register, in their specs' order."""
    import bbgym  # noqa: F401  (registers the ids)
    from bbgym.spec import env_ids

    return env_ids()


def env_id(text: str) -> str:
    """An argparse ``type``: an env id a bbgym family registers, or an error listing them.
    An id another package registers (``CartPole-v1``) is refused too, saying so: the
    commands need what a bbgym family's spec declares (its policies, outcomes, presets)."""
    import gymnasium as gym

    ids = bbgym_env_ids()
    if text in ids:
        return text
    if text in gym.registry:
        raise argparse.ArgumentTypeError(
            f"{text!r} is a registered Gymnasium env but not one of bbgym's; the bbgym "
            f"commands run bbgym's own ids: {', '.join(ids)}"
        )
    raise argparse.ArgumentTypeError(f"unknown env id {text!r}; bbgym's ids: {', '.join(ids)}")


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


def check_device(device: str, argument: str) -> None:
    """``device`` (given as ``argument``) names a CPU or CUDA device torch has here, or
    :class:`UsageError` says why not."""
    import torch

    try:
        kind = torch.device(device).type
    except (RuntimeError, ValueError) as err:
        raise UsageError(f"{argument} {device!r}: not a torch device ({err})") from None
    if kind not in ("cpu", "cuda"):
        raise UsageError(f"{argument} {device}: cpu or cuda (cuda:N), got a {kind} device")
    if kind == "cuda" and not torch.cuda.is_available():
        raise UsageError(
            f"{argument} {device}: torch {torch.__version__} sees no CUDA device "
            f"(CUDA build: {torch.version.cuda or 'none'}); without "
            f"{argument} it runs on the CPU"
        )


class StoreAsPassed(argparse.Action):
    """argparse's ``store``, for an option with aliases (``--policies``, ``--policy``): it
    also keeps the spelling the user typed, so that an error can name the option as
    passed (:func:`as_passed`)."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        setattr(namespace, self.dest, values)
        setattr(namespace, f"_{self.dest}_as_passed", option_string)


def add_aliased(
    parser: argparse.ArgumentParser,
    name: str,
    *aliases: str,
    required: bool = False,
    **kwargs: Any,
) -> argparse.Action:
    """Add option ``name`` that ``aliases`` spell too (the parsers take no abbreviations,
    so each spelling is explicit).

    Each alias is an option of its own, hidden from the usage, that stores to the same
    place: argparse's errors then name the spelling the user typed ("argument --policy:
    invalid choice"), not both. The spellings are a mutually exclusive group (required
    where ``required``): one value, given once.

    Args:
        parser: The command's parser.
        name: The canonical spelling (``"--policies"``): the usage and help show it, and
            ``args`` holds the value under its name.
        *aliases: The other spellings (``"--policy"``), named in the help.
        required: Whether one of the spellings must be given.
        **kwargs: ``add_argument``'s other keyword arguments (not ``action`` nor ``dest``).

    Returns:
        The canonical spelling's argparse action.
    """
    target = parser.add_mutually_exclusive_group(required=required)
    if aliases and kwargs.get("help"):
        kwargs["help"] += f" (also {', '.join(aliases)})"
    action = target.add_argument(name, action=StoreAsPassed, **kwargs)
    hidden = {k: v for k, v in kwargs.items() if k not in ("help", "default", "metavar")}
    for alias in aliases:
        target.add_argument(
            alias,
            dest=action.dest,
            action=StoreAsPassed,
            default=argparse.SUPPRESS,
            help=argparse.SUPPRESS,
            **hidden,
        )
    return action


def as_passed(args: argparse.Namespace, dest: str, canonical: str) -> str:
    """The spelling of an option of :func:`add_aliased` the user typed.

    Args:
        args: The parsed arguments.
        dest: The option's attribute in ``args`` (``"policies"``).
        canonical: What to name it when the user did not pass it (its default applies).

    Returns:
        The option string as typed (``"--policy"``), else ``canonical``.
    """
    return getattr(args, f"_{dest}_as_passed", None) or canonical


def unrecognized_message(parser: argparse.ArgumentParser, extras: Sequence[str]) -> str:
    """argparse's "unrecognized arguments" message, with the nearest option of ``parser``
    after each unknown option that is near one ("did you mean --list?").

    Args:
        parser: The (sub)command's parser the arguments were given to.
        extras: The arguments it did not recognise, as the user typed them.

    Returns:
        The message for ``parser.error``.
    """
    from bbgym.spec import nearest

    options = [s for action in parser._actions for s in action.option_strings]
    words = []
    for text in extras:
        near = nearest(text.split("=", 1)[0], options) if text.startswith("-") else None
        words.append(text if near is None else f"{text} (did you mean {near}?)")
    return f"unrecognized arguments: {' '.join(words)}"


def build_parser() -> argparse.ArgumentParser:
    """The ``bbgym`` parser with every subcommand.

    No parser takes abbreviations (``allow_abbrev=False``): ``--polic`` is an error, not
    ``--policies``; an option that has two names (``--policies``, ``--policy``) declares
    both (:func:`add_aliased`)."""
    from bbgym import __version__

    parser = argparse.ArgumentParser(
        prog="bbgym",
        description=plain_text(__doc__.split("\n\n")[0].replace("\n", " ")),
        epilog=f"ENV_ID: one of {', '.join(bbgym_env_ids())}. Run 'bbgym <command> --help' "
        "for a command's options.",
        allow_abbrev=False,
    )
    parser.add_argument("--version", action="version", version=f"bbgym {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, summary in COMMANDS.items():
        module = importlib.import_module(f"bbgym.cli.{name}")
        sub = commands.add_parser(
            name,
            help=summary,
            description=plain_text(module.__doc__ or ""),
            formatter_class=HelpFormatter,
            allow_abbrev=False,
        )
        module.add_arguments(sub)
        needs = getattr(module, "needs", None)
        sub.set_defaults(_run=module.run, _parser=sub, _needs=needs)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``bbgym`` with ``argv`` (default ``sys.argv[1:]``); return the exit status."""
    parser = build_parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    # A subcommand's parser hands what it does not recognise up to the top-level parser,
    # whose own error would print ``bbgym``'s usage: the subcommand's parser reports it,
    # with its usage, and the nearest option where one is near.
    args, extras = parser.parse_known_args(argv)
    if extras:
        before_command = argv[: argv.index(args.command)]
        target = parser if any(text in extras for text in before_command) else args._parser
        target.error(unrecognized_message(target, extras))  # exits with status 2
    try:
        # Every extra the command will need is checked before it starts any work: a
        # baseline does not train for an hour and then fail for want of pygame.
        if args._needs is not None:
            require_all(args._needs(args))
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
