"""Fuzz every env through its public API (see :mod:`bbgym.fuzz`).

    bbgym fuzz [--steps 1000000] [--seed 0] [--num-envs 32] [--minutes M] [--out runs/fuzz]

Random valid constructor arguments (every physical constant over its whole accepted
interval), reset options and actions, on single and native vector envs; every
observation, reward and info float is checked, and every invalid number argument is
checked to raise the right error naming it. Writes ``fuzz.md`` and ``fuzz.json``; exits
with status 1 if anything failed, with what reproduces it.
"""

from __future__ import annotations

import argparse
import json
import math
import warnings
from pathlib import Path

from bbgym.cli import positive_float, positive_int


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--steps", type=positive_int, default=1_000_000, help="env steps in all")
    parser.add_argument("--seed", type=int, default=0, help="seed of the configurations")
    parser.add_argument("--num-envs", type=positive_int, default=32,
                        help="size of the vector envs")  # fmt: skip
    parser.add_argument("--minutes", type=positive_float, default=math.inf,
                        help="stop after this")  # fmt: skip
    parser.add_argument("--out", type=Path, default=Path("runs/fuzz"), help="report folder")


def run(args: argparse.Namespace) -> int:
    from bbgym.fuzz import format_report
    from bbgym.fuzz import run as fuzz

    # Gymnasium's env checker warns about float precision and the like on every make.
    warnings.filterwarnings("ignore", module="gymnasium")
    report = fuzz(args.steps, args.seed, args.num_envs, args.minutes)
    text = format_report(report)
    print(text)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "fuzz.md").write_text(text + "\n", encoding="utf-8")
    (args.out / "fuzz.json").write_text(json.dumps(report, indent=2), encoding="utf-8")
    return 1 if report["failures"] else 0
