"""An animation (GIF or MP4) of an episode of any policy.

    bbgym record --env ENV_ID --policy scripted [--model path.zip]
        [--seed 0] [--out runs/record/<env>-<policy>-seed<seed>.gif] [--fps 20]
        [--frame-skip 1] [--max-steps M] [--hold 1.0]

Policies: those of ``bbgym evaluate`` (``random``, ``scripted``,
``ppo`` or ``sac`` with ``--model``, ...). The format follows the extension of ``--out``: ``.gif``
(Pillow; at most 300 frames and about 2.8 MB: a long episode keeps every second frame, or
every fourth, ..., each shown for the time of those it stands for, so it still plays in
real time) or ``.mp4`` (H.264 through the ``imageio-ffmpeg`` package, in the ``plots``
extra).

Sailing: one frame per step (0.25 s, so the default 20 fps plays 5x real time). Ball envs
(Throw, Curve, Topple), where a step is a whole throw: the flight of every throw, one frame
per 0.05 s (real time at 20 fps, from the env's ``render_flight()``), then where it landed.
``--frame-skip K`` keeps every K-th frame, but always the end of every throw and of the
episode, which are shown for ``--hold`` seconds. ``--max-steps`` cuts a long episode short.
Each frame has a caption along its bottom: the env id and policy, the step and the return so
far (during a throw's flight the return before it, so the caption does not give the result
away), and on the last frame the final return and the outcome ("success: reached the mark",
"capsized", "timed out", "missed", "success: wall down", "failed: out of throws", ...).
Runs headless (SDL's dummy video driver). Prints a one-line summary.

A family of many agents (the race, PettingZoo's: ``--env`` its PettingZoo id, the
family's extra) records a whole episode of every agent, a frame per step, by the policies
its spec names (:attr:`bbgym.spec.MultiAgentSpec.policies`). The race: ``--policy
scripted``: every boat the scripted racer; ``random``: every boat random; ``ppo --model
M.zip``: a model of ``scripts/race_selfplay.py`` sails its learning boats (as it was
trained: the ``M.json`` beside it says which, and whether it corrects the racer) against
scripted racers. The last frame's caption gives the places ("1st boat_1, 2nd boat_2, ...;
boat_0 did not finish").
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
from bbgym._extras import install_hint
from bbgym.cli import (
    UsageError,
    add_aliased,
    as_passed,
    env_id,
    positive_float,
    positive_int,
    require_all,
)
from bbgym.cli.evaluate import LEARNT, POLICIES, make_policy, model_needs
from bbgym.render.gif import MAX_GIF_FRAMES, GifWriter
from bbgym.spec import MultiAgentSpec, env_id_of, multi_agent_spec_of, spec_of

FORMATS = (".gif", ".mp4")
DEFAULT_FPS = 20.0

FrameSink = Callable[[np.ndarray, int], None]
"""``sink(frame, periods)``: show the ``(H, W, 3)`` uint8 ``frame`` for ``periods`` frames."""

SUCCESS_COLOR = (110, 230, 120)
FAILURE_COLOR = (255, 120, 104)
NEUTRAL_COLOR = (245, 245, 245)


def policy_label(policy: Any) -> str:
    """A policy's name for a caption: its ``name`` attribute, else its class's name."""
    name = getattr(policy, "name", None)
    if isinstance(name, str) and name:
        return name
    if callable(policy) and getattr(policy, "__name__", "") not in ("", "<lambda>"):
        return str(policy.__name__)
    kind = type(policy).__name__
    return "policy" if kind == "function" else kind


class FrameList:
    """A frame sink that keeps the frames in memory (``frames``, with the ``periods`` each
    is shown for): for a notebook, or a test."""

    def __init__(self) -> None:
        self.frames: list[np.ndarray] = []
        self.periods: list[int] = []

    def __call__(self, frame: np.ndarray, periods: int = 1) -> None:
        self.frames.append(frame)
        self.periods.append(periods)


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
                str(self.path),
                (width, height),
                fps=self.fps,
                quality=7,
                ffmpeg_log_level="error",
            )
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
            "writing .mp4 needs the imageio-ffmpeg package (the 'plots' extra): "
            f"{install_hint('plots')}, or write a .gif"
        )
    return suffix


def open_writer(path: Path, fps: float, max_frames: int = MAX_GIF_FRAMES) -> GifWriter | Mp4Writer:
    """A frame sink writing ``path`` in the format its extension names: an MP4 of every
    frame, or a GIF (:class:`bbgym.render.gif.GifWriter`) of at most ``max_frames`` frames
    and about 2.8 MB, in real time still (a long episode keeps every second frame, ...)."""
    if check_format(path) == ".mp4":
        return Mp4Writer(path, fps)
    return GifWriter(path, fps, max_frames=max_frames)


def file_frames(writer: GifWriter | Mp4Writer, kept: int) -> int:
    """How many frames the file ``writer`` wrote holds, ``kept`` frames having been passed
    to it: a GIF may hold fewer (every second one, ..., of a long episode)."""
    return len(writer.images) if isinstance(writer, GifWriter) else kept


def frames_text(stats: dict[str, Any]) -> str:
    """The frames of a recording, for its summary line: ``"31 frames"``, or
    ``"1201 frames (300 in the GIF)"``."""
    kept, held = stats["frames"], stats.get("file_frames", stats["frames"])
    return f"{kept} frames" + (f" ({held} in the GIF)" if held < kept else "")


class _CaptionedFrames:
    """An episode's frames on their way to a sink: every ``frame_skip``-th frame and every key
    frame (the end of a throw: shown ``hold_periods`` frames long) is passed on, with a
    caption over its bottom strip where ``title`` is set (``left`` on its left, what
    :meth:`add` gives on its right). Each frame waits for the next, since only then is it
    known to be the episode's last, which :meth:`finish` always passes on, held, with the
    outcome's caption."""

    def __init__(
        self, sink: FrameSink, left: str, *, title: bool, frame_skip: int, hold_periods: int
    ) -> None:
        self.sink, self.left, self.title = sink, left, title
        self.frame_skip, self.hold_periods = frame_skip, hold_periods
        self.index = 0
        self.kept = 0
        """The frames passed on to the sink so far."""
        # (frame or None where the sink skips it, its caption's right side, kept?,
        # periods): the frame that waits.
        self._waiting: tuple[np.ndarray | None, str, bool, int] | None = None
        self._captioner: Any = None

    def add(self, frame: np.ndarray | Callable[[], np.ndarray], right: str, key: bool) -> None:
        """The next frame, captioned ``right``; a ``key`` frame is kept and held.

        ``frame`` may be a function that draws it, for a frame that is not the episode's
        last: it is drawn now (the env moves on after) unless the sink says it would not
        keep it (a long episode's GIF keeps every second frame, ...), so that a frame
        nobody sees costs no drawing and no caption; the file is the same."""
        waiting = self._waiting
        if waiting is not None and waiting[2]:
            if waiting[0] is None:  # a frame the sink does not keep: only its time
                self.sink.skip(waiting[3])
            else:
                self.sink(self._captioned(waiting[0], waiting[1], NEUTRAL_COLOR), waiting[3])
            self.kept += 1
        kept = key or self.index % self.frame_skip == 0
        if callable(frame):
            keeps = getattr(self.sink, "keeps", None)
            wanted = kept and (keeps is None or keeps(key and self.hold_periods > 1))
            frame = frame() if wanted else None
        self._waiting = (frame, right, kept, self.hold_periods if key else 1)
        self.index += 1

    def finish(self, right: str, color: tuple[int, int, int]) -> None:
        """Pass on the last frame, held, its caption's right side ``right`` in ``color``."""
        assert self._waiting is not None, "no frame was added"
        self.sink(self._captioned(self._waiting[0], right, color), self.hold_periods)
        self.kept += 1

    def _captioned(self, frame: np.ndarray, right: str, color: tuple[int, int, int]) -> np.ndarray:
        if not self.title:
            return frame
        if self._captioner is None:  # pygame's fonts, only once a caption is drawn
            from bbgym.render.base import Captioner

            self._captioner = Captioner()
        return self._captioner(frame, self.left, right, right_color=color)


def _progress_caption(step: int, so_far: float) -> str:
    return f"step {step} \N{MIDDLE DOT} return {so_far:+.2f}"


def record_episode(
    env: gym.Env,
    policy: Any,
    seed: int,
    sink: FrameSink,
    frame_skip: int = 1,
    max_steps: int | None = None,
    hold_periods: int = 1,
    *,
    title: bool = True,
    policy_name: str | None = None,
) -> dict[str, Any]:
    """Run one episode of ``policy`` on ``env`` (``render_mode="rgb_array"``) from
    ``reset(seed=seed)`` and feed its frames to ``sink``; return its statistics (with the
    ``outcome`` of its family's :meth:`~bbgym.spec.EnvSpec.episode_outcome`).

    Frames: the start, then per step the in-flight frames of a ball env
    (``env.unwrapped.render_flight()``) and ``env.render()``. Every ``frame_skip``-th frame
    is kept, and always the end of each throw and of the episode, shown ``hold_periods``
    frames long. With ``title`` each frame gets a caption over its bottom strip (the frame
    keeps its size): env id and ``policy_name`` (default :func:`policy_label`), the step
    and the return so far (in a flight, the return before that throw), and on the last
    frame the final return and the outcome.
    """
    flights = hasattr(env.unwrapped, "render_flight")
    env_name = env.spec.id if env.spec is not None else type(env.unwrapped).__name__
    left = f"{env_name} \N{MIDDLE DOT} {policy_name or policy_label(policy)}"
    frames = _CaptionedFrames(
        sink, left, title=title, frame_skip=frame_skip, hold_periods=hold_periods
    )
    obs, info = env.reset(seed=seed)
    if hasattr(policy, "reset"):
        policy.reset()
    frames.add(env.render(), _progress_caption(0, 0.0), key=False)
    total, steps, terminated, truncated = 0.0, 0, False, False
    while not (terminated or truncated):
        if max_steps is not None and steps >= max_steps:
            break
        before = total
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        total += float(reward)
        steps += 1
        if flights:
            for frame in env.unwrapped.render_flight():
                frames.add(frame, _progress_caption(steps, before), key=False)
        last = terminated or truncated or (max_steps is not None and steps >= max_steps)
        frames.add(
            env.render() if last else env.render, _progress_caption(steps, total), key=flights
        )
    outcome, success = spec_of(env_id_of(env)).episode_outcome(env, info, terminated, truncated)
    color = {True: SUCCESS_COLOR, False: FAILURE_COLOR}.get(success, NEUTRAL_COLOR)
    frames.finish(f"final return {total:+.2f} \N{MIDDLE DOT} {outcome}", color)
    return {
        "steps": steps,
        "frames": frames.kept,
        "return": total,
        "success": bool(info.get("is_success", False)),
        "terminated": bool(terminated),
        "truncated": bool(truncated),
        "capped": not (terminated or truncated),
        "outcome": outcome,
    }


def animation_needs(path: Path) -> list[tuple[str, str]]:
    """``(module, extra)`` drawing and writing the animation ``path`` needs: pygame
    (``render``) and Pillow for ``.gif`` or imageio-ffmpeg for ``.mp4`` (``plots``)."""
    writer = "imageio_ffmpeg" if path.suffix.lower() == ".mp4" else "PIL"
    return [("pygame", "render"), (writer, "plots")]


def default_out(args: argparse.Namespace) -> Path:
    """``--out``, or its default ``runs/record/<env>-<policy>-seed<seed>.gif``."""
    return args.out or Path("runs/record") / f"{args.env}-{args.policy}-seed{args.seed}.gif"


def needs(args: argparse.Namespace) -> list[tuple[str, str]]:
    """``(module, extra)`` the run needs: :func:`animation_needs`, and for a saved model's
    policy the extra that loads it (:func:`~bbgym.cli.evaluate.model_needs`); a family of
    many agents needs PettingZoo (its extra)."""
    agents = multi_agent_spec_of(args.env)
    multi = [("pettingzoo", agents.extra)] if agents is not None else []
    return [*multi, *animation_needs(default_out(args)), *model_needs([args.policy], args.model)]


def recordable_id(text: str) -> str:
    """An argparse ``type``: a bbgym env id, or the PettingZoo id of a family of many
    agents (:class:`~bbgym.spec.MultiAgentSpec`)."""
    agents = multi_agent_spec_of(text)
    return text if agents is not None and text == agents.env_id else env_id(text)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = "Formats: .gif (Pillow), .mp4 (imageio-ffmpeg). Runs headless."
    parser.add_argument(
        "--env",
        required=True,
        type=recordable_id,
        help="a bbgym env id, or the PettingZoo id of a family of many agents (the race)",
    )
    add_aliased(
        parser,
        "--policy",
        "--policies",
        required=True,
        choices=POLICIES,
        help="the policy to record",
    )
    parser.add_argument(
        "--model",
        type=Path,
        default=None,
        help="saved PPO or SAC model (.zip), or a PPO policy .pt of --engine torchrl",
    )
    parser.add_argument("--seed", type=int, default=0, help="episode seed")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help="output file, .gif or .mp4 (default runs/record/<env>-<policy>-seed<seed>.gif)",
    )
    parser.add_argument(
        "--fps",
        type=positive_float,
        default=DEFAULT_FPS,
        help="playback rate (20: real time for the ball envs, 5x for sailing)",
    )
    parser.add_argument("--frame-skip", type=positive_int, default=1, help="keep every K-th frame")
    parser.add_argument(
        "--max-steps", type=positive_int, default=None, help="cut the episode short"
    )
    parser.add_argument(
        "--hold",
        type=float,
        default=1.0,
        help="seconds the end of each throw and of the episode is shown",
    )


def run(args: argparse.Namespace) -> int:
    if args.hold < 0:
        raise UsageError("--hold must be >= 0")
    if args.policy in LEARNT and args.model is None:
        raise UsageError(
            f"{as_passed(args, 'policy', '--policy')} {args.policy} needs --model (a saved "
            "stable-baselines3 model .zip, or a "
            "PPO policy .pt of bbgym train --engine torchrl)"
        )
    args.out = default_out(args)
    try:
        check_format(args.out)
    except ValueError as err:
        raise UsageError(str(err)) from None
    # a whole episode takes seconds to a minute to draw and write: say so first
    starting = f"recording {args.env} {args.policy} seed {args.seed} into {args.out} ..."
    print(starting, file=sys.stderr, flush=True)
    agents = multi_agent_spec_of(args.env)
    if agents is not None and args.policy not in agents.policies:
        raise UsageError(
            f"{as_passed(args, 'policy', '--policy')} {args.policy}: {agents.env_id} records "
            f"{', '.join(agents.policies)}"
        )
    stats = record_to_file(args.env, args.policy, args.out, **recording_options(args))
    result = stats["outcome"]  # an episode of every agent: its outcome says it all
    if "return" in stats:
        result = f"return {stats['return']:.2f}, success {stats['success']} ({result})"
    print(f"{recorded_text(args, stats)}, {result} -> {args.out}")
    return 0


def recording_options(args: argparse.Namespace) -> dict[str, Any]:
    """The keyword arguments of :func:`record_to_file` that ``bbgym record``'s options
    set."""
    return {
        "model": args.model,
        "seed": args.seed,
        "fps": args.fps,
        "frame_skip": args.frame_skip,
        "max_steps": args.max_steps,
        "hold": args.hold,
    }


def recorded_text(args: argparse.Namespace, stats: dict[str, Any]) -> str:
    """The head of ``bbgym record``'s last line, for any env: what was recorded,
    its steps (and whether ``--max-steps`` cut it) and frames."""
    capped = f" (cut at --max-steps {args.max_steps})" if stats["capped"] else ""
    return (
        f"{args.env} {args.policy} seed {args.seed}: {stats['steps']} steps{capped}, "
        f"{frames_text(stats)} at {args.fps:g} fps"
    )


def record_to_file(
    env_id: str,
    policy_name: str,
    out: Path,
    *,
    model: Path | None = None,
    seed: int = 0,
    fps: float = DEFAULT_FPS,
    frame_skip: int = 1,
    max_steps: int | None = None,
    hold: float = 1.0,
    title: bool = True,
) -> dict[str, Any]:
    """Record one episode of ``policy_name`` on ``env_id`` into ``out`` (.gif or .mp4),
    captioned unless ``title`` is False; return the episode's statistics (see
    :func:`record_episode`). ``env_id`` may be the PettingZoo id of a family of many agents
    (:class:`~bbgym.spec.MultiAgentSpec`: the race): then every agent is recorded, by its
    spec's recorder, and the statistics are the spec's (``steps``, ``outcome``, ...)."""
    check_format(out)
    agents = multi_agent_spec_of(env_id)
    if agents is None or env_id != agents.env_id:
        spec_of(env_id)  # a bbgym id, else ValueError listing them (the captions need it)
    require_all(animation_needs(out))
    hold_periods = max(1, round(hold * fps))
    if agents is not None and env_id == agents.env_id:
        every_agent = _agents_episode(agents, policy_name, model, seed, max_steps)
        out.parent.mkdir(parents=True, exist_ok=True)
        writer = open_writer(out, fps)
        frames = _CaptionedFrames(
            writer,
            f"{env_id} \N{MIDDLE DOT} {policy_name}",
            title=title,
            frame_skip=frame_skip,
            hold_periods=hold_periods,
        )
        while True:
            try:
                frame, caption = next(every_agent)
            except StopIteration as end:
                stats = dict(end.value)
                break
            frames.add(frame, caption, key=False)
        frames.finish(stats["outcome"], NEUTRAL_COLOR)
        writer.close()
        return {**stats, "frames": frames.kept, "file_frames": file_frames(writer, frames.kept)}
    env = gym.make(env_id, render_mode="rgb_array")
    try:
        try:
            policy = make_policy(policy_name, env, model, seed)
        except ValueError as err:
            raise UsageError(str(err)) from None
        out.parent.mkdir(parents=True, exist_ok=True)
        writer = open_writer(out, fps)
        stats = record_episode(
            env,
            policy,
            seed,
            writer,
            frame_skip=frame_skip,
            max_steps=max_steps,
            hold_periods=hold_periods,
            title=title,
            policy_name=policy_name,
        )
        writer.close()
        stats["file_frames"] = file_frames(writer, stats["frames"])
    finally:
        env.close()
    return stats


def _agents_episode(
    spec: MultiAgentSpec, policy_name: str, model: Path | None, seed: int, max_steps: int | None
) -> Any:
    """The spec's recorder's frames of one episode of every agent (a learnt policy loaded
    by :func:`~bbgym.cli.evaluate.make_policy`); a policy it does not record, or a model
    that does not fit, is a :class:`UsageError`."""
    if spec.record is None or policy_name not in spec.policies:
        raise UsageError(f"{spec.env_id} records {', '.join(spec.policies) or 'nothing'}")

    def load_policy(env: Any, saved: Path) -> Callable[[Any], Any]:
        return make_policy(policy_name, env, saved, seed)

    try:
        return spec.load(spec.record)(
            policy_name, seed=seed, max_steps=max_steps, model=model, load_policy=load_policy
        )
    except ValueError as err:
        raise UsageError(str(err)) from None
