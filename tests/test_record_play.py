"""``bbgym record`` (animations of an episode), the envs' render_flight(), and ``bbgym play``
(bbgym.keyboard's wrappers, gymnasium.utils.play driven headless)."""

from __future__ import annotations

import importlib.util
import math
import os
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import bbgym  # noqa: F401

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
pygame = pytest.importorskip("pygame")
Image = pytest.importorskip("PIL.Image")

ROOT = Path(__file__).resolve().parents[1]

from bbgym import cli  # noqa: E402
from bbgym import keyboard as play  # noqa: E402
from bbgym.cli import record  # noqa: E402
from bbgym.envs import ball_keys as throw_keys  # noqa: E402
from bbgym.envs.sail import keys as sail_keys  # noqa: E402

# The simple helmsman (the autopilot takes seconds to build).
SAIL_POLICY = "simple"
HAS_MP4 = importlib.util.find_spec("imageio_ffmpeg") is not None


def render_size(env_id: str) -> tuple[int, int]:
    env = gym.make(env_id, render_mode="rgb_array")
    env.reset(seed=0)
    height, width, _ = env.render().shape
    env.close()
    return width, height


def gif_frames(path: Path) -> tuple[int, tuple[int, int], list[int]]:
    """Number of frames, size and per-frame durations (ms) of a GIF."""
    with Image.open(path) as im:
        durations = []
        for k in range(im.n_frames):
            im.seek(k)
            durations.append(im.info["duration"])
        return im.n_frames, im.size, durations


ListSink = record.FrameList


# -- render_flight ---------------------------------------------------------------------------


@pytest.mark.parametrize("env_id", ["BeachballThrow-v0", "BeachballCurve-v0"])
def test_render_flight_throw(env_id):
    env = gym.make(env_id, render_mode="rgb_array")
    env.reset(seed=1, options={"wind": (0.0, 0.0), "gusts": False})
    assert env.unwrapped.render_flight() == []  # nothing thrown yet
    landing_before = env.render()
    _, _, _, _, info = env.step(np.array([0.45, 0.0, 0.35, 0.0, 0.0, 0.0], np.float32))
    end = env.render()
    flight = env.unwrapped.render_flight()
    k = info["trajectory_length"]
    assert k > 10 and len(flight) == k - 1  # one frame per recorded point but the last
    assert all(f.shape == end.shape and f.dtype == np.uint8 for f in flight)
    # The ball moves from frame to frame; the landing frame (render()) is not among them.
    assert all(not np.array_equal(a, b) for a, b in zip(flight[:5], flight[1:6], strict=True))
    assert not np.array_equal(flight[-1], end)
    assert not np.array_equal(end, landing_before)
    np.testing.assert_array_equal(env.render(), end)  # render() is unchanged by it
    env.close()


def test_render_flight_topple():
    env = gym.make("BeachballTopple-v0", render_mode="rgb_array")
    env.reset(seed=0, options={"wind": (0.0, 0.0), "gusts": False, "wall_distance": 4.0})
    assert env.unwrapped.render_flight() == []
    _, _, _, _, info = env.step(np.array([0.5, 0.0, 0.3, 0.0, 0.0, 0.0], np.float32))
    flight = env.unwrapped.render_flight()
    assert len(flight) == info["samples_length"] > 10
    assert not np.array_equal(flight[0], flight[5])  # the ball flies
    np.testing.assert_array_equal(flight[-1], env.render())  # the interval ends at its end
    env.close()


def test_render_flight_without_render_mode_is_empty():
    env = gym.make("BeachballThrow-v0")
    env.reset(seed=0)
    env.step(np.array([0.45, 0.0, 0.35, 0.0, 0.0, 0.0], np.float32))
    with pytest.warns(UserWarning, match="render_mode"):
        assert env.unwrapped.render_flight() == []


# -- bbgym record ------------------------------------------------------------------------------


def test_record_sail_gif(tmp_path, capsys):
    out = tmp_path / "sail.gif"
    argv = ["--env", "BeachballSail-v0", "--policy", SAIL_POLICY, "--max-steps", "30"]
    assert cli.main(["record", *argv, "--seed", "3", "--out", str(out), "--fps", "20"]) == 0
    n, size, durations = gif_frames(out)
    assert n == 31  # the start and one frame per step
    assert size == render_size("BeachballSail-v0")
    assert durations == [50] * 30 + [1000]  # 20 fps; the last frame held --hold 1 s
    line = capsys.readouterr().out.strip().splitlines()[-1]
    assert "30 steps" in line and "31 frames" in line and str(out) in line
    assert "success False" in line  # 30 steps (7.5 s) do not reach the mark


def test_record_gif_of_a_long_episode_stays_small(tmp_path, capsys):
    """A GIF of more frames than the budget (300) keeps every second one, each shown twice
    as long (real time still), and stays under 3 MB; the summary says how many it holds."""
    out = tmp_path / "long.gif"
    argv = ["--env", "BeachballSail-v0", "--policy", "random", "--max-steps", "330"]
    assert cli.main(["record", *argv, "--seed", "0", "--out", str(out)]) == 0
    n, size, durations = gif_frames(out)
    assert n <= record.MAX_GIF_FRAMES == 300
    assert 150 <= n <= 170  # 331 frames: every second one (166), fewer if two were alike
    assert out.stat().st_size < 3_000_000
    assert size == render_size("BeachballSail-v0")
    # 330 steps at 20 fps, then the last frame held 1 s: 17.5 s, as without the budget
    assert sum(durations) == pytest.approx(330 * 50 + 1000, abs=10)
    assert durations[-1] == 1000 and durations[0] == 100
    line = capsys.readouterr().out.strip().splitlines()[-1]
    assert f"331 frames ({n} in the GIF)" in line


def test_record_episode_frame_skip_keeps_the_last_frame():
    env = gym.make("BeachballSail-v0", render_mode="rgb_array")
    sink = ListSink()
    policy = record.make_policy("random", env, None, 0)
    stats = record.record_episode(env, policy, 0, sink, frame_skip=4, max_steps=30, hold_periods=7)
    env.close()
    # Frames 0, 4, ..., 28 of the 31, and the last one (30), held 7 periods.
    assert stats["steps"] == 30 and stats["capped"] and stats["frames"] == 9
    assert len(sink.frames) == 9 and sink.periods == [1] * 8 + [7]
    assert not np.array_equal(sink.frames[-1], sink.frames[-2])


def test_record_throw_shows_the_flights(tmp_path, capsys):
    env = gym.make("BeachballThrow-v0", render_mode="rgb_array")
    sink = ListSink()
    policy = record.make_policy("random", env, None, 5)
    flights = []
    step = env.step

    def counting_step(action):
        result = step(action)
        flights.append(result[4]["trajectory_length"] - 1)
        return result

    env.step = counting_step
    stats = record.record_episode(env, policy, 5, sink, max_steps=2, hold_periods=20)
    env.close()
    assert stats["steps"] == 2 and len(flights) == 2 and min(flights) > 5
    # The start, then per throw its flight and its landing (held 20 periods).
    assert stats["frames"] == len(sink.frames) == 1 + sum(flights) + 2
    assert sink.periods == [1] + ([1] * flights[0] + [20]) + ([1] * flights[1] + [20])

    out = tmp_path / "throw.gif"
    argv = ["--env", "BeachballThrow-v0", "--policy", "random", "--max-steps", "2"]
    assert cli.main(["record", *argv, "--seed", "5", "--out", str(out), "--frame-skip", "2"]) == 0
    n, size, durations = gif_frames(out)
    assert size == render_size("BeachballThrow-v0")
    assert n > 2 * 5  # many more frames than throws: the flights are in it
    assert sum(durations) == pytest.approx(50 * (n - 2) + 2 * 1000, abs=50 * 5)
    assert "2 steps" in capsys.readouterr().out


@pytest.mark.skipif(not HAS_MP4, reason="imageio-ffmpeg not installed")
def test_record_mp4(tmp_path):
    import imageio_ffmpeg

    out = tmp_path / "sail.mp4"
    argv = ["--env", "BeachballSail-v0", "--policy", "random", "--max-steps", "5"]
    assert cli.main(["record", *argv, "--out", str(out), "--fps", "10", "--hold", "0.5"]) == 0
    data = out.read_bytes()
    assert len(data) > 1000 and data[4:8] == b"ftyp"
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(out))
    assert frames == 5 + 5  # 6 frames, the last one repeated for 0.5 s at 10 fps


def test_mp4_without_imageio_ffmpeg_is_a_clear_error(monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *a: None if name == "imageio_ffmpeg" else real(name),
    )
    with pytest.raises(ValueError, match="imageio-ffmpeg"):
        record.check_format(Path("episode.mp4"))
    assert record.check_format(Path("episode.GIF")) == ".gif"


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--policy", "random", "--out", "episode.avi"], "must end in .gif or .mp4"),
        (["--policy", "ppo"], "needs --model"),
        (["--policy", "sac"], "--policy sac needs --model"),
        (["--policy", "nonsense"], "invalid choice"),
        (["--policy", "random", "--frame-skip", "0"], "--frame-skip: must be >= 1"),
    ],
)
def test_record_argument_errors(tmp_path, capsys, extra, message):
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["record", "--env", "BeachballThrow-v0", *extra])
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err
    assert not list(tmp_path.iterdir()) and not Path("episode.avi").exists()


# -- bbgym play: key tables and wrappers ---------------------------------------------------------


class Recorder(gym.Wrapper):
    """Records the actions that reach the env."""

    def __init__(self, env):
        super().__init__(env)
        self.actions = []

    def step(self, action):
        self.actions.append(np.array(action, dtype=np.float64))
        return self.env.step(action)


K = pygame


def combo(*keys: int) -> tuple[int, ...]:
    """A key combination as gymnasium.utils.play looks it up: sorted key codes."""
    return tuple(sorted(keys))


def test_sail_keys_to_action():
    table = play.combine_keys(sail_keys.SAIL_KEYS)
    assert len(table) == 15  # every non-empty combination of the four arrows
    space = gym.make("BeachballSail-v0").action_space
    assert all(a in space and a.dtype == np.float32 for a in table.values())
    expected = {
        (K.K_LEFT,): [1, 0],
        (K.K_RIGHT,): [-1, 0],
        (K.K_UP,): [0, -1],
        (K.K_DOWN,): [0, 1],
        combo(K.K_LEFT, K.K_RIGHT): [0, 0],
        combo(K.K_LEFT, K.K_UP): [1, -1],
        combo(K.K_RIGHT, K.K_DOWN): [-1, 1],
        combo(K.K_UP, K.K_DOWN, K.K_RIGHT): [-1, 0],
    }
    for keys, action in expected.items():
        np.testing.assert_array_equal(table[keys], action)


def test_throw_keys_to_action():
    table = play.combine_keys(throw_keys.THROW_KEYS)
    assert len(table) == 2**11 - 1
    np.testing.assert_array_equal(table[(K.K_SPACE,)], [0, 0, 0, 0, 0, 1])
    np.testing.assert_array_equal(table[combo(K.K_w, K.K_UP)], [1, 1, 0, 0, 0, 0])
    np.testing.assert_array_equal(table[combo(K.K_LEFT, K.K_a, K.K_q)], [0, 0, 1, 1, -1, 0])
    np.testing.assert_array_equal(table[combo(K.K_w, K.K_s, K.K_SPACE)], [0, 0, 0, 0, 0, 1])


def test_sail_wrapper_holds_the_sheet(capsys):
    inner = Recorder(gym.make("BeachballSail-v0"))
    env = sail_keys.SailKeys(inner, seed=0)
    table = env.get_keys_to_action()
    env.reset()
    up, left, down = table[(K.K_UP,)], table[(K.K_LEFT,)], table[(K.K_DOWN,)]
    for command in [up, up, up, env.noop, env.noop, left]:
        env.step(command)
    np.testing.assert_allclose(
        inner.actions,
        [[0, -0.05], [0, -0.10], [0, -0.15], [0, -0.15], [0, -0.15], [1, -0.15]],
        atol=1e-12,
    )
    for _ in range(60):
        env.step(down)
    assert env.sheet == 1.0 and inner.actions[-1][1] == 1.0  # clipped at fully out
    env.reset()
    assert env.sheet == sail_keys.INITIAL_SHEET
    assert "sheet +1.00" in capsys.readouterr().out


def test_wrapper_seeds_the_first_episode_only():
    reference = gym.make("BeachballSail-v0")
    first, _ = reference.reset(seed=7)
    second, _ = reference.reset()
    env = sail_keys.SailKeys(gym.make("BeachballSail-v0"), seed=7)
    np.testing.assert_array_equal(env.reset()[0], first)
    np.testing.assert_array_equal(env.reset()[0], second)


def test_throw_wrapper_aims_and_throws_only_on_space(capsys):
    inner = Recorder(gym.make("BeachballThrow-v0", render_mode="rgb_array"))
    env = throw_keys.ThrowKeys(inner, seed=2)
    table = env.get_keys_to_action()
    obs, info = env.reset()
    target = info["target"]
    assert env.azimuth_deg == pytest.approx(math.degrees(math.atan2(target[1], target[0])))
    assert (env.speed, env.elevation_deg, env.side_spin, env.back_spin) == (10.0, 35.0, 0.0, 0.0)
    start = env.render()

    for keys in [(K.K_UP,)] * 5 + [(K.K_w,)] * 10 + [(K.K_LEFT,)] * 3 + [(K.K_e,)] * 4:
        o, reward, terminated, truncated, _ = env.step(table[keys])
        np.testing.assert_array_equal(o, obs)  # aiming does not step the env
        assert (reward, terminated, truncated) == (0.0, False, False)
    assert inner.actions == []
    assert env.elevation_deg == pytest.approx(40.0) and env.speed == pytest.approx(12.0)
    assert env.back_spin == pytest.approx(8.0)
    azimuth = math.atan2(target[1], target[0]) + math.radians(3.0)
    assert env.azimuth_deg == pytest.approx(math.degrees(azimuth))
    el = math.radians(40.0)
    expected = np.array(
        [
            12 * math.cos(el) * math.cos(azimuth) / 18,
            12 * math.cos(el) * math.sin(azimuth) / 18,
            12 * math.sin(el) / 18,
            8 * math.sin(azimuth) / 60,  # backspin: about the axis to the thrower's right
            -8 * math.cos(azimuth) / 60,
            0.0,
        ]
    )
    np.testing.assert_allclose(env.throw_action(), expected, atol=1e-6)

    space = table[(K.K_SPACE,)]
    _, reward, _, _, info = env.step(space)
    assert len(inner.actions) == 1 and reward > 0.0
    np.testing.assert_allclose(inner.actions[0], expected, atol=1e-6)
    env.step(space)  # still held: no second throw
    assert len(inner.actions) == 1
    # render() plays the flight back, one frame a call, then shows the landing.
    k = info["trajectory_length"]
    played = [env.render() for _ in range(k - 1)]
    assert not np.array_equal(played[0], start) and not np.array_equal(played[0], played[-1])
    end = env.render()
    np.testing.assert_array_equal(end, inner.render())
    env.step(env.noop)
    env.step(space)  # pressed again: the second throw
    assert len(inner.actions) == 2
    assert "throw 2: reward" in capsys.readouterr().out


def test_throw_wrapper_throws_once_per_press():
    inner = Recorder(gym.make("BeachballThrow-v0"))  # no rendering: no flight to wait for
    env = throw_keys.ThrowKeys(inner, seed=0)
    space = env.get_keys_to_action()[(K.K_SPACE,)]
    env.reset()
    for command in [space, space, space, env.noop, space, space, env.noop, env.noop]:
        env.step(command)
    assert len(inner.actions) == 2 and env.throws == 2


def test_throw_wrapper_no_throw_while_the_flight_plays():
    env = throw_keys.ThrowKeys(Recorder(gym.make("BeachballTopple-v0", render_mode="rgb_array")))
    space = env.get_keys_to_action()[(K.K_SPACE,)]
    env.reset(seed=0)
    assert env.azimuth_deg == 0.0  # toward the wall, along +x
    env.step(space)
    env.step(env.noop)
    env.step(space)  # the first step's interval is still being shown
    assert len(env.env.actions) == 1
    while env._frames:
        env.render()
    env.step(env.noop)
    env.step(space)
    assert len(env.env.actions) == 2


# -- bbgym play: gymnasium.utils.play driven headless ---------------------------------------------


def drive(env, script: dict[int, list], limit: int = 40) -> int:
    """Run gymnasium's play on ``env``, posting ``script[n]`` (events) after step ``n``."""
    steps = 0

    def callback(*_):
        nonlocal steps
        steps += 1
        if steps > limit:
            raise RuntimeError("play did not stop: the posted events were not seen")
        for event in script.get(steps, []):
            pygame.event.post(event)

    play.play_env(env, fps=1000, zoom=0.5, callback=callback)
    return steps


def key(kind, code):
    return pygame.event.Event(kind, key=code)


def test_gymnasium_play_drives_the_sail_wrapper():
    inner = Recorder(gym.make("BeachballSail-v0", render_mode="rgb_array"))
    env = sail_keys.SailKeys(inner, seed=0)
    script = {
        1: [key(pygame.KEYDOWN, K.K_UP)],
        4: [key(pygame.KEYUP, K.K_UP), key(pygame.KEYDOWN, K.K_LEFT)],
        6: [pygame.event.Event(pygame.QUIT)],
    }
    assert drive(env, script) == 6
    np.testing.assert_allclose(
        inner.actions,
        [[0, 0], [0, -0.05], [0, -0.10], [0, -0.15], [1, -0.15], [1, -0.15]],
        atol=1e-12,
    )
    env.close()


def test_gymnasium_play_drives_the_throw_wrapper():
    inner = Recorder(gym.make("BeachballThrow-v0", render_mode="rgb_array"))
    env = throw_keys.ThrowKeys(inner, seed=0)
    script = {
        1: [key(pygame.KEYDOWN, K.K_DOWN)],
        3: [key(pygame.KEYUP, K.K_DOWN), key(pygame.KEYDOWN, K.K_SPACE)],
        5: [key(pygame.KEYUP, K.K_SPACE)],
        8: [key(pygame.KEYDOWN, K.K_ESCAPE)],
    }
    assert drive(env, script) == 8
    assert env.elevation_deg == pytest.approx(33.0)  # DOWN held for steps 2 and 3
    assert len(inner.actions) == 1  # SPACE held for steps 4 and 5: one throw
    assert inner.actions[0][2] == pytest.approx(10 * math.sin(math.radians(33.0)) / 18)
    env.close()


def test_play_help_lists_the_keys(capsys):
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["play", "--help"])
    assert exit_info.value.code == 0
    out = capsys.readouterr().out
    assert "SPACE" in out and "sheet in / ease out" in out and "--zoom" in out
