"""The sailing physics and the sailing task core keep the array-API contract: run on
``array_api_strict`` (the standard and nothing more) and on torch through
array-api-compat, they give NumPy's numbers. A non-standard name, a bool used as a
number or two Python scalars in ``where`` raise there, so these tests fail if one creeps
back."""

from __future__ import annotations

import numpy as np
import pytest

from bbgym import backends
from bbgym.envs.functional import InitialNoise, VectorStep, tree_map
from bbgym.envs.sail import SailTask
from bbgym.physics import sailing, sailing_step
from bbgym.physics.calibration import calibrated_sloop
from bbgym.physics.dinghy import SAIL_MODELS, DinghyParams, dinghy_at_rest
from bbgym.physics.water import Sea, WaterParams, sea_at_start
from bbgym.physics.wind import GustParams, GustState, gust_init, gust_step, wind_vector

strict = pytest.importorskip("array_api_strict")
N = 24


def namespaces() -> list:
    out = [pytest.param(strict, id="array_api_strict")]
    try:
        import torch  # noqa: F401

        out.append(pytest.param(backends.torch_namespace(), id="torch"))
    except ImportError:
        pass
    return out


def to_xp(tree, xp):
    if xp is strict:
        return tree_map(lambda a: strict.asarray(np.asarray(a)), tree)
    import torch

    return tree_map(lambda a: torch.as_tensor(np.asarray(a)), tree)


def same(ref, got, tol: float = 1e-12) -> None:
    ref_leaves, got_leaves = [], []
    tree_map(ref_leaves.append, ref)
    tree_map(got_leaves.append, got)
    assert len(ref_leaves) == len(got_leaves)
    for r, g in zip(ref_leaves, got_leaves, strict=True):
        g = np.asarray(backends.to_numpy(g))
        assert g.dtype == np.asarray(r).dtype, (g.dtype, np.asarray(r).dtype)
        np.testing.assert_allclose(g, r, rtol=tol, atol=tol)


def boats(seed: int = 0):
    """Varied boats: fast, at rest, heeled, booms both sides, a capsized one."""
    rng = np.random.default_rng(seed)
    s = dinghy_at_rest(
        N,
        heading_rad=rng.uniform(-3, 3, N),
        speed_mps=rng.uniform(0, 4, N),
        boom_rad=rng.uniform(-1.2, 1.2, N),
    )
    capsized = np.zeros(N, dtype=bool)
    capsized[-1] = True
    s = s._replace(
        heel_rad=rng.uniform(-0.6, 0.6, N),
        heel_rate_rps=rng.uniform(-1, 1, N),
        yaw_rate_rps=rng.uniform(-0.5, 0.5, N),
        boom_rate_rps=rng.uniform(-3, 3, N),
        crew_out=rng.uniform(-1, 1, N),
        capsized=capsized,
    )
    controls = (
        rng.uniform(-0.5, 0.5, N),
        rng.uniform(0, 1, N),
        rng.uniform(-9, 9, N),
        rng.uniform(-9, 9, N),
    )
    return s, controls


@pytest.mark.parametrize("xp", namespaces())
@pytest.mark.parametrize("sail_model", SAIL_MODELS)
def test_sailing_step_and_energy(xp, sail_model: str) -> None:
    # (the cambered sail on a planing hull, so both branches run)
    planing = 3.0 if sail_model == "cambered" else 0.0
    p = DinghyParams(sail_model=sail_model, hull_planing_speed_mps=planing)
    s, (rudder, sheet, wx, wy) = boats()
    ref = sailing_step.step(p, s, rudder, sheet, wx, wy, 0.05, 5, np)
    got = sailing_step.step(p, to_xp(s, xp), *to_xp((rudder, sheet, wx, wy), xp), 0.05, 5, xp)
    same(ref, got)
    same(sailing.mechanical_energy(p, ref[0], np), sailing.mechanical_energy(p, got[0], xp))
    aw = (wx - ref[0].vx_mps, wy - ref[0].vy_mps)
    same(sailing.sail_force(p, s, *aw, np), sailing.sail_force(p, to_xp(s, xp), *to_xp(aw, xp), xp))


@pytest.mark.parametrize("xp", namespaces())
def test_sloop_step(xp) -> None:
    """Main and jib, the jib's sheets pulled either side, eased and backed: the calibrated
    sloop (cambered sails, planing hull)."""
    p = calibrated_sloop()
    s, controls = boats(6)
    jib = np.random.default_rng(7).uniform(-1, 1, N)
    ref = sailing_step.step(p, s, *controls, 0.05, 5, np, jib_sheet=jib)
    got = sailing_step.step(
        p, to_xp(s, xp), *to_xp(controls, xp), 0.05, 5, xp, jib_sheet=to_xp(jib, xp)
    )
    same(ref, got)


@pytest.mark.parametrize("xp", namespaces())
def test_sailing_step_in_moving_water(xp) -> None:
    """A sheared current and a three-component sea, each env its own draws."""
    water = WaterParams(
        current_variation=0.4,
        current_variation_length_m=80.0,
        wave_amplitude_m=0.4,
        wave_components=3,
        wave_spread_rad=0.5,
    )
    rng = np.random.default_rng(4)
    sea = sea_at_start(
        water,
        rng.uniform(0, 1.5, N),
        rng.uniform(-3, 3, N),
        rng.uniform(-3, 3, N),
        rng.uniform(size=(3, N)),
    )
    sea = sea._replace(time_s=rng.uniform(0, 100, N))
    s, controls = boats(5)
    ref = sailing_step.step(DinghyParams(), s, *controls, 0.05, 5, np, water, sea)
    got = sailing_step.step(
        DinghyParams(),
        to_xp(s, xp),
        *to_xp(controls, xp),
        0.05,
        5,
        xp,
        water,
        Sea(*to_xp(tuple(sea), xp)),
    )
    same(ref, got)


@pytest.mark.parametrize("xp", namespaces())
def test_gusts(xp) -> None:
    g = GustParams()
    rng = np.random.default_rng(1)
    noise, enabled = list(rng.standard_normal((2, N))), rng.uniform(size=N) < 0.5
    ref = gust_init(g, noise, enabled, np)
    got = gust_init(g, to_xp(noise, xp), to_xp(enabled, xp), xp)
    same(ref, got)
    ref2 = gust_step(ref, g, 0.25, noise[::-1], enabled, np)
    same(ref2, gust_step(got, g, 0.25, to_xp(noise[::-1], xp), to_xp(enabled, xp), xp))
    speed, wind_from = rng.uniform(0, 9, N), rng.uniform(-3, 3, N)
    same(
        wind_vector(speed, wind_from, ref2, np),
        wind_vector(*to_xp((speed, wind_from), xp), GustState(*to_xp(tuple(ref2), xp)), xp),
    )


@pytest.mark.parametrize("xp", namespaces())
def test_sail_task_core(xp) -> None:
    """initial, transition (with its chunks), measure, observation, info and the fused
    vector step with autoreset, on the same draws."""
    task = SailTask()
    rng = np.random.default_rng(2)
    noise = InitialNoise(list(rng.uniform(size=(6, N))), list(rng.standard_normal((2, N))), [])
    ref = task.initial(noise, {}, np)
    got = task.initial(to_xp(noise, xp), {}, xp)
    same(ref, got)
    pinned = {"wind_speed": 4.0, "mark": (30.0, -20.0), "gusts": False}
    same(task.initial(noise, pinned, np), task.initial(to_xp(noise, xp), pinned, xp))
    action, step_noise = rng.uniform(-1, 1, (N, 2)), list(rng.standard_normal((2, N)))
    ref1, ref_events = task.transition(ref, action, step_noise, np)
    got1, got_events = task.transition(got, to_xp(action, xp), to_xp(step_noise, xp), xp)
    same((ref1, ref_events), (got1, got_events))
    m_ref, m_got = task.measure(ref1, np), task.measure(got1, xp)
    same(m_ref, m_got)
    same(task.observation(ref1, m_ref, np), task.observation(got1, m_got, xp))
    same(task.info(ref1, m_ref, np), task.info(got1, m_got, xp))
    same(
        (task.reward(ref1, np), task.terminal(ref1, np)),
        (task.reward(got1, xp), task.terminal(got1, xp)),
    )

    keys = backends.env_keys(0, N, np)
    counter = np.arange(N, dtype=np.int64)
    steps = np.arange(N, dtype=np.int64) * 100
    restarting = rng.uniform(size=N) < 0.3
    dtype = xp.float64
    ref_out = VectorStep(task, 1000, np, np.float64)(ref1, action, keys, counter, steps, restarting)
    got_out = VectorStep(task, 1000, xp, dtype)(
        got1, *to_xp((action, keys, counter, steps, restarting), xp)
    )
    same(ref_out, got_out)
