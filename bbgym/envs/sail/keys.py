"""The sailing envs from the keyboard (``bbgym play``): rudder while held, sheet stepped."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

# pygame as bbgym.keyboard imports it (quietly, and only where the render extra is in)
from bbgym.keyboard import KeyboardWrapper, pygame, show_status

SHEET_STEP = 0.05
"""Sheet change per frame while UP or DOWN is held (full range -1..1 in 40 frames)."""
INITIAL_SHEET = 0.0

# Sail command [rudder, sheet change]: rudder +1 turns to port; sheet -1 hauls in.
SAIL_KEYS: dict[int, tuple[float, ...]] = {
    pygame.K_LEFT: (1.0, 0.0),
    pygame.K_RIGHT: (-1.0, 0.0),
    pygame.K_UP: (0.0, -1.0),
    pygame.K_DOWN: (0.0, 1.0),
}


class SailKeys(KeyboardWrapper):
    """A sailing env from the keys. Command ``[rudder, sheet change]``: the rudder is
    passed on as it is; the sheet moves by ``sheet_step`` times the change per step and
    stays there (the ``sheet`` attribute, set to ``initial_sheet`` at every reset)."""

    key_effects = SAIL_KEYS

    def __init__(
        self,
        env: gym.Env,
        seed: int | None = None,
        sheet_step: float = SHEET_STEP,
        initial_sheet: float = INITIAL_SHEET,
    ) -> None:
        super().__init__(env, seed)
        self.sheet_step, self.initial_sheet = sheet_step, initial_sheet
        self.sheet = initial_sheet

    def reset(self, **kwargs: Any) -> Any:
        self.sheet = self.initial_sheet
        return super().reset(**kwargs)

    def action(self, command: np.ndarray) -> np.ndarray:
        """The env action for ``command``; moves the sheet."""
        rudder = float(np.clip(command[0], -1.0, 1.0))
        sheet = float(np.clip(self.sheet + self.sheet_step * command[1], -1.0, 1.0))
        if sheet != self.sheet:
            show_status(f"sheet {sheet:+.2f} (-1 in, +1 out)")
        self.sheet = sheet
        return np.array([rudder, sheet], dtype=np.float32)

    def step(self, command: np.ndarray) -> Any:
        return self.env.step(self.action(command))
