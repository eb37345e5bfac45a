"""Seeded races of scripted boats: how often each boat finishes, its places, fouls, starts
over the line and capsizes (developer tool; the figures of the docs' Race page).

    python scripts/race_eval.py --races 20 --boats 4 --policy racer
    python scripts/race_eval.py --races 20 --boats 4 --policy autopilot
    python scripts/race_eval.py --starts --races 40 --seed 1000
    python scripts/race_eval.py --match --start-margin 40 --races 100 --seed 100000
    python scripts/race_eval.py --match --tack-cone 30 --races 100 --seed 100000

``racer`` is :class:`bbgym.agents.RaceRacer`; ``autopilot`` the sail env's VMG autopilot
alone on the sail env's columns (no start routine, no avoidance, no penalty turns).
``--starts``: how the racers start (racing four-boat races at once in the fleet): the share
over the line 10 s after the gun, their speed at the gun, and how the time each crossed
the line goes with the time it finished. ``--match``: racers of another ``--start-margin``,
``--avoid`` distance or ``--tack-cone`` (playing the shifts upwind) in the learners' places
against standard racers (:func:`bbgym.envs.race.match.play_matches`): the pairings they
finish ahead in.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
from bbgym.agents import RaceRacer

from bbgym.envs.race import parallel_env


class AutopilotAlone(RaceRacer):
    """The sail env's VMG autopilot on the sail env's columns, nothing else: no start
    routine, no avoidance, no penalty turns."""

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        return self.pilot(np.asarray(obs)[..., : self.sail_size])


def policy_for(name: str, env) -> RaceRacer:
    return (RaceRacer if name == "racer" else AutopilotAlone).for_env(env)


def run(races: int, boats: int, policy: str, seed: int = 0, **kwargs) -> dict:
    env = parallel_env(num_boats=boats, **kwargs)
    act = policy_for(policy, env)
    stats = {k: [] for k in ("finished", "place", "fouls", "ocs", "capsized", "finish_time")}
    steps, began = 0, time.perf_counter()
    for race in range(races):
        obs, _ = env.reset(seed=seed + race)
        act.reset()
        last = {}
        was_ocs = dict.fromkeys(env.agents, False)
        while env.agents:
            obs, _, _, _, infos = env.step(act.actions(obs, env.agents))
            steps += 1
            for agent, info in infos.items():
                last[agent] = info
                was_ocs[agent] |= bool(info["ocs"])
        for agent, info in last.items():
            stats["finished"].append(bool(info["finished"]))
            stats["place"].append(int(info["place"]))
            stats["fouls"].append(int(info["fouls"]))
            stats["ocs"].append(was_ocs[agent])
            stats["capsized"].append(bool(info["capsized"]))
            if info["finished"]:
                stats["finish_time"].append(float(info["finish_time"]))
    wall = time.perf_counter() - began
    return {
        "policy": policy,
        "races": races,
        "boats": boats,
        "finished": float(np.mean(stats["finished"])),
        "fouls_per_boat": float(np.mean(stats["fouls"])),
        "over_early": float(np.mean(stats["ocs"])),
        "capsized": float(np.mean(stats["capsized"])),
        "mean_finish_time_s": float(np.mean(stats["finish_time"]))
        if stats["finish_time"]
        else None,
        "steps_per_s": steps / wall,
    }


def starts(races: int, seed: int) -> dict:
    """How scripted racers start, over ``races`` four-boat races run at once."""
    from bbgym.envs.race import BeachballRaceFleetEnv

    fleet = BeachballRaceFleetEnv(races)
    racer = RaceRacer.for_env(fleet)
    obs, _ = fleet.reset(seed=seed)
    shape = (races, fleet.num_boats)
    crossed, finished = np.full(shape, np.nan), np.full(shape, np.nan)
    done = np.zeros(races, dtype=bool)
    at_gun = after_10s = None
    while not done.all():
        obs, *_ = fleet.step(racer(obs))
        state = fleet.state
        clock = np.repeat(state.clock_s[:, None], fleet.num_boats, axis=1)
        new = (state.leg > 0) & np.isnan(crossed) & ~done[:, None]
        crossed[new] = clock[new]
        end = np.isfinite(state.crossed_s) & np.isnan(finished) & ~done[:, None]
        finished[end] = state.crossed_s[end]
        if at_gun is None and state.clock_s[0] >= 0.0:
            boat = state.boats.boat
            at_gun = float(np.mean(np.hypot(boat.vx_mps, boat.vy_mps)))
        if after_10s is None and state.clock_s[0] >= 10.0:
            after_10s = float(np.mean(state.leg > 0))
        done |= fleet.races_ended
    both = np.isfinite(crossed) & np.isfinite(finished)
    return {
        "races": races,
        "seed": seed,
        "speed_at_gun_mps": at_gun,
        "over_the_line_10s_after_gun": after_10s,
        "crossed_s_after_gun_median": float(np.nanmedian(crossed)),
        "crossed_finished_correlation": float(np.corrcoef(crossed[both], finished[both])[0, 1]),
    }


def match(races: int, seed: int, **racer: float | None) -> dict:
    """Racers with the settings ``racer`` (:meth:`RaceRacer.for_env`'s) in the learners'
    places against standard racers."""
    from bbgym.envs.race.match import BeachballRaceMatchEnv, play_matches

    result = play_matches(
        RaceRacer.for_env(BeachballRaceMatchEnv(1).fleet, **racer), num_races=races, seed=seed
    )
    return result._asdict() | {"ahead_share": result.ahead_share} | racer


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--races", type=int, default=20)
    parser.add_argument("--boats", type=int, default=4)
    parser.add_argument("--policy", choices=["racer", "autopilot"], default="racer")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--starts", action="store_true", help="how the racers start")
    parser.add_argument(
        "--match", action="store_true", help="racers of other settings against standard racers"
    )
    parser.add_argument("--start-margin", type=float, default=4.0)
    parser.add_argument("--avoid", type=float, default=10.0, help="the racer's avoid_m")
    parser.add_argument(
        "--tack-cone", type=float, default=None, help="the racer's tack_cone_deg (default: none)"
    )
    args = parser.parse_args()
    if args.starts:
        result = starts(args.races, args.seed)
    elif args.match:
        result = match(
            args.races,
            args.seed,
            start_margin_s=args.start_margin,
            avoid_m=args.avoid,
            tack_cone_deg=args.tack_cone,
        )
    else:
        result = run(args.races, args.boats, args.policy, args.seed)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
