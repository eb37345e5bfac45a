"""Right of way, simplified from World Sailing's Racing Rules of Sailing, Part 2: who must
keep clear of whom, from the geometry of every pair of boats.

- **Rule 10, on opposite tacks**: a boat on port tack (the wind over her port side) keeps
  clear of one on starboard tack.
- **Rule 12, on the same tack, not overlapped**: a boat clear astern keeps clear of the
  boat clear ahead. A boat is clear astern of another when her hull is behind a line
  abeam from the other's aftermost point; neither clear astern, they are overlapped.
- **Rule 11, on the same tack, overlapped**: the windward boat keeps clear of the leeward
  one (leeward: on the side away from the wind of the other boat).
- **Rule 18, mark room (simplified)**: two boats on the same tack, overlapped, both within
  the zone of the mark they are both sailing to (the windward mark or the gate, a radius
  of three hull lengths): the outside boat (further from the mark) keeps clear of the
  inside one, whichever is to windward.

A boat that must keep clear and comes within ``keep_clear_m`` of the other's hull (or
touches it) has fouled her: a new foul each time such an encounter begins. Pure functions
over ``(races, K)`` arrays, pairs ``(races, K, K)``: ``[.., i, j]`` is boat ``i`` against
boat ``j``.
"""

from __future__ import annotations

from typing import Any

from bbgym.envs.race import course as rc
from bbgym.physics.namespace import Array

ZONE_HULL_LENGTHS = 3.0
"""The zone round a mark: three hull lengths (the rules' default)."""


def on_port_tack(wind_from_rad: Array, heading_rad: Array, xp: Any) -> Array:
    """The wind comes over the boat's port side (from her left)."""
    return xp.sin(wind_from_rad - heading_rad) > 0.0


def clear_astern(length_m: float, x: Array, y: Array, heading: Array, xp: Any) -> Array:
    """``[.., i, j]``: boat ``i``'s bow is behind the line abeam from boat ``j``'s stern."""
    half = 0.5 * length_m
    cos_h, sin_h = xp.cos(heading), xp.sin(heading)
    bow_x, bow_y = (x + half * cos_h)[:, :, None], (y + half * sin_h)[:, :, None]
    stern_x, stern_y = (x - half * cos_h)[:, None, :], (y - half * sin_h)[:, None, :]
    return (bow_x - stern_x) * cos_h[:, None, :] + (bow_y - stern_y) * sin_h[:, None, :] < 0.0


def keeps_clear(
    length_m: float,
    course: rc.Course,
    wind_from_rad: Array,
    kind: Array,
    x: Array,
    y: Array,
    heading: Array,
    xp: Any,
) -> Array:
    """``[.., i, j]``: boat ``i`` must keep clear of boat ``j`` (module docstring).
    ``wind_from_rad`` is each boat's true wind's direction, ``kind`` the waypoint each
    boat sails to (:mod:`bbgym.envs.race.course`)."""
    port = on_port_tack(wind_from_rad, heading, xp)
    port_i, port_j = port[:, :, None], port[:, None, :]
    same_tack = port_i == port_j
    rule_10 = port_i & xp.logical_not(port_j)
    astern = clear_astern(length_m, x, y, heading, xp)
    overlapped = xp.logical_not(astern) & xp.logical_not(xp.matrix_transpose(astern))
    # Boat j's windward side: her port side on port tack, her starboard side on starboard.
    dx, dy = x[:, :, None] - x[:, None, :], y[:, :, None] - y[:, None, :]
    to_port_of_j = -dx * xp.sin(heading)[:, None, :] + dy * xp.cos(heading)[:, None, :]
    windward = xp.where(port_j, to_port_of_j > 0.0, to_port_of_j < 0.0)
    rule_11 = overlapped & windward
    rule_12 = astern
    # Mark room: both in the zone of the mark both sail to, the outside one gives room.
    mark_x = xp.where(kind == rc.WINDWARD, course.windward_x_m, course.gate_x_m)
    mark_y = xp.where(kind == rc.WINDWARD, course.windward_y_m, course.gate_y_m)
    to_mark = xp.hypot(x - mark_x, y - mark_y)
    rounding = ((kind == rc.WINDWARD) | (kind == rc.GATE)) & (
        to_mark < ZONE_HULL_LENGTHS * length_m
    )
    both = rounding[:, :, None] & rounding[:, None, :] & (kind[:, :, None] == kind[:, None, :])
    room = both & overlapped
    outside = to_mark[:, :, None] > to_mark[:, None, :]
    same_tack_rule = xp.where(room, outside, xp.where(overlapped, rule_11, rule_12))
    return xp.where(same_tack, same_tack_rule, rule_10)
