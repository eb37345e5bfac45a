"""The race course: a start line, a windward mark, a leeward gate and a finish line laid
to the race's mean wind, and the geometry that says when a boat has passed each of them.

Frame: ``upwind`` is the unit vector toward where the mean wind comes from, ``across`` the
upwind vector turned 90 deg counterclockwise (to the left of a boat heading upwind). The
start line is centred on the origin along ``across``: the committee boat at its starboard
end (``-across``), the pin at its port end. The windward mark lies ``leg_length_m``
upwind of the line's centre and is left to port (rounded counterclockwise, seen from
above); the leeward gate, ``gate_depth_m`` below the line, is sailed through downwind;
the finish is the start line crossed downwind after the last windward mark.

The waypoints of a race with ``laps`` laps, in order: the start (the line crossed upwind
after the gun), then for each lap the windward mark and the gate, the last lap's gate
replaced by the finish. Functions are pure and batched: a race's geometry is ``(races,)``
or ``(races, 1)`` arrays, its boats' ``(races, K)``.
"""

from __future__ import annotations

from typing import Any, NamedTuple

from bbgym.physics.namespace import Array

START, WINDWARD, GATE, FINISH = 0, 1, 2, 3
"""The kinds of waypoint: what passing it means (module docstring)."""
WAYPOINT_NAMES = ("start", "windward mark", "gate", "finish")


def waypoint_kinds(laps: int) -> tuple[int, ...]:
    """The kind of each waypoint of a race of ``laps`` laps, in the order sailed."""
    kinds = [START]
    for lap in range(laps):
        kinds += [WINDWARD, FINISH if lap == laps - 1 else GATE]
    return tuple(kinds)


class Course(NamedTuple):
    """A race's course (each field ``(races, 1)``, so it broadcasts over the boats)."""

    upwind_x: Array
    upwind_y: Array
    line_half_m: float
    """Half the start (and finish) line's length."""
    windward_x_m: Array
    windward_y_m: Array
    gate_x_m: Array
    """The gate's centre."""
    gate_y_m: Array
    gate_half_m: float
    """Half the gate's width."""

    @property
    def across_x(self) -> Array:
        return -self.upwind_y

    @property
    def across_y(self) -> Array:
        return self.upwind_x

    def ends(self) -> tuple[tuple[Array, Array], tuple[Array, Array]]:
        """The start line's ends: ``((committee x, y), (pin x, y))``."""
        h = self.line_half_m
        return (-h * self.across_x, -h * self.across_y), (h * self.across_x, h * self.across_y)


def lay_course(
    wind_from_rad: Array,
    line_length_m: float,
    leg_length_m: float,
    gate_depth_m: float,
    gate_width_m: float,
    xp: Any,
) -> Course:
    """The course laid square to a race's mean wind ``wind_from_rad`` (``(races,)``)."""
    ux, uy = xp.cos(wind_from_rad)[:, None], xp.sin(wind_from_rad)[:, None]
    return Course(
        upwind_x=ux,
        upwind_y=uy,
        line_half_m=0.5 * line_length_m,
        windward_x_m=leg_length_m * ux,
        windward_y_m=leg_length_m * uy,
        gate_x_m=-gate_depth_m * ux,
        gate_y_m=-gate_depth_m * uy,
        gate_half_m=0.5 * gate_width_m,
    )


def crossed_line(
    center_x: Array,
    center_y: Array,
    normal_x: Array,
    normal_y: Array,
    half_m: float,
    x0: Array,
    y0: Array,
    x1: Array,
    y1: Array,
    xp: Any,
) -> tuple[Array, Array]:
    """Whether a boat that moved from ``(x0, y0)`` to ``(x1, y1)`` crossed the segment of
    half-length ``half_m`` centred at ``center`` and square to ``normal``, going the way
    ``normal`` points (from its back to its front side; at the segment's ends included),
    and the fraction of the move done where it crossed."""
    before = (x0 - center_x) * normal_x + (y0 - center_y) * normal_y
    after = (x1 - center_x) * normal_x + (y1 - center_y) * normal_y
    crossing = (before < 0.0) & (after >= 0.0)
    t = before / xp.where(crossing, before - after, -1.0)
    x, y = x0 + t * (x1 - x0) - center_x, y0 + t * (y1 - y0) - center_y
    lateral = -x * normal_y + y * normal_x
    return crossing & (xp.abs(lateral) <= half_m), t


def rounded_windward(course: Course, x0: Array, y0: Array, x1: Array, y1: Array, xp: Any) -> Array:
    """Whether a boat rounded the windward mark, leaving it to port: it crossed the ray
    from the mark straight upwind from its starboard side to its port side (passing above
    the mark, heading across the wind to the left, as a boat rounding counterclockwise
    does). A boat passing the mark on the wrong side crosses that ray the other way."""
    ax, ay = course.across_x, course.across_y
    ux, uy = course.upwind_x, course.upwind_y
    rel_x0, rel_y0 = x0 - course.windward_x_m, y0 - course.windward_y_m
    rel_x1, rel_y1 = x1 - course.windward_x_m, y1 - course.windward_y_m
    side0 = rel_x0 * ax + rel_y0 * ay
    side1 = rel_x1 * ax + rel_y1 * ay
    crossing = (side0 < 0.0) & (side1 >= 0.0)
    t = side0 / xp.where(crossing, side0 - side1, -1.0)
    above = (rel_x0 + t * (rel_x1 - rel_x0)) * ux + (rel_y0 + t * (rel_y1 - rel_y0)) * uy
    return crossing & (above > 0.0)


def passed_waypoint(
    course: Course, kind: Array, x0: Array, y0: Array, x1: Array, y1: Array, xp: Any
) -> tuple[Array, Array]:
    """Whether each boat, moving from ``(x0, y0)`` to ``(x1, y1)``, passed the waypoint of
    ``kind`` it is sailing to (:data:`START`: the line upwind; :data:`WINDWARD`: rounded
    to port; :data:`GATE`: through it downwind; :data:`FINISH`: the line downwind), and
    for the finish the fraction of the move done where it crossed the line."""
    ux, uy, h = course.upwind_x, course.upwind_y, course.line_half_m
    zero = 0.0 * ux
    up_line, _ = crossed_line(zero, zero, ux, uy, h, x0, y0, x1, y1, xp)
    down_line, t = crossed_line(zero, zero, -ux, -uy, h, x0, y0, x1, y1, xp)
    gate, _ = crossed_line(
        course.gate_x_m, course.gate_y_m, -ux, -uy, course.gate_half_m, x0, y0, x1, y1, xp
    )
    windward = rounded_windward(course, x0, y0, x1, y1, xp)
    passed = xp.where(
        kind == START,
        up_line,
        xp.where(kind == WINDWARD, windward, xp.where(kind == GATE, gate, down_line)),
    )
    return passed, t


ROUNDING_OFFSET_M = 5.0
"""How far above and to the side of the windward mark a boat steers to round it."""
BEHIND_LINE_M = 10.0
"""How far below the line a boat on the course side before its start steers to get back."""


def steer_target(course: Course, kind: Array, x: Array, y: Array, xp: Any) -> tuple[Array, Array]:
    """The point a boat at ``(x, y)`` steers for on its way to a waypoint of ``kind``.

    For the start, a point level with the boat (so a fleet spreads along the line rather
    than heading for one point) but at least :data:`ROUNDING_OFFSET_M` inside the line's
    ends: below the line and between its ends, that point :data:`ROUNDING_OFFSET_M` above
    the line (steering for it starts); below the line and beyond an end, the point on the
    line (it leads inside the end before crossing, where crossing the extension would
    not start); on the course side (over early, or come round an end), the point
    :data:`BEHIND_LINE_M` below the line (a start is a crossing from below). Then the
    windward mark's point :data:`ROUNDING_OFFSET_M` above it, on its starboard side while
    the boat is on its port side and on its port side once the boat is on its starboard
    side, so that steering for it rounds the mark to port (:func:`rounded_windward`); the
    gate's centre; the finish line's centre. A boat over early needs no rule of its own:
    it is on the course side until it is back below the line."""
    ux, uy = course.upwind_x, course.upwind_y
    ax, ay = course.across_x, course.across_y
    side = (x - course.windward_x_m) * ax + (y - course.windward_y_m) * ay
    zero = 0.0 * x
    turn = xp.where(side > 0.0, zero - ROUNDING_OFFSET_M, zero + ROUNDING_OFFSET_M)
    mark_x = course.windward_x_m + ROUNDING_OFFSET_M * ux + turn * ax
    mark_y = course.windward_y_m + ROUNDING_OFFSET_M * uy + turn * ay
    target_x = xp.where(
        kind == WINDWARD, mark_x, xp.where(kind == GATE, course.gate_x_m + zero, zero)
    )
    target_y = xp.where(
        kind == WINDWARD, mark_y, xp.where(kind == GATE, course.gate_y_m + zero, zero)
    )
    inside = max(course.line_half_m - ROUNDING_OFFSET_M, 0.0)
    across = x * ax + y * ay
    level = xp.clip(across, -inside, inside)
    height = xp.where(xp.abs(across) > inside, zero, zero + ROUNDING_OFFSET_M)
    height = xp.where(above_line(course, x, y) > 0.0, zero - BEHIND_LINE_M, height)
    target_x = xp.where(kind == START, level * ax + height * ux, target_x)
    target_y = xp.where(kind == START, level * ay + height * uy, target_y)
    return target_x, target_y


def above_line(course: Course, x: Array, y: Array) -> Array:
    """Signed distance of each boat upwind of the start line's extension (m): > 0 on the
    course side."""
    return x * course.upwind_x + y * course.upwind_y
