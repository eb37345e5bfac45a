"""One scripted episode of an env, as an animation and a table of its statistics.

    bbgym demo [--env ENV_ID] [--seed S] [--out runs/demo] [--format gif]

The env's family declares the demo (:attr:`bbgym.spec.EnvSpec.demo`; by default the first
family that has one: sailing's helmsman beating to an upwind mark). Prints its statistics,
writes ``<out>/episode.gif`` (every ``--frame-skip``-th frame, at most ``--max-frames`` of
them, 300: a longer episode keeps every second one, ...) and ``<out>/episode.json``.
Runs headless (SDL's dummy video driver).
"""

from __future__ import annotations

import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import argparse
import json
from pathlib import Path

import bbgym  # noqa: F401  (registers the ids)
from bbgym.cli import UsageError, env_id, positive_float, positive_int, require_all
from bbgym.render.gif import MAX_GIF_FRAMES
from bbgym.spec import spec_of, specs


def add_arguments(parser: argparse.ArgumentParser) -> None:
    with_demo = [s.versions[0].env_id for s in specs() if s.demo is not None]
    parser.add_argument(
        "--env",
        type=env_id,
        default=with_demo[0] if with_demo else None,
        help="an env id whose family has a demo",
    )
    parser.add_argument("--seed", type=int, default=None, help="episode seed (the family's)")
    parser.add_argument("--out", type=Path, default=Path("runs/demo"), help="output folder")
    parser.add_argument("--format", choices=["gif", "mp4"], default="gif", help="animation format")
    parser.add_argument("--frame-skip", type=positive_int, default=2, help="keep every n-th frame")
    parser.add_argument("--fps", type=positive_float, default=10.0, help="animation playback rate")
    parser.add_argument(
        "--max-frames",
        type=positive_int,
        default=MAX_GIF_FRAMES,
        help="frames a GIF keeps at most: a longer episode keeps every second frame (every "
        "fourth, ...), still in real time (default: %(default)s)",
    )


def needs(args: argparse.Namespace) -> list[tuple[str, str]]:
    """``(module, extra)`` the run needs: drawing and writing the animation."""
    from bbgym.cli.record import animation_needs

    return animation_needs(Path(f"episode.{args.format}"))


def run(args: argparse.Namespace) -> int:
    from bbgym.cli.record import check_format, file_frames, open_writer

    require_all(needs(args))
    spec = spec_of(args.env) if args.env else None
    if spec is None or spec.demo is None:
        raise UsageError(f"--env {args.env}: its family has no demo")
    animation = args.out / f"episode.{args.format}"
    check_format(animation)
    caption, table, stats, frames = spec.demo(args.seed, args.frame_skip)
    print(caption)
    print(table)

    args.out.mkdir(parents=True, exist_ok=True)
    writer = open_writer(animation, args.fps, max_frames=args.max_frames)
    for frame in frames:
        writer(frame)
    writer.close()
    stats_path = args.out / "episode.json"
    stats_path.write_text(json.dumps(stats, indent=2) + "\n")
    kept = file_frames(writer, len(frames))
    print(f"wrote {animation} ({kept} of {len(frames)} frames, in real time at {args.fps:g} fps)")
    print(f"wrote {stats_path}")
    return 0
