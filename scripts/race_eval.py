"""Seeded races of scripted boats: how often each boat finishes, its places, fouls, starts
over the line and capsizes (developer tool; the figures of the docs' Race page).

    python scripts/race_eval.py --races 20 --boats 4 --policy racer
    python scripts/race_eval.py --races 20 --boats 4 --policy autopilot

``racer`` is :class:`bbgym.agents.RaceRacer`; ``autopilot`` the sail env's VMG autopilot
alone on the sail env's columns (no start routine, no avoidance, no penalty turns).
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--races", type=int, default=20)
    parser.add_argument("--boats", type=int, default=4)
    parser.add_argument("--policy", choices=["racer", "autopilot"], default="racer")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    print(json.dumps(run(args.races, args.boats, args.policy, args.seed), indent=2))


if __name__ == "__main__":
    main()
