"""An animation (GIF or MP4) of an episode of any policy.

    python scripts/record.py --env BeachballSail-v0 --policy scripted [--model path.zip]
        [--seed 0] [--out runs/record/<env>-<policy>-seed<seed>.gif] [--fps 20]
        [--frame-skip 1] [--max-steps M] [--hold 1.0]

Policies: those of ``scripts/evaluate.py``'s ``make_policy`` (``random``, ``scripted``,
``ppo`` with ``--model``, ...). The format follows the extension of ``--out``: ``.gif``
(Pillow) or ``.mp4`` (H.264 through the ``imageio-ffmpeg`` package, in the ``plots``
extra).

Sailing: one frame per step (0.25 s, so the default 20 fps plays 5x real time). Ball envs
(Throw, Curve, Topple), where a step is a whole throw: the flight of every throw, one frame
per 0.05 s (real time at 20 fps, from the env's ``render_flight()``), then where it landed.
``--frame-skip K`` keeps every K-th frame, but always the end of every throw and of the
episode, which are shown for ``--hold`` seconds. ``--max-steps`` cuts a long episode short.
Runs headless (SDL's dummy video driver). Prints a one-line summary.
"""

from __future__ import annotations

import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import argparse
import importlib.util
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import bbgym  # noqa: F401  (registers the envs)

FORMATS = (".gif", ".mp4")
DEFAULT_FPS = 20.0


# scripts/ is not a package: its sibling evaluate.py is imported from its folder, as
# baseline.py does.
sys.path.insert(0, str(Path(__file__).resolve().parent))
import evaluate  # noqa: E402  (scripts/evaluate.py)

make_policy = evaluate.make_policy

FrameSink = Callable[[np.ndarray, int], None]
"""``sink(frame, periods)``: show the ``(H, W, 3)`` uint8 ``frame`` for ``periods`` frames."""


class GifWriter:
    """Collects frames (as palette images, a quarter of the memory) and writes a looping GIF.

    Pillow merges identical consecutive frames into one (adding up their durations), so
    the file may hold fewer frames than were added; the timing is kept.
    """

    def __init__(self, path: Path, fps: float) -> None:
        from PIL import Image

        self._image = Image
        self.path, self.fps = path, fps
        self.images: list[Any] = []
        self.durations: list[int] = []

    def __call__(self, frame: np.ndarray, periods: int = 1) -> None:
        image = self._image.fromarray(np.asarray(frame, dtype=np.uint8))
        self.images.append(image.convert("P", palette=self._image.Palette.ADAPTIVE))
        self.durations.append(int(round(periods * 1000.0 / self.fps)))

    def close(self) -> None:
        if not self.images:
            raise ValueError("no frames to write")
        self.images[0].save(
            self.path,
            save_all=True,
            append_images=self.images[1:],
            duration=self.durations if len(self.durations) > 1 else self.durations[0],
            loop=0,
            optimize=False,
        )


class Mp4Writer:
    """Streams frames to an H.264 MP4 through imageio-ffmpeg (a held frame is repeated)."""

    def __init__(self, path: Path, fps: float) -> None:
        import imageio_ffmpeg

        self._write_frames = imageio_ffmpeg.write_frames
        self.path, self.fps = path, fps
        self._gen: Any = None

    def __call__(self, frame: np.ndarray, periods: int = 1) -> None:
        frame = np.ascontiguousarray(frame, dtype=np.uint8)
        if self._gen is None:
            height, width = frame.shape[:2]
            self._gen = self._write_frames(
                str(self.path), (width, height), fps=self.fps, quality=7,
                ffmpeg_log_level="error",
            )  # fmt: skip
            self._gen.send(None)
        for _ in range(max(1, periods)):
            self._gen.send(frame)

    def close(self) -> None:
        if self._gen is None:
            raise ValueError("no frames to write")
        self._gen.close()
        self._gen = None


def check_format(path: Path) -> str:
    """The animation format for ``path`` (``.gif`` or ``.mp4``), or ``ValueError`` saying why
    it cannot be written."""
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(
            f"cannot tell the animation format from {str(path)!r}: the file name must end "
            f"in {' or '.join(FORMATS)}"
        )
    if suffix == ".mp4" and importlib.util.find_spec("imageio_ffmpeg") is None:
        raise ValueError(
            "writing .mp4 needs the imageio-ffmpeg package: pip install imageio-ffmpeg "
            '(or pip install -e ".[plots]"), or write a .gif'
        )
    return suffix


def open_writer(path: Path, fps: float) -> GifWriter | Mp4Writer:
    """A frame sink writing ``path`` in the format its extension names."""
    return Mp4Writer(path, fps) if check_format(path) == ".mp4" else GifWriter(path, fps)


def record_episode(
    env: gym.Env,
    policy: Any,
    seed: int,
    sink: FrameSink,
    frame_skip: int = 1,
    max_steps: int | None = None,
    hold_periods: int = 1,
) -> dict[str, Any]:
    """Run one episode of ``policy`` on ``env`` (``render_mode="rgb_array"``) from
    ``reset(seed=seed)`` and feed its frames to ``sink``; return its statistics.

    Frames: the start, then per step the in-flight frames of a ball env
    (``env.unwrapped.render_flight()``) and ``env.render()``. Every ``frame_skip``-th frame
    is kept, and always the end of each throw and of the episode, shown ``hold_periods``
    frames long.
    """
    flights = hasattr(env.unwrapped, "render_flight")
    obs, info = env.reset(seed=seed)
    if hasattr(policy, "reset"):
        policy.reset()
    index, kept = 0, 0
    last: tuple[np.ndarray, bool, int] | None = None  # (frame, kept?, periods), sent later

    def emit(frame: np.ndarray, key: bool) -> None:
        # Each frame waits for the next: the last one of the episode is always kept.
        nonlocal index, kept, last
        if last is not None and last[1]:
            sink(last[0], last[2])
            kept += 1
        last = (frame, key or index % frame_skip == 0, hold_periods if key else 1)
        index += 1

    emit(env.render(), key=False)
    total, steps, terminated, truncated = 0.0, 0, False, False
    while not (terminated or truncated):
        if max_steps is not None and steps >= max_steps:
            break
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        total += float(reward)
        steps += 1
        if flights:
            for frame in env.unwrapped.render_flight():
                emit(frame, key=False)
        emit(env.render(), key=flights)
    assert last is not None
    sink(last[0], hold_periods)  # the episode's last frame, always kept and held
    kept += 1
    return {
        "steps": steps,
        "frames": kept,
        "return": total,
        "success": bool(info.get("is_success", False)),
        "terminated": bool(terminated),
        "truncated": bool(truncated),
        "capped": not (terminated or truncated),
    }


def main(argv: list[str] | None = None) -> int:
    known = getattr(evaluate, "POLICIES", ("random", "scripted", "ppo"))
    parser = argparse.ArgumentParser(
        description=__doc__.splitlines()[0],
        epilog="Formats: .gif (Pillow), .mp4 (imageio-ffmpeg). Runs headless.",
    )
    parser.add_argument("--env", required=True, help="env id, e.g. BeachballSail-v0")
    parser.add_argument(
        "--policy", required=True, help=f"one of scripts/evaluate.py's: {', '.join(known)}"
    )
    parser.add_argument("--model", type=Path, default=None, help="saved PPO model (.zip)")
    parser.add_argument("--seed", type=int, default=0, help="episode seed")
    parser.add_argument(
        "--out", type=Path, default=None,
        help="output file, .gif or .mp4 (default runs/record/<env>-<policy>-seed<seed>.gif)",
    )  # fmt: skip
    parser.add_argument(
        "--fps", type=float, default=DEFAULT_FPS,
        help="playback rate (default 20: real time for the ball envs, 5x for sailing)",
    )  # fmt: skip
    parser.add_argument("--frame-skip", type=int, default=1, help="keep every K-th frame")
    parser.add_argument("--max-steps", type=int, default=None, help="cut the episode short")
    parser.add_argument(
        "--hold", type=float, default=1.0,
        help="seconds the end of each throw and of the episode is shown (default 1)",
    )  # fmt: skip
    args = parser.parse_args(argv)
    if args.fps <= 0:
        parser.error("--fps must be > 0")
    if args.frame_skip < 1:
        parser.error("--frame-skip must be >= 1")
    if args.max_steps is not None and args.max_steps < 1:
        parser.error("--max-steps must be >= 1")
    if args.hold < 0:
        parser.error("--hold must be >= 0")
    if args.policy == "ppo" and args.model is None:
        parser.error("--policy ppo needs --model (a saved stable-baselines3 model .zip)")
    if args.out is None:
        args.out = Path("runs/record") / f"{args.env}-{args.policy}-seed{args.seed}.gif"
    try:
        check_format(args.out)
    except ValueError as err:
        parser.error(str(err))
    gym.spec(args.env)  # unknown ids fail here, with Gymnasium's message

    env = gym.make(args.env, render_mode="rgb_array")
    try:
        try:
            policy = make_policy(args.policy, env, args.model, args.seed)
        except ValueError as err:
            parser.error(str(err))
        args.out.parent.mkdir(parents=True, exist_ok=True)
        writer = open_writer(args.out, args.fps)
        stats = record_episode(
            env, policy, args.seed, writer, frame_skip=args.frame_skip,
            max_steps=args.max_steps, hold_periods=max(1, round(args.hold * args.fps)),
        )  # fmt: skip
        writer.close()
    finally:
        env.close()
    capped = f" (cut at --max-steps {args.max_steps})" if stats["capped"] else ""
    print(
        f"{args.env} {args.policy} seed {args.seed}: {stats['steps']} steps{capped}, "
        f"{stats['frames']} frames at {args.fps:g} fps, return {stats['return']:.2f}, "
        f"success {stats['success']} -> {args.out}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
