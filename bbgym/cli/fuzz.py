"""Fuzz every env, the families of many agents (the race) and the course's scenes through
their public API (see :mod:`bbgym.fuzz`).

    bbgym fuzz [--steps 1000000] [--seed 0] [--num-envs 32] [--minutes M]
               [--multi-agent-share 0.1] [--scene-share 0.1] [--out runs/fuzz]

Random valid constructor arguments (every physical constant over its whole accepted
interval), reset options and actions, on single and native vector envs; every
observation, reward and info float is checked, and every invalid number argument is
checked to raise the right error naming it. Each family of many agents whose spec says how
(:class:`bbgym.spec.MultiAgentFuzz`; the PettingZoo race, with the ``race`` extra, in its
parallel and AEC forms) is run the same way, and the course's scenes are run with
random parameters on NumPy and torch (the ``torch`` extra), each taking its share of the
steps. Writes ``fuzz.md`` and ``fuzz.json``; exits with status 1 if anything failed, with
what reproduces it.
"""

from __future__ import annotations

import argparse
import json
import math
import warnings
from pathlib import Path

from bbgym.cli import UsageError, positive_float, positive_int


def share(text: str) -> float:
    """An argparse ``type``: a share of the steps, in [0, 1)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not 0.0 <= value < 1.0:
        raise argparse.ArgumentTypeError(f"must be in [0, 1), got {text}")
    return value


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--steps", type=positive_int, default=1_000_000, help="steps in all")
    parser.add_argument("--seed", type=int, default=0, help="seed of the configurations")
    parser.add_argument("--num-envs", type=positive_int, default=32, help="size of the vector envs")
    parser.add_argument("--minutes", type=positive_float, default=math.inf, help="stop after this")
    parser.add_argument(
        "--multi-agent-share",
        "--race-share",
        dest="multi_agent_share",
        type=share,
        default=0.1,
        help="the share of the steps of the families of many agents (the race; 0: none)",
    )
    parser.add_argument(
        "--scene-share", type=share, default=0.1, help="the scenes' share of the steps (0: none)"
    )
    parser.add_argument("--out", type=Path, default=Path("runs/fuzz"), help="report folder")


def run(args: argparse.Namespace) -> int:
    from bbgym.fuzz import format_report
    from bbgym.fuzz import run as fuzz

    # Gymnasium's env checker warns about float precision and the like on every make.
    warnings.filterwarnings("ignore", module="gymnasium")
    if args.multi_agent_share + args.scene_share >= 1.0:
        raise UsageError(
            "--multi-agent-share and --scene-share must sum to under 1 (the envs' share)"
        )
    report = fuzz(
        args.steps,
        args.seed,
        args.num_envs,
        args.minutes,
        multi_agent_share=args.multi_agent_share,
        scene_share=args.scene_share,
    )
    from bbgym.cli.bench import machine_info

    # What the site's table cites: the command and the machine that ran it.
    minutes = "" if math.isinf(args.minutes) else f" --minutes {args.minutes:g}"
    report["command"] = (
        f"bbgym fuzz --steps {args.steps} --seed {args.seed} --num-envs {args.num_envs}"
        f" --multi-agent-share {args.multi_agent_share:g} --scene-share {args.scene_share:g}"
        f"{minutes}"
        f" --out {args.out}"
    )
    report["machine"] = machine_info()
    text = format_report(report)
    print(text)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "fuzz.md").write_text(text + "\n", encoding="utf-8")
    (args.out / "fuzz.json").write_text(json.dumps(report, indent=2), encoding="utf-8")
    return 1 if report["failures"] else 0
