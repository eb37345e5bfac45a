"""BeachballThrow-v1 and BeachballCurve-v2 (the RK4 flight with event location) never
change behaviour: the single and native vector env replay the observations, rewards and
ends recorded when they were registered (fixed seeds and random actions, gusts on,
autoresets included). Regenerate only for a new env version:
``PYTHONPATH=tests python tests/throw/test_golden_throw_v1.py --write``."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from test_golden_v0 import STEPS, check_replay, record

GOLDEN = Path(__file__).parents[1] / "data" / "golden_throw_v1.npz"
ENV_IDS = ("BeachballThrow-v1", "BeachballCurve-v2")
STEPS.update({"BeachballThrow-v1": 24, "BeachballCurve-v2": 24})


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_replays_recorded_rk4_flight_episodes(env_id: str) -> None:
    recorded = check_replay(GOLDEN, env_id)
    ends = recorded["vector"][..., -1]
    assert ends.sum() >= 3  # autoresets inside the replay
    # the throws landed (the landing offset from the target is columns 4 and 5)
    assert np.abs(recorded["vector"][..., 4:6]).max() > 0.1


if __name__ == "__main__" and "--write" in sys.argv:
    data = {f"{e}/{k}": v for e in ENV_IDS for k, v in record(e).items()}
    np.savez_compressed(GOLDEN, **data)
    print({k: v.shape for k, v in data.items()})
