"""The course's scenes: each claim of the text measured, NumPy against torch, the
parameters' errors, the view and the ``bbgym scene`` command."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from bbgym.cli import main
from bbgym.physics.ball import drag_rate_per_s
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.scenes import SCENES, get_scene, simulate


def test_push_gives_each_ball_impulse_over_mass_and_keeps_momentum_zero() -> None:
    """§2: the same impulse each way; the speeds are J / m (the lighter ball faster, by
    the mass ratio), the total momentum is zero and nothing changes after the push."""
    run = simulate(
        get_scene("push"), {"mass_left_kg": 0.5, "mass_right_kg": 2.0, "impulse_ns": 3.0}
    )
    speed = run.measures["speed_mps"]
    np.testing.assert_allclose(speed[0], [3.0 / 0.5, 3.0 / 2.0], rtol=1e-15)
    assert speed[0, 0] / speed[0, 1] == pytest.approx(2.0 / 0.5)
    np.testing.assert_allclose(run.measures["momentum_ns"].sum(axis=1), 0.0, atol=1e-12)
    kinetic = run.measures["kinetic_energy_j"]
    np.testing.assert_array_equal(kinetic - kinetic[0], 0.0)
    gap = run.state.x_m[1] - run.state.x_m[0]
    assert gap == pytest.approx(0.3 * (math.sqrt(0.5) + math.sqrt(2.0)) + 2.0 * (6.0 + 1.5))


def test_a_level_arrow_falls_below_its_aim_and_an_aimed_one_hits() -> None:
    """§3: after n steps the level arrow has fallen exactly g dt^2 n (n + 1) / 2 (the
    semi-implicit step's sum), which is g t^2 / 2 to within g t dt / 2; where it reaches
    the apple it is that far below; the arrow raised by asin(g D / v^2) / 2 passes the
    apple within the same error."""
    scene = get_scene("arrow")
    params = scene.make_params(None)
    run = simulate(scene)
    dt, g = params.dt_s, GRAVITY_MPS2
    n = np.arange(len(run.times_s))
    np.testing.assert_allclose(
        run.measures["drop_m"][:, 0], g * dt**2 * n * (n + 1) / 2, rtol=1e-12, atol=1e-12
    )
    t_apple = params.target_distance_m / params.speed_mps
    for body, expected in ((0, 0.5 * g * t_apple**2), (1, 0.0)):
        x, drop = run.measures["x_m"][:, body], run.measures["drop_m"][:, body]
        at_apple = np.interp(params.target_distance_m, x, drop)
        assert abs(at_apple - expected) < g * t_apple * dt, (body, at_apple, expected)
    assert 0.5 * g * t_apple**2 > 2.0  # the level arrow misses the apple by metres


def energy(name: str, **params: float) -> np.ndarray:
    return simulate(get_scene(name), params).measures["energy_jpkg"]


def test_three_beachballs_1_one_stable_one_gaining_one_sinking() -> None:
    """§3: over a minute the left ball (velocity first, put back on the floor) stays
    within 10% of its energy, the middle (position first) more than doubles it, and the
    right (velocity reversed only) loses all of it and its centre ends under the floor."""
    e = energy("three-beachballs-1")
    start = e[0, 0]
    assert np.all(np.abs(e[:, 0] - start) < 0.1 * start)
    assert e[-1, 1] > 2.0 * start and np.all(np.diff(e[:, 1]) >= -1e-9)
    assert e[-1, 2] < 0.0
    height = simulate(get_scene("three-beachballs-1")).measures["height_m"][:, 2]
    assert height[-1] < -1.0  # the centre a radius under the floor: the ball sank through


def test_three_beachballs_1a_reflected_ball_is_fairly_stable_not_perfect() -> None:
    """§3: moving the ball up as far as it went into the floor keeps its energy within 5%
    over a minute (it never sinks), not exactly, and the error shrinks with the time step
    (from 4.9% at 1/30 s to under 1% at 1/240 s)."""
    errors = []
    for dt in (1.0 / 30.0, 1.0 / 60.0, 1.0 / 120.0, 1.0 / 240.0):
        e = energy("three-beachballs-1a", dt_s=dt)[:, 2]
        errors.append(np.max(np.abs(e - e[0])) / e[0])
    assert 0.01 < errors[0] < 0.05 and errors[-1] < 0.01
    assert all(np.diff(errors) < 0.0)
    assert energy("three-beachballs-1a")[:, 2].min() > 0.0


def test_arrow_2_sticks_and_keeps_momentum() -> None:
    """§4: the arrow and the apple end at the common velocity v1 m1 / (m1 + m2), the total
    momentum never changes, and the kinetic energy keeps the share m1 / (m1 + m2)."""
    scene = get_scene("arrow-2")
    params = scene.make_params({"arrow_mass_kg": 0.025, "apple_mass_kg": 0.2})
    run = simulate(scene, params)
    m1, m2 = params.arrow_mass_kg, params.apple_mass_kg
    common = params.speed_mps * m1 / (m1 + m2)
    np.testing.assert_allclose(run.measures["velocity_mps"][-1], [common, common], rtol=1e-12)
    assert run.measures["velocity_mps"][0, 0] == params.speed_mps
    momentum = run.measures["momentum_ns"].sum(axis=1)
    np.testing.assert_allclose(momentum, momentum[0], rtol=1e-12)
    kinetic = run.measures["kinetic_energy_j"].sum(axis=1)
    assert kinetic[-1] / kinetic[0] == pytest.approx(m1 / (m1 + m2), rel=1e-12)


@pytest.mark.parametrize("restitution", [1.0, 0.8, 0.5])
def test_double_bounce_follows_the_restitution_formula(restitution: float) -> None:
    """§4: the top ball leaves the bounce at (e (2 + e) m1 - m2) / (m1 + m2) times its
    impact speed (within 1%: the floor and the ball meet within one step of each other),
    with masses ~ r^2 (a quarter for half the radius); elastic, the pair's energy is kept
    over the run to 1%."""
    scene = get_scene("double-bounce")
    run = simulate(scene, {"restitution": restitution})
    params = run.params
    m1, m2 = params.masses()
    assert m2 / m1 == pytest.approx(0.25)
    velocity = run.measures["velocity_mps"][:, 1]
    bounce = int(np.argmax(velocity > 0.0))
    ratio = velocity[bounce] / -velocity[bounce - 1]
    assert ratio == pytest.approx(params.rebound_ratio(), rel=0.01)
    if restitution == 1.0:
        assert params.rebound_ratio() == pytest.approx(2.2)
        total = run.measures["energy_j"].sum(axis=1)
        assert np.all(np.abs(total - total[0]) < 0.01 * total[0])


def test_three_beachballs_2_drag_is_divided_by_the_mass() -> None:
    """§8: the same drag on a ball of four times the mass slows it a quarter as much, so
    after 15 s the light ball's bounces have died, the heavy one still bounces, and the
    ball without drag keeps within 10% of its energy."""
    scene = get_scene("three-beachballs-2")
    none, light, heavy = scene.make_params(None).balls()
    assert drag_rate_per_s(none, 5.0) == 0.0
    assert drag_rate_per_s(heavy, 5.0) == pytest.approx(drag_rate_per_s(light, 5.0) / 4.0)
    e = energy("three-beachballs-2")
    assert e[-1, 1] < 0.01 * e[0, 1] < e[-1, 2] < 0.5 * e[0, 2]
    assert np.all(np.abs(e[:, 0] - e[0, 0]) < 0.1 * e[0, 0])


EXPLICIT, SEMI, VERLET = 0, 1, 2  # the spring scenes' rows


def test_sproing_the_integrator_and_the_damping_decide_stability() -> None:
    """§7, Sproing (8 x 8 beach balls, 8 springs each): undamped, explicit Euler explodes
    within a second while semi-implicit Euler stays within 30% of its energy and velocity
    Verlet within 10% over 10 s; damped (1 N s/m a spring) all three settle to under 1%; a
    stiff spring (500 N/m at the same step) makes all three explode."""
    scene = get_scene("sproing")
    undamped = simulate(scene, {"damping_nspm": 0.0})
    e, exploded = undamped.measures["energy_j"], undamped.measures["exploded"]
    assert exploded[-1].tolist() == [1.0, 0.0, 0.0]
    assert np.argmax(exploded[:, EXPLICIT] > 0) < 60
    for row, band in ((SEMI, 0.3), (VERLET, 0.1)):
        assert np.all(np.abs(e[:, row] / e[0, row] - 1.0) < band), row
    damped = simulate(scene).measures
    assert damped["exploded"][-1].tolist() == [0.0, 0.0, 0.0]
    assert np.all(damped["energy_j"][-1] < 0.01 * damped["energy_j"][0])
    stiff = simulate(scene, {"stiffness_npm": 500.0}).measures
    assert stiff["exploded"][-1].tolist() == [1.0, 1.0, 1.0]
    assert np.all(np.isfinite(stiff["energy_j"]))


def test_sproing_needs_diagonal_springs_to_hold_its_shape() -> None:
    """§7's "try 4 or 6 springs per node": from a jostled start, with diagonals (8, or the
    triangulated 6) the cells come back to squares; with 4 the grid has no shear stiffness
    and stays collapsed."""
    shear = {
        n: simulate(get_scene("sproing"), {"neighbours": n, "jitter_m": 0.1}).measures["shear"]
        for n in (4, 6, 8)
    }
    assert shear[8][-1, SEMI] < 0.01 and shear[6][-1, SEMI] < 0.02
    assert shear[4][-1, SEMI] > 0.5 > shear[4][0, SEMI]


def test_sproing_3d_is_stable_with_one_layer_of_springs() -> None:
    """§7, Sproing 3D (5 x 5 x 5, 26 springs each): damped it settles with every
    integrator; undamped, explicit Euler explodes and the other two stay bounded."""
    scene = get_scene("sproing-3d")
    damped = simulate(scene).measures
    assert damped["exploded"][-1].tolist() == [0.0, 0.0, 0.0]
    assert np.all(damped["energy_j"][-1] < 0.01 * damped["energy_j"][0])
    undamped = simulate(scene, {"damping_nspm": 0.0}).measures
    assert undamped["exploded"][-1].tolist() == [1.0, 0.0, 0.0]
    e = undamped["energy_j"]
    assert np.all(np.abs(e[:, VERLET] / e[0, VERLET] - 1.0) < 0.1)


def test_sproing_cloth_falls_and_hangs_below_its_anchored_row() -> None:
    """§7, Sproing cloth (10 x 10, top row anchored, started standing above it): after 8 s
    every free particle hangs below the anchored row, the lowest about the cloth's length
    down (its springs stretch under the weight: within 10% over), and the energy has gone
    down; explicit Euler explodes."""
    scene = get_scene("sproing-cloth")
    params = scene.make_params(None)
    states = []
    run = simulate(scene, on_step=lambda p, state: states.append(state))
    last = states[-1]
    free = last.free[:, 0] > 0.5
    length = (params.size - 1) * params.spacing_m
    for row in (SEMI, VERLET):
        assert np.all(last.x_m[row, free, 1] < 0.0), row
        assert -1.1 * length < run.measures["lowest_m"][-1, row] < -length
        assert run.measures["energy_j"][-1, row] < run.measures["energy_j"][0, row]
    np.testing.assert_array_equal(last.x_m[:, ~free], states[0].x_m[:, ~free])
    assert run.measures["exploded"][-1, EXPLICIT] == 1.0


def test_gerstner_points_circle_and_the_wave_self_intersects_past_ka_1() -> None:
    """§10: every surface point stays on its circle of the amplitude's radius; the first
    crest moves at -w / k (within one point's spacing over half a second); with k a = 0.63
    the points stay in order along x all period long, with k a = 1.26 neighbours cross."""
    scene = get_scene("gerstner")
    calm = simulate(scene)
    params = calm.params
    np.testing.assert_allclose(calm.measures["circle_radius_m"], params.amplitude_m, rtol=1e-12)
    assert params.steepness == pytest.approx(0.628, abs=1e-3)
    assert np.all(calm.measures["smallest_gap_m"] > 0.0)
    half_second = int(round(0.5 / params.dt_s))
    moved = (
        calm.measures["first_crest_x_m"][half_second, 0] - calm.measures["first_crest_x_m"][0, 0]
    )
    speed = params.angular_speed_radps / params.wavenumber_radpm
    spacing = params.wavelengths * params.wavelength_m / params.points
    assert abs(moved + speed * half_second * params.dt_s) <= spacing
    steep = simulate(scene, {"amplitude_m": 2.0}).measures["smallest_gap_m"]
    assert np.all(steep < 0.0)


def test_sliding_block_stops_with_the_zero_crossing_check_and_creeps_without() -> None:
    """§6: with the check each block stops (its velocity exactly 0) within a step of
    v0 / (mu_k g), at v0^2 / (2 mu_k g) to within v0 dt, and stays; without it none ever
    stops: each rocks between two velocities of opposite signs and creeps, some forward and
    some back, by its starting speed."""
    scene = get_scene("sliding-block")
    run = simulate(scene)
    p = run.params
    speeds, dt, mu_g = p.speeds(), p.dt_s, p.mu_kinetic * GRAVITY_MPS2
    distance, velocity = run.measures["distance_m"], run.measures["velocity_mps"]
    creep = []
    for k, v0 in enumerate(speeds):
        checked = p.blocks + k
        stop = int(np.argmax(velocity[:, checked] == 0.0))
        assert abs(stop * dt - v0 / mu_g) <= dt
        assert np.all(velocity[stop:, checked] == 0.0)
        assert np.all(distance[stop:, checked] == distance[stop, checked])
        assert distance[stop, checked] == pytest.approx(v0**2 / (2 * mu_g), abs=v0 * dt)
        after = velocity[stop + 1 :, k]
        assert np.all(after != 0.0) and after.min() < 0.0 < after.max()
        creep.append(distance[-1, k] - distance[stop + 1, k])
    assert min(creep) < 0.0 < max(creep)


def test_blocks_on_slopes_hold_below_the_friction_angle_and_slide_above() -> None:
    """§6: released at rest, the blocks on slopes under atan(mu_s) = 31 deg never move;
    those above accelerate at g (sin theta - mu_k cos theta) (their speed after 2 s exact,
    their distance to within v dt)."""
    scene = get_scene("sliding-block-2")
    run = simulate(scene)
    p = run.params
    friction_angle = math.atan(p.mu_static)
    t = run.times_s[-1]
    for k, angle in enumerate(p.angles_rad()):
        distance, velocity = run.measures["distance_m"][:, k], run.measures["velocity_mps"][:, k]
        if angle <= friction_angle:
            assert np.all(distance == 0.0) and np.all(velocity == 0.0), k
            continue
        accel = GRAVITY_MPS2 * (math.sin(angle) - p.mu_kinetic * math.cos(angle))
        assert velocity[-1] == pytest.approx(accel * t, rel=1e-9)
        assert distance[-1] == pytest.approx(0.5 * accel * t * t, abs=velocity[-1] * p.dt_s)


def test_points_of_sail_reach_fastest_run_slower_than_the_wind_beat_to_windward() -> None:
    """§9: after a minute with the bow and sheets set, every boat sails ahead at a steady
    speed; the beam reach is the fastest; running, the boat is slower than the wind that
    pushes it; beating, it makes ground to windward (VMG > 0) and drifts the most, running
    hardly at all; the sail is about 45 deg out on the reach."""
    run = simulate(get_scene("points-of-sail"))
    speed, drift = run.measures["speed_mps"][-1], run.measures["drift_deg"][-1]
    RUN, REACH, BEAT = 0, 1, 2
    late = run.measures["speed_mps"][-40:]  # the last 2 s: steady
    assert np.all(np.abs(late - late[-1]) < 0.01 * late[-1])
    assert speed[REACH] > max(speed[RUN], speed[BEAT]) > 0.0
    assert speed[RUN] < run.params.wind_speed_mps
    assert run.measures["vmg_mps"][-1, BEAT] > 1.0
    assert drift[BEAT] > drift[REACH] > drift[RUN] >= 0.0 and drift[RUN] < 0.5
    assert run.measures["boom_deg"][-1, REACH] == pytest.approx(45.0, abs=2.0)


def test_bowling_balls_the_elephant_falls_faster_beach_balls_alike() -> None:
    """§8: dropped together, both solid balls first fall alike (no drag at rest), then
    the large one is faster all the way down and lands first; the small solid ball and
    both beach balls reach their terminal speeds sqrt(2 m g / (rho C_d A)) (within 1%);
    the two beach balls, their radii 10x apart, fall at one speed (to 1e-9) and land
    together."""
    scene = get_scene("bowling-balls")
    run = simulate(scene)
    speed, height = run.measures["speed_mps"], run.measures["height_m"]
    SMALL, LARGE, SHELL, BIG_SHELL = 0, 1, 2, 3
    landed = [int(np.argmax(height[:, k] <= 0.0)) for k in range(4)]
    assert landed[LARGE] < landed[SMALL] and landed[SHELL] == landed[BIG_SHELL]
    # "both will momentarily start falling with the same velocity", then drag parts them
    assert speed[1, LARGE] == speed[1, SMALL] == pytest.approx(GRAVITY_MPS2 * run.params.dt_s)
    falling = slice(2, landed[LARGE])
    assert np.all(speed[falling, LARGE] > speed[falling, SMALL])
    np.testing.assert_allclose(speed[:, SHELL], speed[:, BIG_SHELL], rtol=1e-9, atol=1e-12)
    balls = run.params.balls()
    for k in (SMALL, SHELL):
        top = speed[: landed[k], k].max()
        assert top == pytest.approx(balls[k].terminal_speed_mps(), rel=0.01), k
    assert balls[LARGE].terminal_speed_mps() > 3.0 * balls[SMALL].terminal_speed_mps()


def test_magnus_backspin_carries_farther_topspin_lands_sooner() -> None:
    """§8: thrown level at 8 m/s with 20 rad/s of backspin, none, or topspin, the ball
    with backspin stays up longest and lands farthest, the topspin one soonest and
    nearest; without spin it lands between (the envs' Magnus law)."""
    run = simulate(get_scene("magnus"))
    height, distance = run.measures["height_m"], run.measures["distance_m"]
    BACK, NONE, TOP = 0, 1, 2
    landed = [int(np.argmax(height[:, k] <= 0.0)) for k in range(3)]
    assert landed[TOP] < landed[NONE] < landed[BACK]
    assert distance[-1, TOP] < distance[-1, NONE] < distance[-1, BACK]
    assert distance[-1, BACK] > 1.2 * distance[-1, NONE]


@pytest.mark.parametrize("name", list(SCENES))
def test_torch_runs_the_same_scene(name: str) -> None:
    """Every scene on torch (float64) equals NumPy, step for step (to 1e-9)."""
    pytest.importorskip("torch")
    pytest.importorskip("array_api_compat")
    ours, theirs = (
        simulate(SCENES[name], steps=300),
        simulate(SCENES[name], steps=300, backend="torch"),
    )
    for key, values in ours.measures.items():
        # summation orders differ: the springs' chaotic motion grows 1e-16 to 1e-12 in 300 steps
        np.testing.assert_allclose(theirs.measures[key], values, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("name", list(SCENES))
def test_the_scenes_keep_to_the_array_api(name: str) -> None:
    """Every scene's step runs on ``array_api_strict`` (only the standard's names) and
    equals NumPy."""
    xp = pytest.importorskip("array_api_strict")
    scene = SCENES[name]
    params = scene.make_params(None)
    strict, ours = scene.initial(params, xp), scene.initial(params, np)
    for _ in range(200):
        strict, ours = scene.step(params, strict, xp), scene.step(params, ours, np)
    for key, value in scene.measures(params, strict, xp).items():
        np.testing.assert_array_equal(np.asarray(value), scene.measures(params, ours, np)[key])


def test_every_scene_names_a_test_of_its_claim_that_exists() -> None:
    """A scene's ``test`` is a test function of ``tests/scenes/test_scenes*.py``."""
    sources = "".join(path.read_text() for path in Path(__file__).parent.glob("test_scenes*.py"))
    tests = set(re.findall(r"^def (test_\w+)\(", sources, flags=re.MULTILINE))
    for scene in SCENES.values():
        assert scene.test in tests, scene.name
        assert scene.section.startswith("§") and scene.claim and scene.title


def test_parameters_are_checked_naming_the_scene_and_field() -> None:
    with pytest.raises(ValueError, match=r"arrow\.dt_s"):
        simulate(get_scene("arrow"), {"dt_s": -1.0})
    with pytest.raises(TypeError, match="unexpected key 'mass'"):
        simulate(get_scene("push"), {"mass": 1.0})
    with pytest.raises(ValueError, match="target_distance_m"):
        simulate(get_scene("arrow"), {"speed_mps": 10.0, "target_distance_m": 100.0})
    with pytest.raises(ValueError, match="drop_height_m"):
        simulate(get_scene("three-beachballs-1"), {"drop_height_m": 0.5})
    with pytest.raises(ValueError, match="steps"):
        simulate(get_scene("push"), steps=-1)
    with pytest.raises(KeyError, match="the scenes: push"):
        get_scene("pull")


def test_every_accepted_extreme_runs_finite() -> None:
    """Each scene at the ends of its parameters' intervals (the coarsest step included)
    stays finite over 40 steps (a spring system that explodes is stopped, finite); the
    counts (particles, grid sizes, balls) over 8: their extremes try the shapes and the
    memory, and 40 steps of 65,536 SPH particles would take 18 s. An extreme may be
    refused only with the other fields' defaults, by a rule that names the scene and
    another field: refused on its own, the declared interval would promise a value the
    scene does not take (sproing's neighbours once declared 26, a 3D count, in 2D)."""
    from dataclasses import fields

    from bbgym.physics.validation import accepted_interval

    for scene in SCENES.values():
        names = [f.name for f in fields(scene.params)]
        for f in fields(scene.params):
            accepted = accepted_interval(scene.params, f.name)
            others = [rf"\b{re.escape(n)}\b" for n in names if n != f.name]
            for value in (accepted.low, accepted.high):
                count = isinstance(f.default, int)
                value = int(value) if count else value
                try:
                    run = simulate(scene, {f.name: value}, steps=8 if count else 40)
                except ValueError as err:  # a combination the scene refuses, naming why
                    message = str(err)
                    assert message.startswith(f"{scene.name}."), message
                    assert any(re.search(other, message) for other in others), message
                    continue
                for values in run.measures.values():
                    assert np.all(np.isfinite(values)), (scene.name, f.name, value)


def test_the_view_draws_each_ball_where_it_is() -> None:
    pytest.importorskip("pygame")
    from bbgym.scenes.view import SceneView

    scene = get_scene("three-beachballs-1")
    params = scene.make_params(None)
    frame = scene.frame(params, scene.initial(params, np))
    view = SceneView(scene, params)
    image = view.render((0.0, frame))
    view.close()
    assert image.shape == (400, 640, 3)
    for ball in frame.circles:
        x, y = view.to_px(ball.x_m, ball.y_m)
        assert tuple(image[int(y), int(x)]) == ball.color


def test_the_scene_command_lists_runs_and_draws(tmp_path, capsys) -> None:
    assert main(["scene", "--list"]) == 0
    listed = capsys.readouterr().out
    assert all(name in listed for name in SCENES)
    assert main(["scene", "push", "--steps", "3", "--param", "impulse_ns=4"]) == 0
    out = capsys.readouterr().out
    assert "3 steps" in out and "momentum_ns" in out and "-4" in out
    pytest.importorskip("pygame")
    pytest.importorskip("PIL")
    gif = tmp_path / "push.gif"
    assert main(["scene", "push", "--steps", "9", "--fps", "10", "--out", str(gif)]) == 0
    from PIL import Image

    with Image.open(gif) as image:  # every third step of 1/30 s at 10 fps: 0, 3, 6, 9
        assert image.n_frames == 4


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["scene"], "name a scene"),
        (["scene", "pull"], "unknown scene 'pull'"),
        (["scene", "push", "--param", "impulse_ns"], "--param takes KEY=VALUE"),
        (["scene", "push", "--param", "mass=2"], "unexpected key 'mass'"),
        (["scene", "push", "--param", "dt_s=0"], r"push\.dt_s"),
        (["scene", "push", "--out", "x.png"], "--out x.png"),
    ],
)
def test_the_scene_command_refuses_naming_the_argument(argv, message, capsys) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 2
    assert re.search(message, capsys.readouterr().err)
