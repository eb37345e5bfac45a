"""BeachballSail-v2 never changes behaviour: the single and native vector env replay the
observations, rewards and ends recorded when it was registered (fixed seeds and random
actions: the jib backed and trimmed, the current and waves drawn, autoresets included).
Regenerate only for a new env version:
``PYTHONPATH=tests python tests/sail/test_golden_v2.py --write``."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from test_golden_v0 import STEPS, check_replay, record

GOLDEN = Path(__file__).parents[1] / "data" / "golden_v2.npz"
ENV_IDS = ("BeachballSail-v2",)
STEPS["BeachballSail-v2"] = 120


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_replays_recorded_v2_episodes(env_id: str) -> None:
    recorded = check_replay(GOLDEN, env_id)["vector"]
    # the episodes have the sea and the jib in them
    assert np.abs(recorded[..., 16]).max() > 0.1  # jib angle
    assert np.abs(recorded[..., 19]).max() > 0.3  # the sea's height


if __name__ == "__main__" and "--write" in sys.argv:
    data = {f"{e}/{k}": v for e in ENV_IDS for k, v in record(e).items()}
    np.savez_compressed(GOLDEN, **data)
    print({k: v.shape for k, v in data.items()})
