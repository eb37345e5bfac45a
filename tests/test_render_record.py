"""The caption of recorded episodes (``bbgym record``): what it says on which frame."""

import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

import gymnasium as gym
import numpy as np
import pytest

pytest.importorskip("pygame")

import bbgym  # noqa: E402, F401
from bbgym.cli import record  # noqa: E402
from bbgym.render.annotations import CAPTION_BAND_PX, draw_caption, fit_text  # noqa: E402

DOT = "\N{MIDDLE DOT}"


ListSink = record.FrameList


def test_caption_covers_only_the_bottom_band_and_keeps_the_size() -> None:
    rng = np.random.default_rng(0)
    frame = rng.integers(0, 256, (120, 320, 3), dtype=np.uint8)
    before = frame.copy()
    out = draw_caption(frame, "BeachballSail-v0 \N{MIDDLE DOT} ppo", "return +1.00")
    assert out.shape == frame.shape and out.dtype == np.uint8
    np.testing.assert_array_equal(out[:-CAPTION_BAND_PX], frame[:-CAPTION_BAND_PX])
    assert np.mean(np.any(out[-CAPTION_BAND_PX:] != frame[-CAPTION_BAND_PX:], axis=-1)) > 0.9
    np.testing.assert_array_equal(frame, before)  # a copy: the frame itself is untouched
    # Different text, different band.
    other = draw_caption(frame, "BeachballSail-v0 \N{MIDDLE DOT} ppo", "return +2.00")
    assert np.any(other != out)


def test_fit_text_cuts_long_text() -> None:
    def measure(text: str) -> float:
        return 10.0 * len(text)

    assert fit_text("short", 100, measure) == "short"
    cut = fit_text("a rather long caption", 100, measure)
    assert cut.endswith("...") and measure(cut) <= 100
    assert fit_text("anything", 5, measure) == ""


@pytest.mark.parametrize(
    ("env_id", "info", "terminated", "truncated", "outcome", "success"),
    [
        (
            "BeachballSail-v0",
            {"is_success": True, "capsized": False},
            True,
            False,
            "success: reached the mark",
            True,
        ),
        (
            "BeachballSail-v0",
            {"is_success": False, "capsized": True},
            True,
            False,
            "capsized",
            False,
        ),
        (
            "BeachballSail-v0",
            {"is_success": False, "capsized": False},
            False,
            True,
            "timed out",
            False,
        ),
        (
            "BeachballThrow-v0",
            {"is_success": True, "throws_left": 1},
            True,
            False,
            "success: hit",
            True,
        ),
        (
            "BeachballThrow-v0",
            {"is_success": False, "throws_left": 0, "hit_screen": True},
            True,
            False,
            "missed screen",
            False,
        ),
        (
            "BeachballTopple-v0",
            {"is_success": True, "wall_state": "fallen_away"},
            True,
            False,
            "success: wall down",
            True,
        ),
        (
            "BeachballTopple-v0",
            {"is_success": True, "wall_state": "loose"},
            True,
            False,
            "success: wall down (broke loose)",
            True,
        ),
        (
            "BeachballTopple-v0",
            {"is_success": False, "wall_state": "fallen_toward"},
            True,
            False,
            "failed: wall fell toward you",
            False,
        ),
        (
            "BeachballTopple-v0",
            {"is_success": False, "wall_state": "standing", "throws_left": 0},
            True,
            False,
            "failed: out of throws, wall standing",
            False,
        ),
        (
            "BeachballSail-v0",
            {"is_success": False, "capsized": False},
            False,
            False,
            "cut short (--max-steps)",
            None,
        ),
    ],
)
def test_episode_outcome(env_id, info, terminated, truncated, outcome, success) -> None:
    """Each family's spec says how an episode ended (the caption of a recording's end)."""
    from bbgym.spec import spec_of

    assert spec_of(env_id).episode_outcome(None, info, terminated, truncated) == (
        outcome,
        success,
    )


def run_episode(env_id: str, title: bool, max_steps: int) -> tuple[ListSink, dict]:
    env = gym.make(env_id, render_mode="rgb_array")
    try:
        policy = record.make_policy("random", env, None, 5)
        sink = ListSink()
        stats = record.record_episode(
            env,
            policy,
            5,
            sink,
            max_steps=max_steps,
            hold_periods=3,
            title=title,
            policy_name="random",
        )
    finally:
        env.close()
    return sink, stats


def test_throw_caption_gives_nothing_away_during_a_flight() -> None:
    raw, stats = run_episode("BeachballThrow-v0", title=False, max_steps=1)
    captioned, again = run_episode("BeachballThrow-v0", title=True, max_steps=1)
    assert stats == again and len(raw.frames) == len(captioned.frames) > 3
    left = f"BeachballThrow-v0 {DOT} random"
    n = len(raw.frames)
    # The start, the flight (the return before the throw), then the landing: the last frame,
    # with the final return and the outcome.
    expected = [f"step 0 {DOT} return +0.00"] + [f"step 1 {DOT} return +0.00"] * (n - 2)
    for frame, plain, right in zip(captioned.frames[:-1], raw.frames[:-1], expected, strict=True):
        np.testing.assert_array_equal(frame, draw_caption(plain, left, right))
    final = f"final return {stats['return']:+.2f} {DOT} {stats['outcome']}"
    assert stats["outcome"] == "cut short (--max-steps)"
    np.testing.assert_array_equal(captioned.frames[-1], draw_caption(raw.frames[-1], left, final))
    assert stats["return"] != 0.0  # so a flight frame's "+0.00" is not the throw's result


def test_sail_caption_shows_the_return_so_far_and_the_outcome() -> None:
    raw, stats = run_episode("BeachballSail-v0", title=False, max_steps=4)
    captioned, _ = run_episode("BeachballSail-v0", title=True, max_steps=4)
    assert len(captioned.frames) == 5 and captioned.periods == [1, 1, 1, 1, 3]
    for plain, frame in zip(raw.frames, captioned.frames, strict=True):
        assert frame.shape == plain.shape
        np.testing.assert_array_equal(frame[:-CAPTION_BAND_PX], plain[:-CAPTION_BAND_PX])
        assert np.any(frame[-CAPTION_BAND_PX:] != plain[-CAPTION_BAND_PX:])
    left = f"BeachballSail-v0 {DOT} random"
    final = f"final return {stats['return']:+.2f} {DOT} cut short (--max-steps)"
    np.testing.assert_array_equal(captioned.frames[-1], draw_caption(raw.frames[-1], left, final))


def test_policy_label() -> None:
    class Named:
        name = "autopilot"

    class Agent:
        def __call__(self, obs):  # noqa: ANN001, ANN204
            return obs

    assert record.policy_label(Named()) == "autopilot"
    assert record.policy_label(Agent()) == "Agent"
    assert record.policy_label(lambda obs: obs) == "policy"


def test_captioner_outlives_pygame_quit() -> None:
    # gymnasium's play() ends with pygame.quit(); a font kept past it would crash pygame.
    import pygame

    from bbgym.render.annotations import Captioner

    frame = np.full((60, 200, 3), 90, dtype=np.uint8)
    captioner = Captioner()
    first = captioner(frame, "left", "right")
    pygame.quit()
    np.testing.assert_array_equal(captioner(frame, "left", "right"), first)
    np.testing.assert_array_equal(draw_caption(frame, "left", "right"), first)
