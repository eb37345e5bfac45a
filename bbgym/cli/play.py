"""Play an env from the keyboard (gymnasium.utils.play, in a pygame window).

    bbgym play --env ENV_ID [--seed S] [--fps 20] [--zoom 1.0]

Sailing (one env step per frame, 0.25 s, so 20 fps is 5x real time):
  LEFT / RIGHT   rudder hard over while held: turn to port / to starboard (0 when released)
  UP / DOWN      sheet in / ease out, 0.05 a frame; the sheet stays where you leave it

Throwing, curving and toppling (aim first, then throw):
  UP / DOWN      elevation +/- 1 deg a frame
  LEFT / RIGHT   azimuth +/- 1 deg a frame (left: counterclockwise)
  W / S          launch speed +/- 0.2 m/s a frame (Topple: under 0.5 m/s throwing waits)
  A / D          side spin +/- 2 rad/s a frame (A: curves the ball to the left)
  E / Q          back spin +/- 2 rad/s a frame (Q below 0: top spin)
  SPACE          throw (once per press); the flight is played back, then where it landed

ESC or closing the window quits; a finished episode starts the next one. Needs pygame (the
``render`` extra); each env family's spec names its key mapping (:mod:`bbgym.keyboard`).
"""

from __future__ import annotations

import argparse

from bbgym._extras import extra_needs
from bbgym.cli import UsageError, env_id, positive_float, positive_int, require_all


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--env", required=True, type=env_id, help="a bbgym env id")
    parser.add_argument("--seed", type=int, default=None, help="seed of the first episode")
    parser.add_argument(
        "--fps", type=positive_int, default=20, help="frames (sail: env steps) a second"
    )
    parser.add_argument("--zoom", type=positive_float, default=1.0, help="window scale")


def needs(args: argparse.Namespace) -> list[tuple[str, str]]:
    """``(module, extra)`` the run needs: pygame (``render``)."""
    return extra_needs("render")


def run(args: argparse.Namespace) -> int:
    require_all(needs(args))
    from bbgym.keyboard import make_play_env, play_env

    try:
        env = make_play_env(args.env, args.seed)
    except ValueError as err:
        raise UsageError(str(err)) from None
    try:
        play_env(env, fps=args.fps, zoom=args.zoom)
    finally:
        env.close()
        print()
    return 0
