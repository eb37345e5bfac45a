"""BeachballTopple-v2 (the interval in RK4 steps with the ball's events located) never
changes behaviour: the single and native vector env replay the observations, rewards and
ends recorded when it was registered (fixed seeds and random actions, gusts on, autoresets
included). Regenerate only for a new env version:
``PYTHONPATH=tests python tests/topple/test_golden_topple_v2.py --write``."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from test_golden_v0 import STEPS, check_replay, record

GOLDEN = Path(__file__).parents[1] / "data" / "golden_topple_v2.npz"
ENV_ID = "BeachballTopple-v2"
STEPS[ENV_ID] = 24
LAST_HIT = 8
"""The observation's column saying whether the last throw hit the wall (1), missed (-1)."""


def test_replays_recorded_topple_v2_episodes() -> None:
    recorded = check_replay(GOLDEN, ENV_ID)
    for kind in ("single", "vector"):
        last_hit = recorded[kind][..., LAST_HIT]
        assert (last_hit == 1.0).any() and (last_hit == -1.0).any(), kind  # hits and misses
    assert recorded["vector"][..., -1].sum() >= 3  # autoresets inside the replay


if __name__ == "__main__" and "--write" in sys.argv:
    data = {f"{ENV_ID}/{k}": v for k, v in record(ENV_ID).items()}
    np.savez_compressed(GOLDEN, **data)
    print({k: v.shape for k, v in data.items()})
