"""The dinghy's integration is stable for every accepted boat (issue 10, DESIGN §2 "Stability").

Before the stiff terms were integrated implicitly, one changed constant was enough for a NaN
within a few hundred steps: a 45 kg m^2 yaw inertia, a 34 kg boat, a centreboard 4x stiffer,
a yaw damping 4x stronger (explicit Euler overshoots once ``dt * c / m > 2``); a 30 m/s
start or a 500 m/s wind overflowed the hull drag, and an abrupt stall the logistic blend.
Each case here ran NaN or raised on the old code; every run must now stay finite and
bounded, on a NumPy batch and on Python floats (the single env's backend), directly and
through the env.
"""

from __future__ import annotations

import math
from dataclasses import fields, replace

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import bbgym  # noqa: F401  (registers the ids)
from bbgym.physics.dinghy import RIGS, SAIL_MODELS, DinghyParams, DinghyState, dinghy_at_rest
from bbgym.physics.namespace import floats
from bbgym.physics.sailing import hull_force, mechanical_energy, sail_normal_coefficient
from bbgym.physics.sailing_step import step, substep
from bbgym.physics.validation import accepted_interval

REGRESSION_BOATS = [
    {"yaw_inertia_kgm2": 45.0},
    {"mass_kg": 34.0},
    {"keel_lift_slope": 2400.0},
    {"yaw_damping_linear": 2000.0},
    {"sail_stall_width_rad": 0.001},
]
YAW_RATE_BOUND_RPS = 3.0
"""A dinghy spins at most about 1.5 rad/s under full rudder (measured: 1.45)."""


def check_bounded(p: DinghyParams, s: DinghyState, wind_mps, speed0_mps, where: str) -> None:
    """Finite, and bounded as a boat is: never faster than twice the wind plus its start
    speed, heel within the capsize angle unless capsized, crew within its two sides."""
    state = np.stack([np.asarray(getattr(s, f), dtype=float) for f in s._fields])
    assert np.isfinite(state).all(), where
    speed = np.hypot(s.vx_mps, s.vy_mps)
    assert (speed <= 2.0 * np.asarray(wind_mps) + speed0_mps + 1e-9).all(), where
    upright = np.logical_not(s.capsized)
    assert (np.abs(np.where(upright, s.heel_rad, 0.0)) <= p.capsize_heel_rad).all(), where
    assert (np.abs(s.crew_out) <= 1.0).all(), where


def sail_batch(p, n, steps, wind, speed0, seed, dt=0.05, bound_yaw=True):
    """``n`` boats with random headings and wind directions, random rudder and sheet each
    0.25 s step, checked every step."""
    rng = np.random.default_rng(seed)
    wind = np.broadcast_to(np.asarray(wind, dtype=float), (n,))
    wind_from = rng.uniform(-math.pi, math.pi, n)
    wx, wy = -wind * np.cos(wind_from), -wind * np.sin(wind_from)
    s = dinghy_at_rest(n, heading_rad=rng.uniform(-math.pi, math.pi, n), speed_mps=speed0)
    for t in range(steps):
        rudder = rng.uniform(-1.0, 1.0, n) * p.rudder_max_rad
        s, _ = step(p, s, rudder, rng.uniform(0.0, 1.0, n), wx, wy, dt, round(0.25 / dt))
        check_bounded(p, s, wind, speed0, f"step {t}")
        if bound_yaw:
            assert (np.abs(s.yaw_rate_rps) <= YAW_RATE_BOUND_RPS).all(), f"step {t}"
    return s


def sail_floats(p, steps, wind, speed0, seed, heading=0.7, wind_from=0.0):
    """One boat on Python floats (``backend.floats``), random rudder and sheet."""
    rng = np.random.default_rng(seed)
    s0 = dinghy_at_rest(1, heading_rad=heading, speed_mps=speed0)
    s = DinghyState(**{f: getattr(s0, f)[0].item() for f in s0._fields})
    wx, wy = -wind * math.cos(wind_from), -wind * math.sin(wind_from)
    for t in range(steps):
        rudder = float(rng.uniform(-1.0, 1.0)) * p.rudder_max_rad
        s, _ = step(p, s, rudder, float(rng.uniform(0.0, 1.0)), wx, wy, 0.05, 5, floats)
        assert isinstance(s.x_m, float)
        check_bounded(p, s, wind, speed0, f"step {t}")
        assert abs(s.yaw_rate_rps) <= YAW_RATE_BOUND_RPS, f"step {t}"
    return s


@pytest.mark.parametrize("boat", REGRESSION_BOATS, ids=lambda b: next(iter(b)))
def test_regression_boats_stay_bounded_on_a_batch_and_on_floats(boat):
    p = DinghyParams(**boat)
    rng = np.random.default_rng(1)
    sail_batch(p, 24, 1000, rng.uniform(2.0, 12.0, 24), 2.0, seed=2)
    for seed, (wind, heading) in enumerate([(6.0, 0.7), (10.0, 2.5), (4.0, -1.2)]):
        sail_floats(p, 400, wind, 2.0, seed, heading=heading)


def test_floats_and_batch_agree_for_the_regression_boats():
    # The same implicit scheme on both namespaces: one boat on floats follows its batch twin.
    for boat in REGRESSION_BOATS:
        p = DinghyParams(**boat)
        s = dinghy_at_rest(1, heading_rad=0.4, speed_mps=2.0, boom_rad=-0.3)
        f = DinghyState(**{k: getattr(s, k)[0].item() for k in s._fields})
        for k in range(120):
            rudder, sheet = 0.35 * math.sin(0.1 * k), 0.2 + 0.4 * (k % 7) / 7
            s, _ = step(
                p,
                s,
                np.array([rudder]),
                np.array([sheet]),
                np.array([-7.0]),
                np.array([2.0]),
                0.05,
                5,
            )
            f, _ = step(p, f, rudder, sheet, -7.0, 2.0, 0.05, 5, floats)
        assert f.x_m == pytest.approx(s.x_m[0], rel=1e-9, abs=1e-9)
        assert f.heel_rad == pytest.approx(s.heel_rad[0], rel=1e-9, abs=1e-9)


@pytest.mark.parametrize(
    "wind, speed0",
    [(5.0, 30.0), (5.0, 15.0), (30.0, 2.0), (30.0, 15.0)],
    ids=["speed30", "speed15", "wind30", "wind30-speed15"],
)
def test_strong_wind_and_fast_starts_stay_bounded(wind, speed0):
    # The env plans true winds to 30 m/s (gusts included) and starts to 15 m/s; a 30 m/s
    # start gave vmg -inf before (the hull drag overshot). Capsizes are allowed (the boat
    # then lies still), blowing up is not.
    p = DinghyParams()
    sail_batch(p, 16, 1000, wind, speed0, seed=3)
    sail_floats(p, 1000, wind, speed0, seed=4)


def test_hull_drag_decays_a_fast_boat_without_overshoot():
    # 100 m/s raised OverflowError on floats. With the drag's derivative in the implicit
    # update the speed falls monotonically, never reversing, at any step.
    p = DinghyParams()
    for dt in (0.05, 0.25):
        s0 = dinghy_at_rest(1, speed_mps=100.0)
        f = DinghyState(**{k: getattr(s0, k)[0].item() for k in s0._fields})
        speeds = [100.0]
        for _ in range(200):
            f, _, _ = substep(p, f, 0.0, p.sheet_min_rad, 0.0, 0.0, dt, floats)
            assert 0.0 < f.vx_mps < speeds[-1]
            speeds.append(f.vx_mps)
        assert speeds[-1] < 5.0
    # The drag itself at 100 m/s is finite and opposes the motion.
    along, across = hull_force(p, np.array([100.0, -100.0]), np.array([100.0, -100.0]))
    assert along[0] < 0.0 < along[1] and across[0] < 0.0 < across[1]


def test_gale_and_hurricane_winds_stay_finite():
    # 500 m/s gave NaN before. Gusts can lift a 25 m/s mean several times; the boat may
    # capsize at once but every number stays finite, with bounded speed.
    p = DinghyParams()
    for wind in (60.0, 150.0, 500.0):
        sail_batch(p, 8, 200, wind, 2.0, seed=5, bound_yaw=False)
        s = sail_floats_unbounded_yaw(p, 200, wind)
        assert math.isfinite(s.x_m)


def sail_floats_unbounded_yaw(p, steps, wind):
    s0 = dinghy_at_rest(1, heading_rad=1.0, speed_mps=2.0)
    s = DinghyState(**{f: getattr(s0, f)[0].item() for f in s0._fields})
    for t in range(steps):
        s, _ = step(p, s, 0.2 * p.rudder_max_rad, 0.5, -wind, 0.0, 0.05, 5, floats)
        check_bounded(p, s, wind, 2.0, f"step {t}")
    return s


def test_abrupt_stall_blend_never_overflows():
    # sail_stall_width_rad 0.001 overflowed exp() in the logistic blend; it is now
    # 0.5 * (1 - tanh(x / 2)), the same function, finite for any width.
    angles = np.radians(np.linspace(0.0, 90.0, 721))
    for width in (1e-4, 1e-3, 0.5):
        p = DinghyParams(sail_stall_width_rad=width)
        cn = sail_normal_coefficient(p, np.sin(angles))
        assert np.isfinite(cn).all() and (cn >= 0.0).all()
        # never above the attached slope's or the flat plate's line
        assert cn.max() <= max(p.sail_cn_peak / math.sin(p.sail_stall_rad), p.sail_cn_flat)
        on_floats = [sail_normal_coefficient(p, math.sin(a), floats) for a in angles[::40]]
        assert on_floats == pytest.approx(list(cn[::40]), rel=1e-12)
    # Where exp() does not overflow the blend equals the logistic 1 / (1 + exp(x)).
    p = DinghyParams()
    a = np.radians([5.0, 14.0, 16.0, 18.0, 40.0])
    share = 1.0 / (1.0 + np.exp((a - p.sail_stall_rad) / p.sail_stall_width_rad))
    attached = p.sail_cn_peak * np.sin(a) / math.sin(p.sail_stall_rad)
    expected = share * attached + (1.0 - share) * p.sail_cn_flat * np.sin(a)
    assert sail_normal_coefficient(p, np.sin(a)) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("boat", REGRESSION_BOATS, ids=lambda b: next(iter(b)))
def test_regression_boats_through_the_env(boat):
    # gym.make and gym.make_vec with the boat, 1000 steps of random actions each.
    kwargs = dict(dinghy=boat, gusts=False, wind_speed_range=(4.0, 12.0))
    speed_hi = 2.0  # the default initial_speed_range's top
    env = gym.make("BeachballSail-v0", **kwargs)
    env.reset(seed=0)
    env.action_space.seed(0)
    for _ in range(1000):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert np.isfinite(obs).all() and math.isfinite(reward)
        assert math.isfinite(info["vmg_to_mark"])
        assert info["boat_speed"] <= 2.0 * 12.0 + speed_hi
        if terminated or truncated:
            env.reset()
    vec = gym.make_vec("BeachballSail-v0", num_envs=8, **kwargs)
    vec.reset(seed=0)
    vec.action_space.seed(0)
    for _ in range(1000):
        obs, reward, _, _, info = vec.step(vec.action_space.sample())
        assert np.isfinite(obs).all() and np.isfinite(reward).all()
        assert (info["boat_speed"] <= 2.0 * 12.0 + speed_hi).all()


@pytest.mark.parametrize("options", [{"speed": 15.0}, {"wind_speed": 25.0}])
def test_fast_start_and_strong_wind_through_the_env(options):
    # Reset options at the top of the env's accepted intervals (30 m/s is tested on the
    # physics above: the env refuses it for now).
    env = gym.make("BeachballSail-v0", gusts=False)
    env.reset(seed=0, options=options)
    env.action_space.seed(1)
    for _ in range(1000):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert np.isfinite(obs).all() and math.isfinite(reward)
        assert math.isfinite(info["vmg_to_mark"]) and info["boat_speed"] <= 2.0 * 25.0 + 15.0
        if terminated or truncated:
            env.reset(options=options)


# -- every accepted boat ---------------------------------------------------------------------

FIELDS = [f for f in fields(DinghyParams) if f.metadata.get("interval") is not None]


@st.composite
def dinghy_params(draw: st.DrawFn) -> DinghyParams:
    """Every field over its whole accepted interval, log-uniform where the interval is
    positive (ends included), all at once; the sail model too."""
    values = {}
    for f in FIELDS:
        accepted = f.metadata["interval"]
        lo, hi = accepted.low, accepted.high
        floor = lo if lo > 0.0 else hi * 1e-6
        u = draw(st.floats(0.0, 1.0), label=f.name)
        value = math.exp(math.log(floor) + u * (math.log(hi) - math.log(floor)))
        if lo == 0.0 and not accepted.low_open and u < 0.05:
            value = 0.0  # the degenerate boat: no damping, no windage, ...
        if accepted.high_open and value >= hi:
            value = math.nextafter(hi, 0.0)
        values[f.name] = min(max(value, lo), hi) if accepted.contains(value) else floor
    for small, large in SHEET_PAIRS:
        lo, hi = sorted((values[small], values[large]))
        if lo == hi:
            lo = 0.5 * hi
        values[small], values[large] = lo, hi
    sail_model = draw(st.sampled_from(SAIL_MODELS), label="sail_model")
    rig = draw(st.sampled_from(RIGS), label="rig")
    return DinghyParams(sail_model=sail_model, rig=rig, **values)


SHEET_PAIRS = (("sheet_min_rad", "sheet_max_rad"), ("jib_sheet_min_rad", "jib_sheet_max_rad"))
"""Fields that must stay in order (``min < max``)."""


@settings(max_examples=24, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    p=dinghy_params(),
    dt=st.sampled_from([0.05, 0.125, 0.25]),
    seed=st.integers(0, 2**16),
)
def test_every_accepted_boat_stays_finite(p, dt, seed):
    # Any boat of the box, random actions, true wind 0-30 m/s, starts at 0-15 m/s, any step
    # up to the env's 0.25 s control step. A boat of the box can be absurd (a 20 kg hull
    # under 150 m^2 of frictionless sail sails like an iceboat, several times the wind), so
    # the speed bound here is loose: 10x wind plus start speed. A numerical blow-up passes
    # any such bound within a few steps.
    rng = np.random.default_rng(seed)
    n = 8
    wind = rng.uniform(0.0, 30.0, n)
    speed0 = rng.uniform(0.0, 15.0, n)
    wind_from = rng.uniform(-math.pi, math.pi, n)
    wx, wy = -wind * np.cos(wind_from), -wind * np.sin(wind_from)
    s = dinghy_at_rest(n, heading_rad=rng.uniform(-math.pi, math.pi, n), speed_mps=speed0)
    for t in range(200):
        rudder = rng.uniform(-1.0, 1.0, n) * p.rudder_max_rad
        jib = rng.uniform(-1.0, 1.0, n)
        s, events = step(
            p, s, rudder, rng.uniform(0.0, 1.0, n), wx, wy, dt, round(0.25 / dt), jib_sheet=jib
        )
        state = np.stack([np.asarray(getattr(s, f), dtype=float) for f in s._fields])
        assert np.isfinite(state).all(), t
        assert np.isfinite(events.jibe_severity_rps).all(), t
        assert (np.hypot(s.vx_mps, s.vy_mps) <= 10.0 * (wind + speed0) + 1.0).all(), t
        upright = np.logical_not(s.capsized)
        assert (np.abs(np.where(upright, s.heel_rad, 0.0)) <= p.capsize_heel_rad).all(), t
        assert (np.abs(s.crew_out) <= 1.0).all(), t
    # The same boat on Python floats (math.* raises where NumPy would only warn).
    f = DinghyState(**{k: getattr(s, k)[0].item() for k in s._fields})
    f = f._replace(capsized=False, heel_rad=0.0, heel_rate_rps=0.0)
    for _ in range(50):
        f, _ = step(
            p,
            f,
            0.5 * p.rudder_max_rad,
            0.5,
            float(wx[0]),
            float(wy[0]),
            dt,
            round(0.25 / dt),
            floats,
            jib_sheet=-0.5,
        )
        assert all(math.isfinite(getattr(f, k)) for k in f._fields)


def passive(p: DinghyParams) -> DinghyParams:
    """The boat without its one actuator, the hiking crew (which can add energy)."""
    return replace(p, crew_righting_nm=0.0)


def check_energy_never_grows(p: DinghyParams, s: DinghyState, sheet, dt: float) -> None:
    """No wind, rudder centred: every substep without a sheet-stop impact loses energy.

    (At the stop the boom's momentum is handed to the hull: an inelastic collision seen
    from the hull's frame, which the model does not take, so it can add energy.)"""
    limit = p.sheet_min_rad + sheet * (p.sheet_max_rad - p.sheet_min_rad)
    zero = np.zeros_like(s.x_m)
    energy = mechanical_energy(p, s)
    for k in range(60):
        s, impact, _ = substep(p, s, zero, limit, zero, zero, dt)
        new = mechanical_energy(p, s)
        assert np.isfinite(new).all()
        calm = impact == 0.0
        assert (new[calm] <= energy[calm] * (1.0 + 1e-12) + 1e-300).all(), k
        energy = new


@settings(max_examples=20, deadline=None)
@given(p=dinghy_params(), dt=st.sampled_from([0.05, 0.25]), seed=st.integers(0, 2**16))
def test_implicit_damping_never_creates_energy(p, dt, seed):
    # The implicit parts must dissipate, never create energy, however stiff. Two passive
    # cases cover every implicit term: upright boats at rest in a calm (heel spring and
    # damping, yaw damping, boom air damping: no apparent wind, no sail force), and
    # capsized boats moving (hull drag with waves, centreboard, windage, yaw damping).
    q = passive(p)
    rng = np.random.default_rng(seed)
    n = 8
    sheet = rng.uniform(0.0, 1.0, n)
    limit = q.sheet_min_rad + sheet * (q.sheet_max_rad - q.sheet_min_rad)
    upright = dinghy_at_rest(n)
    upright = upright._replace(
        heel_rad=rng.uniform(-0.9, 0.9, n) * q.capsize_heel_rad,
        heel_rate_rps=rng.uniform(-3.0, 3.0, n),
        yaw_rate_rps=rng.uniform(-2.0, 2.0, n),
        boom_rad=rng.uniform(-1.0, 1.0, n) * limit,
        boom_rate_rps=rng.uniform(-5.0, 5.0, n),
    )
    check_energy_never_grows(q, upright, sheet, dt)
    heading = rng.uniform(-math.pi, math.pi, n)
    moving = dinghy_at_rest(n, heading_rad=heading, speed_mps=rng.uniform(0.0, 15.0, n))
    moving = moving._replace(
        heading_rad=heading + rng.uniform(-math.pi, math.pi, n),  # drifting any way
        yaw_rate_rps=rng.uniform(-2.0, 2.0, n),
        capsized=np.ones(n, dtype=bool),
    )
    check_energy_never_grows(q, moving, sheet, dt)


# -- accepted intervals ------------------------------------------------------------------------


def test_every_field_has_a_documented_interval():
    doc = DinghyParams.__doc__
    for f in fields(DinghyParams):
        if f.name in ("sail_model", "rig"):
            continue
        accepted = accepted_interval(DinghyParams, f.name)
        assert accepted is not None, f.name
        assert accepted.contains(f.default), f.name
        assert f"\n    {f.name} " in doc, f.name  # a row of the table


@pytest.mark.parametrize("name", [f.name for f in FIELDS])
def test_values_outside_an_interval_raise_naming_the_field(name):
    accepted = accepted_interval(DinghyParams, name)
    for outside in (accepted.low - 1e-6 * max(1.0, abs(accepted.low)), accepted.high * 1.001):
        if accepted.contains(outside):
            continue
        with pytest.raises(ValueError, match=rf"^DinghyParams\.{name} "):
            DinghyParams(**{name: outside})
    for end, is_open in ((accepted.low, accepted.low_open), (accepted.high, accepted.high_open)):
        if is_open or any(
            name == small and end >= getattr(DinghyParams, large) for small, large in SHEET_PAIRS
        ):
            continue
        changes = {name: end}
        for small, large in SHEET_PAIRS:
            if name == large and end <= getattr(DinghyParams, small):
                changes[small] = 0.0
        assert getattr(DinghyParams(**changes), name) == end


def test_cross_field_errors_name_the_field():
    with pytest.raises(ValueError, match=r"^DinghyParams\.sheet_min_rad "):
        DinghyParams(sheet_min_rad=0.5, sheet_max_rad=0.5)
    with pytest.raises(ValueError, match=r"^DinghyParams\.jib_sheet_min_rad "):
        DinghyParams(jib_sheet_min_rad=0.5, jib_sheet_max_rad=0.4)
    with pytest.raises(ValueError, match=r"^DinghyParams\.rig "):
        DinghyParams(rig="ketch")
    with pytest.raises(ValueError, match=r"^DinghyParams\.sail_model "):
        DinghyParams(sail_model="wing")
    with pytest.raises(TypeError, match=r"^DinghyParams\.mass_kg "):
        DinghyParams(mass_kg="heavy")
    with pytest.raises(ValueError, match=r"^DinghyParams\.capsize_heel_rad "):
        DinghyParams(capsize_heel_rad=math.pi / 2)
