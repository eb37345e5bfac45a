"""Gymnasium's vector envs and wrappers on every env: SyncVectorEnv, AsyncVectorEnv and the
native vector env agree with single envs and stack the infos; RecordEpisodeStatistics,
RecordVideo (``rgb_array`` and ``rgb_array_list``), NormalizeObservation/Reward,
FrameStackObservation, TimeLimit and the vector wrappers give the numbers they should."""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from gymnasium.wrappers import (
    FrameStackObservation,
    NormalizeObservation,
    NormalizeReward,
    RecordEpisodeStatistics,
    RecordVideo,
    TimeLimit,
)
from gymnasium.wrappers import vector as vector_wrappers

import bbgym  # noqa: F401  (registers the ids)
from bbgym.envs import RecordFlightVideo
from bbgym.spec import spec_of, specs

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

ENV_IDS = list(dict.fromkeys(i for s in specs() for i in (s.ids[0], s.ids[-1])))
"""Every registered family's oldest and newest version."""
BALL_IDS = [e for e in ENV_IDS if spec_of(e).step_unit == "throws"]
"""The ball envs: a step is a throw (or a wait), its flight recorded."""
LENGTH_KEY = {"throw": "trajectory_length", "topple": "samples_length"}
"""By family: the info counting a step's recorded rows (its flight's frames: one per row)."""
PADDED = {
    "throw": {"trajectory": (3,), "orientations": (4,)},
    "topple": {
        "ball_trajectory": (3,),
        "ball_orientations": (4,),
        "wall_angle_samples": (),
        "loose_samples": (3,),
        "loose_mask": (),
    },
}
"""By family: the per-step records and the shape of a row (each has the task's
``record_capacity`` rows)."""
END_FRAME = {"topple": 1}
"""By family: frames ``rgb_array_list`` adds after a step's recorded rows (Topple's end)."""


def family(env_id: str) -> str:
    return spec_of(env_id).family


def length_key(env_id: str) -> str | None:
    """The info counting the step's recorded rows; None for an env that records none."""
    return LENGTH_KEY.get(family(env_id))


def padded(env_id: str) -> dict[str, tuple[int, ...]]:
    """The per-step records of an env and their fixed shapes (record_capacity rows)."""
    records = PADDED.get(family(env_id), {})
    if not records:
        return {}
    capacity = gym.make(env_id).unwrapped.task.record_capacity
    return {key: (capacity, *row) for key, row in records.items()}


def step_frames(env_id: str, info: dict[str, Any]) -> int:
    """The frames ``rgb_array_list`` collects for a step: a throw's flight, one per recorded
    pose but the last, then its landing; Topple's interval, one per sample, then its end;
    Sail's one."""
    key = length_key(env_id)
    if key is None:
        return 1
    return int(info[key]) + END_FRAME.get(family(env_id), 0)


def action_shape(env_id: str) -> tuple[int, ...]:
    return gym.make(env_id).action_space.shape


def actions_for(env_id: str, shape: tuple[int, ...], seed: int = 0) -> np.ndarray:
    """Random actions in [-1, 1]; the ball envs' throws forward and up (long flights)."""
    a = np.random.default_rng(seed).uniform(-1.0, 1.0, shape)
    if env_id in BALL_IDS:
        a[..., 0], a[..., 2] = np.abs(a[..., 0]) * 0.5 + 0.2, np.abs(a[..., 2]) * 0.4 + 0.2
    return a.astype(np.float32)


def leaves(info: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    """An info's entries by dotted name (nested dicts flattened), masks left out."""
    out: dict[str, Any] = {}
    for key, value in info.items():
        if key.startswith("_"):
            continue
        if isinstance(value, dict):
            out.update(leaves(value, f"{prefix}{key}."))
        else:
            out[prefix + key] = value
    return out


def signature(info: dict[str, Any]) -> dict[str, tuple]:
    """Each entry's type, dtype and shape: what Gymnasium's info stacking depends on."""
    return {
        k: (type(v).__name__, str(getattr(v, "dtype", "")), np.shape(v))
        for k, v in leaves(info).items()
    }


def assert_infos_equal(got: dict[str, Any], want: dict[str, Any], atol: float) -> None:
    """The same entries, shapes and dtype kinds; numbers within ``atol`` (NaN equal)."""
    got, want = leaves(got), leaves(want)
    assert set(got) == set(want)
    for key, value in want.items():
        a, b = np.asarray(got[key]), np.asarray(value)
        assert a.shape == b.shape and a.dtype.kind == b.dtype.kind, key
        if b.dtype.kind in "fiub":
            np.testing.assert_allclose(a, b, atol=atol, rtol=0, err_msg=key)
        else:
            assert a.tolist() == b.tolist(), key


# -- vector envs ----------------------------------------------------------------------------


def run_vector(env: gym.vector.VectorEnv, seed: int, actions: np.ndarray) -> list[tuple]:
    out = [env.reset(seed=seed)]
    out += [env.step(a) for a in actions]
    env.close()
    return out


def run_singles(env_id: str, n: int, seed: int, actions: np.ndarray, **kwargs: Any) -> list:
    """Single envs seeded ``seed + i``, restarted on the step after an end (as the vector
    envs do: that step returns the new episode's first observation, reward 0)."""
    runs = []
    for i in range(n):
        env = gym.make(env_id, **kwargs)
        rows: list[tuple] = [env.reset(seed=seed + i)]
        done = False
        for a in actions[:, i]:
            if done:
                obs, info = env.reset()
                rows.append((obs, 0.0, False, False, info))
                done = False
            else:
                rows.append(env.step(a))
                done = rows[-1][2] or rows[-1][3]
        runs.append(rows)
        env.close()
    return runs


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_sync_async_native_and_single_envs_agree(env_id):
    n, steps, seed, limit = 3, 7, 21, 4
    actions = actions_for(env_id, (steps, n, *action_shape(env_id)))
    runs = {
        mode: run_vector(
            gym.make_vec(env_id, num_envs=n, vectorization_mode=mode, max_episode_steps=limit),
            seed,
            actions,
        )
        for mode in ("sync", "async", "vector_entry_point")
    }
    singles = run_singles(env_id, n, seed, actions, max_episode_steps=limit)
    records = padded(env_id)
    sync, native = runs["sync"], runs["vector_entry_point"]
    ends = 0
    for t in range(steps + 1):
        # Sync and async step the same single envs: the same bits.
        for a, b in zip(runs["async"][t], sync[t], strict=True):
            if isinstance(b, dict):
                assert_infos_equal(a, b, atol=0.0)
            else:
                np.testing.assert_array_equal(a, b)
        # The native vector env: the same numbers (NumPy against Python floats).
        np.testing.assert_allclose(native[t][0], sync[t][0], atol=1e-5)
        assert_infos_equal(native[t][-1], sync[t][-1], atol=1e-6)
        if t:
            np.testing.assert_allclose(native[t][1], sync[t][1], atol=1e-6)
            np.testing.assert_array_equal(native[t][2], sync[t][2])
            np.testing.assert_array_equal(native[t][3], sync[t][3])
            ends += int(np.sum(sync[t][2] | sync[t][3]))
        for i in range(n):
            np.testing.assert_array_equal(singles[i][t][0], sync[t][0][i])
            if t:
                assert singles[i][t][1] == sync[t][1][i]
                assert (singles[i][t][2], singles[i][t][3]) == (sync[t][2][i], sync[t][3][i])
        # The records stack: fixed shapes, lengths per env (0 after a reset).
        info = sync[t][-1]
        for key, shape in records.items():
            assert info[key].shape == (n, *shape) and info[f"_{key}"].all()
        if length_key(env_id) is not None:
            lengths = info[length_key(env_id)]
            assert lengths.shape == (n,) and lengths.dtype == np.int64
            if t < 2:  # the reset's, then the first step's
                fresh = np.full(n, t == 0)
            else:  # an env ended last step restarts on this one
                fresh = sync[t - 1][2] | sync[t - 1][3]
            assert ((lengths == 0) == fresh).all() and (lengths[~fresh] > 5).all()
    assert ends >= n  # every env ended an episode and restarted


@pytest.mark.parametrize("env_id", BALL_IDS)
def test_padded_records_repeat_the_last_row_and_match_the_vector_env(env_id):
    env = gym.make(env_id)
    _, info = env.reset(seed=4)
    records = padded(env_id)
    key, length = next(iter(records)), length_key(env_id)
    assert info[length] == 0 and not np.any(info[key])  # zeros: nothing recorded
    vec = gym.make_vec(env_id, num_envs=2)
    vec.reset(seed=4)
    action = actions_for(env_id, (2, 6), seed=3)
    _, _, _, _, info = env.step(action[0])
    _, _, _, _, vec_info = vec.step(action)
    k, rows = info[length], info[key]
    assert 5 < k <= len(rows) and (k < len(rows) or family(env_id) == "topple")
    assert np.isfinite(rows).all()
    np.testing.assert_array_equal(rows[k:], np.broadcast_to(rows[k - 1], rows[k:].shape))
    assert vec_info[length][0] == k
    for name in records:
        np.testing.assert_allclose(vec_info[name][0], info[name], atol=1e-9)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_info_keys_and_types_are_the_same_after_reset_and_step(env_id):
    env = gym.make(env_id, max_episode_steps=5)
    _, info = env.reset(seed=1)
    want = signature(info)
    for a in actions_for(env_id, (12, *env.action_space.shape), seed=2):
        _, _, terminated, truncated, info = env.step(a)
        assert signature(info) == want
        if terminated or truncated:
            _, info = env.reset()
            assert signature(info) == want
    vec = gym.make_vec(env_id, num_envs=2, max_episode_steps=5)
    _, vec_info = vec.reset(seed=1)
    _, _, _, _, stepped = vec.step(actions_for(env_id, (2, *env.action_space.shape)))
    assert signature(vec_info) == signature(stepped)
    assert set(leaves(vec_info)) == set(want)


# -- episode statistics -----------------------------------------------------------------------


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_record_episode_statistics(env_id):
    env = RecordEpisodeStatistics(gym.make(env_id, max_episode_steps=6))
    env.reset(seed=5)
    total, steps = 0.0, 0
    for a in actions_for(env_id, (6, *env.action_space.shape), seed=5):
        _, reward, terminated, truncated, info = env.step(a)
        total, steps = total + reward, steps + 1
        if terminated or truncated:
            break
    assert "episode" in info and info["episode"]["l"] == steps
    assert info["episode"]["r"] == pytest.approx(total, abs=1e-9)

    n = 3
    vec = vector_wrappers.RecordEpisodeStatistics(
        gym.make_vec(env_id, num_envs=n, max_episode_steps=6)
    )
    vec.reset(seed=5)
    totals, lengths, restart = np.zeros(n), np.zeros(n, int), np.zeros(n, bool)
    checked = np.zeros(n, bool)
    for a in actions_for(env_id, (8, n, *env.action_space.shape), seed=6):
        _, reward, terminated, truncated, info = vec.step(a)
        totals, lengths = np.where(restart, 0.0, totals + reward), np.where(restart, 0, lengths + 1)
        restart = terminated | truncated
        if restart.any():
            assert (info["_episode"] == restart).all()
            np.testing.assert_allclose(info["episode"]["r"][restart], totals[restart], atol=1e-9)
            np.testing.assert_array_equal(info["episode"]["l"][restart], lengths[restart])
            checked |= restart
    assert checked.all() and len(vec.return_queue) >= n


# -- rendering and videos ---------------------------------------------------------------------


def video_frames(path: Path) -> int:
    """The frames of a video, counted by decoding them all with ffmpeg (imageio-ffmpeg, the
    one moviepy writes with). Not by moviepy's reader: moviepy 2.2 closes its ffmpeg pipes
    only when ffmpeg is still running, so after a whole file has been read they are left to
    the garbage collector, whose ResourceWarning then fails whichever test it lands in."""
    import imageio_ffmpeg

    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(path))
    return frames


def assert_video(folder: Path, frames: int) -> None:
    """One mp4 in ``folder`` of the ``frames`` the wrapper recorded (moviepy 2.2's writer
    drops the last of more than a few: ``ImageSequenceClip`` of 10 frames writes 9)."""
    (video,) = folder.glob("*.mp4")
    assert video_frames(video) in (frames - 1, frames)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_rgb_array_list_collects_every_frame_since_the_last_render(env_id):
    env = gym.make(env_id, render_mode="rgb_array_list")
    assert "rgb_array_list" in env.metadata["render_modes"]
    assert env.render_mode == env.unwrapped.render_mode == "rgb_array_list"  # no RenderCollection
    twin = gym.make(env_id, render_mode="rgb_array")
    env.reset(seed=2)
    twin.reset(seed=2)
    env.step(np.zeros(env.action_space.shape, np.float32))  # dropped by reset()
    env.reset(seed=2)
    start = env.render()
    assert len(start) == 1 and start[0].shape == (480, 640, 3) and start[0].dtype == np.uint8
    np.testing.assert_array_equal(start[0], twin.render())
    assert env.render() == []  # cleared by render()
    action = actions_for(env_id, env.action_space.shape, seed=8)
    _, _, _, _, info = env.step(action)
    twin.step(action)
    frames = env.render()
    # A ball env's step is its flight (render_flight()), then its end (render()).
    assert len(frames) == step_frames(env_id, info)
    assert len(frames) > 10 or length_key(env_id) is None
    np.testing.assert_array_equal(frames[-1], twin.render())
    if length_key(env_id) is not None:
        flight = twin.unwrapped.render_flight()
        assert len(flight) == len(frames) - 1
        for k in (0, len(flight) // 2, len(flight) - 1):
            np.testing.assert_array_equal(frames[k], flight[k])
        assert not np.array_equal(frames[0], frames[len(flight) // 2])  # the ball moves
    env.close()
    twin.close()


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_native_vector_env_rgb_array_list(env_id):
    vec = gym.make_vec(env_id, num_envs=2, render_mode="rgb_array_list")
    vec.reset(seed=3)
    _, _, _, _, info = vec.step(actions_for(env_id, (2, *vec.single_action_space.shape)))
    frames = vec.render()
    assert isinstance(frames, tuple) and len(frames) == 2
    for i, lst in enumerate(frames):
        sub_info = {k: v[i] for k, v in info.items() if k == length_key(env_id)}
        assert len(lst) == 1 + step_frames(env_id, sub_info)
        assert all(f.shape == (480, 640, 3) for f in lst)
    assert vec.render() == ([], [])
    vec.close()


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_check_env_passes_for_every_render_mode(env_id):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # check_env makes the env anew in each of metadata["render_modes"] and renders it.
        check_env(gym.make(env_id, render_mode="rgb_array_list").unwrapped)
    # (Gymnasium's own notice that a newer version of an id exists is not check_env's.)
    assert [str(w.message) for w in caught if "is out of date" not in str(w.message)] == []
    assert set(gym.make(env_id).metadata["render_modes"]) == {
        "human",
        "rgb_array",
        "rgb_array_list",
    }


def record_episode(env: RecordVideo, env_id: str, steps: int) -> tuple[list[dict], int]:
    """The infos of up to ``steps`` steps and the frames the wrapper recorded."""
    env.reset(seed=6)
    infos = []
    for a in actions_for(env_id, (steps, *env.action_space.shape), seed=9):
        _, _, terminated, truncated, info = env.step(a)
        infos.append(info)
        if terminated or truncated:
            break
    recorded = len(env.recorded_frames)
    env.close()  # writes the video
    return infos, recorded


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_record_video(env_id, tmp_path):
    steps = 1 if env_id in BALL_IDS else 4
    every = dict(episode_trigger=lambda episode: True)
    # rgb_array: one frame per reset and step.
    env = RecordVideo(gym.make(env_id, render_mode="rgb_array"), str(tmp_path / "a"), **every)
    infos, recorded = record_episode(env, env_id, steps)
    assert recorded == 1 + len(infos)
    assert_video(tmp_path / "a", recorded)
    # rgb_array_list: Gymnasium 1.2's RecordVideo puts the last frame of each list (the
    # landing) in the video and keeps the lists (the flights) in its render_history.
    env = RecordVideo(gym.make(env_id, render_mode="rgb_array_list"), str(tmp_path / "b"), **every)
    infos, recorded = record_episode(env, env_id, 1)
    assert recorded == 2 and len(env.render_history) == 1 + step_frames(env_id, infos[0])
    assert_video(tmp_path / "b", recorded)
    if length_key(env_id) is None:
        return
    # RecordFlightVideo puts every frame of the lists in the video: the flights.
    env = RecordFlightVideo(
        gym.make(env_id, render_mode="rgb_array_list"), str(tmp_path / "c"), **every
    )
    infos, recorded = record_episode(env, env_id, steps)
    rows = sum(step_frames(env_id, info) for info in infos)
    assert recorded == 1 + rows and rows > 10 * len(infos)
    assert env.render_history == []
    assert_video(tmp_path / "c", recorded)


# -- observation, reward and time wrappers ----------------------------------------------------


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_normalize_observation_and_reward(env_id):
    steps = 24
    actions = actions_for(env_id, (steps, *gym.make(env_id).action_space.shape), seed=4)

    def run(env: gym.Env) -> tuple[np.ndarray, np.ndarray]:
        obs, _ = env.reset(seed=8)
        seen, rewards = [obs], []
        for a in actions:
            obs, reward, terminated, truncated, _ = env.step(a)
            seen.append(obs)
            rewards.append(reward)
            if terminated or truncated:
                obs, _ = env.reset()
                seen.append(obs)
        return np.array(seen, dtype=np.float64), np.array(rewards, dtype=np.float64)

    raw_obs, raw_rewards = run(gym.make(env_id))
    norm = NormalizeObservation(gym.make(env_id))
    norm_obs, norm_rewards = run(norm)
    assert np.isfinite(norm_obs).all()
    np.testing.assert_array_equal(norm_rewards, raw_rewards)
    # The running statistics are those of the raw observations (all seen, the wrapper's
    # initial count of 1e-4 aside), and each observation is normalized by them.
    np.testing.assert_allclose(norm.obs_rms.mean, raw_obs.mean(axis=0), atol=1e-4)
    np.testing.assert_allclose(norm.obs_rms.var, raw_obs.var(axis=0), atol=1e-4)
    last = (raw_obs[-1] - norm.obs_rms.mean) / np.sqrt(norm.obs_rms.var + 1e-8)
    np.testing.assert_allclose(norm_obs[-1], last, rtol=1e-5, atol=1e-5)
    # Normalized, the observations are centred: their mean over the second half within 2
    # std of 0 (a dinghy gathering speed is not stationary: Sail's largest is 1.75).
    assert np.all(np.abs(norm_obs[len(norm_obs) // 2 :].mean(axis=0)) < 2.0)

    scaled = NormalizeReward(gym.make(env_id), gamma=0.9)
    obs, scaled_rewards = run(scaled)
    np.testing.assert_array_equal(obs, raw_obs)
    assert np.isfinite(scaled_rewards).all()
    # Each reward is divided by the std of the discounted returns so far (one factor).
    ratio = scaled_rewards[raw_rewards != 0] / raw_rewards[raw_rewards != 0]
    assert (ratio > 0).all() and len(ratio) > 0
    assert ratio[-1] == pytest.approx(1 / np.sqrt(scaled.return_rms.var + 1e-8), rel=1e-9)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_frame_stack_and_time_limit(env_id):
    kwargs = {"throws_per_episode": 10} if env_id in BALL_IDS else {}
    raw = gym.make(env_id, **kwargs)
    env = FrameStackObservation(gym.make(env_id, **kwargs), 4)
    size = raw.observation_space.shape[0]
    assert env.observation_space.shape == (4, size)
    first, _ = raw.reset(seed=3)
    stacked, _ = env.reset(seed=3)
    assert stacked.shape == (4, size)
    np.testing.assert_array_equal(stacked, np.tile(first, (4, 1)))  # padded with the reset's
    history = [first] * 4
    for a in actions_for(env_id, (5, *raw.action_space.shape), seed=1):
        obs = raw.step(a)[0]
        stacked = env.step(a)[0]
        history.append(obs)
        np.testing.assert_array_equal(stacked[-1], obs)
        np.testing.assert_array_equal(stacked, np.array(history[-4:]))

    # Zero actions end no episode (a throw dropped at the feet, a wait in calm air, a
    # dinghy drifting): the limit truncates at step 3 exactly.
    options = {"wind": (0.0, 0.0), "gusts": False} if env_id in BALL_IDS else None
    limited = TimeLimit(gym.make(env_id, **kwargs), max_episode_steps=3)
    for _ in range(2):  # and again after a reset
        limited.reset(seed=0, options=options)
        ends = [limited.step(np.zeros(raw.action_space.shape, np.float32))[2:4] for _ in range(3)]
        assert ends == [(False, False), (False, False), (False, True)]


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_vector_wrappers_on_the_native_vector_env(env_id):
    n, steps = 2, 4
    actions = actions_for(env_id, (steps, n, *action_shape(env_id)), seed=7)
    plain = run_vector(gym.make_vec(env_id, num_envs=n), 11, actions)
    raw_obs = np.concatenate([row[0] for row in plain])

    norm = vector_wrappers.NormalizeObservation(gym.make_vec(env_id, num_envs=n))
    normalized = run_vector(norm, 11, actions)
    np.testing.assert_allclose(norm.obs_rms.mean, raw_obs.mean(axis=0), atol=1e-4)
    last = (plain[-1][0] - norm.obs_rms.mean) / np.sqrt(norm.obs_rms.var + 1e-8)
    np.testing.assert_allclose(normalized[-1][0], last, rtol=1e-5, atol=1e-5)

    scaled = vector_wrappers.NormalizeReward(gym.make_vec(env_id, num_envs=n), gamma=0.9)
    rewards = run_vector(scaled, 11, actions)
    assert all(np.isfinite(row[1]).all() for row in rewards[1:])
    np.testing.assert_allclose(
        rewards[-1][1] * np.sqrt(scaled.return_rms.var + 1e-8), plain[-1][1], rtol=1e-9, atol=1e-12
    )

    # ClipAction: actions far out of the box step as the clipped ones do.
    clipped = vector_wrappers.ClipAction(gym.make_vec(env_id, num_envs=n))
    wild = run_vector(clipped, 11, actions * 5.0)
    for got, want in zip(
        wild,
        run_vector(gym.make_vec(env_id, num_envs=n), 11, np.clip(actions * 5.0, -1, 1)),
        strict=True,
    ):
        np.testing.assert_array_equal(got[0], want[0])
    # The clipped actions are other actions than the plain run's: other throws.
    assert not all(np.allclose(a[0], b[0]) for a, b in zip(wild, plain, strict=True))
