"""Sails that steer (a sloop: main and jib, each force at its centre of effort) and the
foresail trick of seed §9: a boat stopped head to wind gets out by backing the jib."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from bbgym.physics.dinghy import DinghyParams, DinghyState, dinghy_at_rest
from bbgym.physics.sailing import jib_angle, sail_yaw_moment
from bbgym.physics.sailing_step import step

SLOOP = DinghyParams(rig="sloop")
WIND_MPS = 5.0
"""The true wind blows from +x (from 0 rad): toward -x."""
DEG = math.pi / 180.0

Policy = Callable[[float, DinghyState], tuple[float, float, float]]


def true_wind_angle_deg(boat: DinghyState) -> float:
    """Where the wind comes from off the bow, degrees, + from port."""
    return math.degrees(math.remainder(-float(boat.heading_rad[0]), 2.0 * math.pi))


def surge(boat: DinghyState) -> float:
    h = float(boat.heading_rad[0])
    return float(boat.vx_mps[0]) * math.cos(h) + float(boat.vy_mps[0]) * math.sin(h)


def sail(boat: DinghyState, seconds: float, policy: Policy, p: DinghyParams = SLOOP) -> list:
    """Control steps of 0.25 s: ``policy(t, boat) -> (rudder_rad, main_sheet, jib_sheet)``."""
    track = [boat]
    for k in range(round(seconds / 0.25)):
        rudder, main, jib = policy(0.25 * k, boat)
        boat, _ = step(
            p,
            boat,
            np.array([rudder]),
            np.array([main]),
            np.array([-WIND_MPS]),
            np.array([0.0]),
            0.05,
            5,
            np,
            jib_sheet=np.array([jib]),
        )
        track.append(boat)
    return track


def steer_to(twa_deg: float, main: float = 0.15, jib: float = 0.9) -> Policy:
    """Hold a true wind angle with the rudder, main and jib trimmed to leeward."""

    def policy(t: float, boat: DinghyState) -> tuple[float, float, float]:
        twa = true_wind_angle_deg(boat)
        leeward = 1.0 if twa < 0.0 else -1.0  # wind from starboard: the port sheet
        rudder = float(np.clip(0.04 * (twa - twa_deg), -0.5, 0.5))
        return rudder, main, leeward * jib

    return policy


def test_a_cat_rig_keeps_its_bits_whatever_the_jib_sheet() -> None:
    rng = np.random.default_rng(0)
    boat = dinghy_at_rest(5, heading_rad=rng.uniform(-3, 3, 5), speed_mps=rng.uniform(0, 3, 5))
    controls = (
        rng.uniform(-0.5, 0.5, 5),
        rng.uniform(0, 1, 5),
        rng.uniform(-8, 8, 5),
        rng.uniform(-8, 8, 5),
    )
    plain = step(DinghyParams(), boat, *controls, 0.05, 5)
    with_jib = step(DinghyParams(), boat, *controls, 0.05, 5, jib_sheet=rng.uniform(-1, 1, 5))
    for a, b in zip(plain[0], with_jib[0], strict=True):
        assert np.array_equal(a, b)


def test_the_jib_trims_to_leeward_backs_to_windward_and_swings_across_when_released() -> None:
    p = SLOOP
    # wind over the starboard bow, 40 deg off: the air flows aft and to port
    aw_u, aw_v = -math.cos(40 * DEG), math.sin(40 * DEG)
    flow = math.atan2(aw_v, -aw_u)
    assert flow == pytest.approx(40 * DEG)
    # the port (leeward) sheet: fully in holds it at 10 deg, eased it luffs along the flow
    assert jib_angle(p, 1.0, aw_u, aw_v) == pytest.approx(p.jib_sheet_min_rad)
    assert jib_angle(p, 0.2, aw_u, aw_v) == pytest.approx(flow)
    # the starboard (windward) sheet pulled hard: backed at 10 deg to starboard
    assert jib_angle(p, -1.0, aw_u, aw_v) == pytest.approx(-p.jib_sheet_min_rad)
    # the starboard sheet eased: the clew swings across to port, up to 2 min - limit
    released = jib_angle(p, -0.1, aw_u, aw_v)
    limit = p.jib_sheet_max_rad - 0.1 * (p.jib_sheet_max_rad - p.jib_sheet_min_rad)
    assert released == pytest.approx(min(flow, limit - 2 * p.jib_sheet_min_rad))
    assert released > 0.0


def test_sails_steer_a_trimmed_main_gives_weather_helm_and_the_jib_lee_helm() -> None:
    """Close-hauled with the wind from starboard (the sails to port, their side force to
    port, drive ahead): the main, its centre of effort aft of the centreboard, turns the
    bow to starboard, into the wind; the jib, ahead of it, turns it to port, away."""
    drive, side = 40.0, 120.0  # N: forces of a sail close-hauled, side force to port
    main = sail_yaw_moment(
        SLOOP.mast_ahead_m, SLOOP.sail_ce_aft_m, SLOOP.sail_ce_height_m, 10 * DEG, 0.0, drive, side
    )
    jib = sail_yaw_moment(
        SLOOP.jib_tack_ahead_m,
        SLOOP.jib_ce_aft_m,
        SLOOP.jib_ce_height_m,
        10 * DEG,
        0.0,
        drive,
        side,
    )
    assert main < 0.0 < jib  # clockwise (bow to starboard, to windward) and the other way
    # heeled to port (the low side), the centre of effort moves to leeward: more weather helm
    heeled = sail_yaw_moment(
        SLOOP.mast_ahead_m,
        SLOOP.sail_ce_aft_m,
        SLOOP.sail_ce_height_m,
        10 * DEG,
        math.sin(20 * DEG),
        drive,
        side,
    )
    assert heeled < main

    # Sailing: close-hauled at 50 deg on port tack, then the rudder let go. Trimmed, the
    # boat rounds up into the wind; the main eased (luffing), the jib bears it away.
    boat = sail(dinghy_at_rest(1, heading_rad=-50 * DEG, speed_mps=2.0), 30.0, steer_to(50.0))[-1]
    assert true_wind_angle_deg(boat) == pytest.approx(50.0, abs=3.0)
    assert surge(boat) > 1.8
    trimmed = sail(boat, 4.0, lambda t, b: (0.0, 0.15, -0.9))[-1]
    eased = sail(boat, 4.0, lambda t, b: (0.0, 1.0, -0.9))[-1]
    assert true_wind_angle_deg(trimmed) < 40.0
    assert true_wind_angle_deg(eased) > 55.0


IRONS = dinghy_at_rest(1, heading_rad=0.02)
"""Stopped head to wind, the wind 1 deg on the starboard bow."""


@pytest.mark.parametrize("rudder", [0.5, -0.5])
@pytest.mark.parametrize("jib", [0.9, -0.9, 0.0])
def test_in_irons_the_rudder_alone_cannot_turn_the_boat(rudder: float, jib: float) -> None:
    """Sails sheeted in (as after a failed tack), the rudder hard over either way: 30 s
    later the boat is still within 20 deg of the wind and has made no way ahead."""
    track = sail(IRONS, 30.0, lambda t, b: (rudder, 0.0, jib))
    assert max(abs(true_wind_angle_deg(b)) for b in track) < 20.0
    assert max(surge(b) for b in track) < 0.1


def out_of_irons(jib_at_first: float) -> Policy:
    """Main eased, rudder centred, the jib as given until the bow is 45 deg off the wind;
    then the jib trimmed to leeward (the port sheet) and the main half out; moving ahead,
    trim the main and sail 60 deg off the wind."""
    phase = {"off": False, "moving": False}

    def policy(t: float, boat: DinghyState) -> tuple[float, float, float]:
        twa = true_wind_angle_deg(boat)
        phase["off"] = phase["off"] or abs(twa) >= 45.0
        phase["moving"] = phase["moving"] or (phase["off"] and surge(boat) > 0.8)
        if phase["moving"]:
            return steer_to(-60.0, main=0.35)(t, boat)
        if phase["off"]:
            return 0.0, 0.8, 0.9
        return 0.0, 1.0, jib_at_first

    return policy


def test_backing_the_jib_gets_a_boat_out_of_irons() -> None:
    """Seed §9's trick: hold the jib to windward (the starboard sheet: the wind is on the
    starboard bow) and the wind pushes the bow off to port: 45 deg off within 10 s, and
    within 20 s the boat sails on starboard tack. Its sheets let go instead, the same boat
    with the same rudder and main is still head to wind after 20 s."""
    track = sail(IRONS, 20.0, out_of_irons(-1.0))
    twa = [true_wind_angle_deg(b) for b in track]
    assert min(twa[:40]) <= -45.0  # off to port within 10 s
    assert surge(track[-1]) > 1.0
    assert -80.0 < twa[-1] < -45.0  # on starboard tack (the wind from starboard)
    released = sail(IRONS, 20.0, out_of_irons(0.0))
    assert max(abs(true_wind_angle_deg(b)) for b in released) < 20.0
    assert max(surge(b) for b in released) < 0.1


def test_releasing_the_jib_as_the_bow_passes_the_wind_loses_less_speed() -> None:
    """A tack from port to starboard. Released as the bow passes head to wind (the new
    sheet pulled), the jib draws on the new side at once; kept on the old sheet for 6 s,
    it is backed and holds the boat back: 10 s into the tack the boat is slower, and it
    makes less ground to windward in 20 s."""
    start = sail(dinghy_at_rest(1, heading_rad=-50 * DEG, speed_mps=2.0), 40.0, steer_to(50.0))
    boat = start[-1]

    def tack(keep_s: float) -> list:
        through = {"t": None}

        def policy(t: float, b: DinghyState) -> tuple[float, float, float]:
            if through["t"] is None and true_wind_angle_deg(b) < 0.0:
                through["t"] = t  # head to wind
            if through["t"] is not None and t - through["t"] >= keep_s:
                return steer_to(-50.0)(t, b)
            return 0.5, 0.15, -0.9  # helm over, the old (starboard) jib sheet still in

        return sail(boat, 20.0, policy)

    released, kept = tack(0.0), tack(6.0)
    assert surge(released[40]) > 1.05 * surge(kept[40])
    gained = [track[-1].x_m[0] - boat.x_m[0] for track in (released, kept)]  # to windward
    assert gained[0] > gained[1] + 1.0
