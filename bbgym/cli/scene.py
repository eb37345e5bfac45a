"""Run a scene of the course text: print what it measures, and draw it.

    bbgym scene --list
    bbgym scene NAME [--steps N] [--param KEY=VALUE] [--backend numpy]
        [--out FILE.gif] [--fps 30]

A scene (bbgym.scenes) is one of the course text's demos on the envs' physics: its claim
(what the text says the demo shows, as the tests check it) and a table of its measures at
the start and the end of the run are printed; with --out an animation is written (.gif
through Pillow, .mp4 through imageio-ffmpeg; pygame draws it), played in real time at
--fps frames a second (a run longer than --max-frames frames, 300, is drawn every n-th
step instead, still in real time: a GIF of a few MB at most). --param sets one of the
scene's parameters (repeat it; --list shows each scene's parameters and defaults).
"""

from __future__ import annotations

import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import argparse
import math
from dataclasses import fields
from pathlib import Path
from typing import Any

from bbgym.cli import UsageError, nonnegative_int, positive_float, positive_int
from bbgym.render.gif import MAX_GIF_FRAMES


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("name", nargs="?", metavar="NAME", help="the scene (see --list)")
    parser.add_argument("--list", action="store_true", help="list the scenes and their parameters")
    parser.add_argument(
        "--steps",
        type=nonnegative_int,
        default=None,
        help="time steps to run (default: the scene's own)",
    )
    parser.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="a parameter of the scene (repeatable)",
    )
    parser.add_argument(
        "--backend",
        choices=["numpy", "torch"],
        default="numpy",
        help="the array namespace it runs on (torch: the torch extra)",
    )
    parser.add_argument(
        "--out", type=Path, default=None, help="write an animation, .gif or .mp4 (default: none)"
    )
    parser.add_argument("--fps", type=positive_float, default=30.0, help="animation frame rate")
    frames_help = (
        "frames an animation keeps at most: a longer run is drawn every n-th step, still "
        "in real time (default: %(default)s)"
    )
    parser.add_argument("--max-frames", type=positive_int, default=MAX_GIF_FRAMES, help=frames_help)


def needs(args: argparse.Namespace) -> list[tuple[str, str]]:
    """``(module, extra)`` the run needs: drawing and writing an animation, torch."""
    from bbgym.cli.record import animation_needs

    extra = [("torch", "torch"), ("array_api_compat", "torch")] if args.backend == "torch" else []
    return extra + (animation_needs(args.out) if args.out is not None and not args.list else [])


def parse_params(items: list[str]) -> dict[str, float]:
    """``--param KEY=VALUE`` items as numbers (an integer where written as one), or
    :class:`UsageError` naming the item."""
    values: dict[str, float] = {}
    for item in items:
        key, sep, text = item.partition("=")
        try:
            if not sep or not key:
                raise ValueError
            values[key.strip()] = int(text) if text.strip().lstrip("-").isdigit() else float(text)
        except ValueError:
            raise UsageError(f"--param takes KEY=VALUE with a number, got {item!r}") from None
    return values


def listing() -> str:
    from bbgym.scenes import SCENES

    lines = []
    for scene in SCENES.values():
        defaults = ", ".join(f"{f.name}={f.default:g}" for f in fields(scene.params))
        lines += [f"{scene.name:<20} {scene.section} {scene.title}", f"{'':<20} {defaults}"]
    return "\n".join(lines)


def measures_table(trajectory: Any, bodies: tuple[str, ...]) -> str:
    """Each measure of each body at the start and the end, with its least and greatest."""
    from bbgym.scenes.scene import summary_rows

    rows = [f"{'measure':<18} {'body':<20} {'start':>10} {'end':>10} {'min':>10} {'max':>10}"]
    for name, body, *numbers in summary_rows(trajectory, bodies):
        rows.append(f"{name:<18} {body:<20} " + " ".join(f"{v:>10.4g}" for v in numbers))
    return "\n".join(rows)


def frame_every(scene: Any, params: Any, args: argparse.Namespace) -> int:
    """Steps between an animation's frames: one frame each ``1 / --fps`` seconds, or fewer
    where the run would take more than ``--max-frames`` frames."""
    steps = args.steps
    if steps is None:
        steps = math.ceil(scene.duration_s(params) / params.dt_s - 1e-9)
    real_time = max(1, round(1.0 / (args.fps * params.dt_s)))
    return max(real_time, math.ceil(steps / max(args.max_frames - 1, 1)))


def run(args: argparse.Namespace) -> int:
    from bbgym.scenes import SCENES, simulate, unknown_scene

    if args.list:
        print(listing())
        return 0
    if args.name is None:
        raise UsageError("name a scene (bbgym scene --list lists them)")
    if args.name not in SCENES:
        raise UsageError(unknown_scene(args.name))
    scene = SCENES[args.name]
    if args.out is not None:
        from bbgym.cli.record import check_format

        try:
            check_format(args.out)
        except ValueError as err:
            raise UsageError(f"--out {args.out}: {err}") from None
    try:
        params = scene.make_params(parse_params(args.param))
    except (TypeError, ValueError) as err:
        raise UsageError(f"--param: {err}") from None
    states: list[Any] = []
    keep = None if args.out is None else frame_every(scene, params, args)
    step = iter(range(10**12))

    def collect(p: Any, state: Any) -> None:
        if keep is not None and next(step) % keep == 0:
            states.append(state)

    trajectory = simulate(scene, params, args.steps, args.backend, on_step=collect)
    steps = len(trajectory.times_s) - 1
    print(f"{scene.section} {scene.title}: {steps} steps of {params.dt_s:g} s on {args.backend}")
    print(f"claim: {scene.claim}")
    print(measures_table(trajectory, scene.names(params)))
    if args.out is not None:
        from bbgym.cli.record import open_writer
        from bbgym.scenes.view import frames

        args.out.parent.mkdir(parents=True, exist_ok=True)
        # each frame stands for ``keep`` steps, shown for their time (real time)
        fps = 1.0 / (keep * params.dt_s)
        if args.out.suffix.lower() == ".gif":
            writer, periods = open_writer(args.out, fps, max_frames=args.max_frames), 1
        else:
            writer, periods = open_writer(args.out, args.fps), max(1, round(args.fps / fps))
        for image in frames(scene, params, states, every=keep):
            writer(image, periods)
        writer.close()
        print(f"wrote {args.out} ({len(states)} frames at {fps:.3g} fps, real time)")
    return 0
