"""A simple scripted helmsman for BeachballSail-v0 that sees only the observation vector.

Steering: head for the mark unless it lies in a "no-go" sector, then sail the edge of the
sector instead and switch sides on the layline:

* mark within ``upwind_angle`` of the true wind (upwind): sail close-hauled,
  ``upwind_angle`` off the wind, and tack when the mark crosses the other tack's
  close-hauled course (the layline);
* mark within ``downwind_angle`` of dead downwind: sail a broad reach,
  ``180 deg - downwind_angle`` off the wind, and jibe on the other gybe's layline;
* otherwise steer straight at the mark.

The side of the sector (tack or gybe) is kept per env and changes only when the mark has
crossed the whole sector, which gives the hysteresis that stops the boat from tacking every
step. Rudder ``clip(k * heading_error, -1, 1)`` (sign reversed while the boat moves
astern, e.g. stuck in irons after a slow tack, where the rudder acts the other way).

Sheet: boom about ``|AWA| - 12 deg`` off the centreline (clipped to [4, 85] deg), eased
further by ``3 x (heel - 25 deg)`` when the boat heels past 25 deg. The offset comes from
the polar (``bbgym polar``): the best trim sits 10-14 deg inside the apparent wind,
just under the lift model's 16 deg stall; a 20 deg offset stalls the sail close-hauled,
and the 50 seeded episodes then take about 60 % longer.
"""

from __future__ import annotations

import math

import numpy as np

from bbgym.physics.common import wrap_angle
from bbgym.physics.dinghy import DinghyParams

# Observation indices (see the BeachballSail-v0 docstring).
OBS_AWA_COS, OBS_AWA_SIN = 0, 1
OBS_TWA_COS, OBS_TWA_SIN = 3, 4
OBS_SURGE = 6
OBS_HEEL = 9
OBS_MARK_COS, OBS_MARK_SIN = 12, 13
OBS_SIZE = 16
OBS_SIZES = (16, 23)
"""v0 and v1's observation, and v2's (the same 16 columns, then the jib and the sea)."""


def as_batch(obs: np.ndarray) -> tuple[np.ndarray, bool]:
    """``(batch of float64 observations (N, 16 or 23), whether a single one was given)``."""
    o = np.asarray(obs, dtype=np.float64)
    single = o.ndim == 1
    o = np.atleast_2d(o)
    if o.ndim != 2 or o.shape[1] not in OBS_SIZES:
        raise ValueError(f"obs must have shape (16,) or (23,), or (N, 16 or 23), got {o.shape}")
    return o, single


def trimmed_jib(o: np.ndarray, sheet: np.ndarray) -> np.ndarray:
    """A sloop's jib sheet trimmed with the main, as the polar sails it: the leeward sheet
    (where the air goes: starboard, -, with the wind from port) pulled as far as the main
    sheet is in (``sheet`` -1 in .. +1 out)."""
    awa = np.arctan2(o[:, OBS_AWA_SIN], o[:, OBS_AWA_COS])
    leeward = np.where(awa > 0.0, -1.0, 1.0)
    return leeward * (1.0 - 0.5 * (sheet + 1.0))


class SimpleSailController:
    """Scripted controller: ``controller(obs) -> action``.

    Accepts one observation of shape ``(16,)`` (returns ``(2,)``) or a batch ``(N, 16)``
    (returns ``(N, 2)``), both float32. Keeps the tack/gybe side of each env between calls;
    call :meth:`reset` at the start of an episode (``reset(i)`` for one env of a batch).
    """

    def __init__(
        self,
        upwind_angle_deg: float = 45.0,
        downwind_angle_deg: float = 30.0,
        rudder_gain: float = 2.0,
        trim_offset_deg: float = 12.0,
        tie_deg: float = 10.0,
        ease_heel_deg: float = 25.0,
        ease_gain: float = 3.0,
        dinghy: DinghyParams | None = None,
    ) -> None:
        self.upwind_angle = math.radians(upwind_angle_deg)
        self.downwind_angle = math.radians(downwind_angle_deg)
        self.rudder_gain = float(rudder_gain)
        self.trim_offset = math.radians(trim_offset_deg)
        self.tie = math.radians(tie_deg)
        self.ease_heel = math.radians(ease_heel_deg)
        self.ease_gain = float(ease_gain)
        # The boat's documented limits (the env's `dinghy` argument): heel is observed as a
        # fraction of the capsize heel, the sheet maps to the boom's range.
        dinghy = dinghy or DinghyParams()
        self.capsize_heel = dinghy.capsize_heel_rad
        self.boom_min, self.boom_max = dinghy.sheet_min_rad, dinghy.sheet_max_rad
        self.sloop = dinghy.rig == "sloop"  # a sloop's jib is trimmed with the main
        # Side of the no-go sector per env: +1 / -1, 0 = not chosen yet.
        self._upwind_side = np.zeros(0)
        self._downwind_side = np.zeros(0)

    def reset(self, index: int | np.ndarray | None = None) -> None:
        """Forget the tack/gybe side of every env, or only of ``index``."""
        if index is None:
            self._upwind_side = np.zeros(0)
            self._downwind_side = np.zeros(0)
        elif self._upwind_side.size:
            self._upwind_side[index] = 0.0
            self._downwind_side[index] = 0.0

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        o, single = as_batch(obs)
        columns = [self._rudder(o), self._sheet(o)]
        if self.sloop:
            columns.append(trimmed_jib(o, columns[1]))
        actions = np.stack(columns, axis=1).astype(np.float32)
        return actions[0] if single else actions

    def desired_heading(self, obs: np.ndarray) -> np.ndarray:
        """Desired heading relative to the bow, ``(N,)`` rad, + = to port.

        Updates the remembered tack/gybe sides (a batch of a new size starts afresh).
        """
        o = np.atleast_2d(np.asarray(obs, dtype=np.float64))
        if self._upwind_side.shape != (o.shape[0],):
            self._upwind_side = np.zeros(o.shape[0])
            self._downwind_side = np.zeros(o.shape[0])
        twa = np.arctan2(o[:, OBS_TWA_SIN], o[:, OBS_TWA_COS])
        bearing = np.arctan2(o[:, OBS_MARK_SIN], o[:, OBS_MARK_COS])
        # Angles measured from the direction the true wind comes from (+ = counterclockwise).
        mark = wrap_angle(bearing - twa)
        bow = wrap_angle(-twa)
        mark_downwind = wrap_angle(mark - np.pi)
        bow_downwind = wrap_angle(bow - np.pi)
        self._upwind_side = self._choose_side(self._upwind_side, mark, bow, self.upwind_angle)
        self._downwind_side = self._choose_side(
            self._downwind_side, mark_downwind, bow_downwind, self.downwind_angle
        )
        target = mark.copy()
        upwind = np.abs(mark) < self.upwind_angle
        downwind = np.abs(mark_downwind) < self.downwind_angle
        target = np.where(upwind, self._upwind_side * self.upwind_angle, target)
        target = np.where(downwind, np.pi + self._downwind_side * self.downwind_angle, target)
        return wrap_angle(target + twa)

    def _choose_side(
        self, side: np.ndarray, mark: np.ndarray, bow: np.ndarray, half_width: float
    ) -> np.ndarray:
        """Side of a no-go sector of ``half_width`` around angle 0 (the sector's axis).

        Outside the sector the side is where the mark is (the boat heads for it). Inside, a
        side already chosen is kept: it changes only once the mark has crossed the whole
        sector (the other side's course points at or past the mark). A first choice takes
        the side closer to the mark, or the boat's current side when the mark is near the
        axis (within ``tie``).
        """
        outside = np.abs(mark) >= half_width
        first = np.where(np.abs(mark) > self.tie, np.sign(mark), np.sign(bow))
        first = np.where(first == 0.0, 1.0, first)
        return np.where(outside, np.where(mark >= 0.0, 1.0, -1.0), np.where(side == 0, first, side))

    def _rudder(self, o: np.ndarray) -> np.ndarray:
        error = self.desired_heading(o)
        # Going astern (stuck in irons) the rudder acts reversed: steer the other way.
        astern = o[:, OBS_SURGE] < 0.0
        return np.clip(np.where(astern, -1.0, 1.0) * self.rudder_gain * error, -1.0, 1.0)

    def _sheet(self, o: np.ndarray) -> np.ndarray:
        awa = np.abs(np.arctan2(o[:, OBS_AWA_SIN], o[:, OBS_AWA_COS]))
        heel = np.abs(o[:, OBS_HEEL]) * self.capsize_heel
        # Ease the sheet (spill wind) when the boat heels too far, as a helmsman would.
        ease = self.ease_gain * np.maximum(heel - self.ease_heel, 0.0)
        boom = np.clip(awa - self.trim_offset + ease, self.boom_min, self.boom_max)
        return -1.0 + 2.0 * (boom - self.boom_min) / (self.boom_max - self.boom_min)
