"""The VMG autopilot for BeachballSail-v0: a sailing oracle built on the boat's own polar.

It sees only the observation vector and the env's documented boat (``DinghyParams``, the
``dinghy`` argument), and knows how the boat sails because it computes the polar from the
physics (:func:`bbgym.physics.polar.compute_polar`) at a grid of wind speeds when it is
built; nothing is typed in.

**Course.** Each heading gives a steady velocity over the ground, leeway included. The
convex hull of those velocities (the polar's "hull") is what the boat can make good in
every direction by mixing two headings: where the hull touches the polar, the fastest way
to a mark in that direction is to sail straight at it (heading corrected for leeway);
where the hull bridges a gap (straight upwind, and dead downwind when running is slower
than broad reaching), the fastest way is to sail one of the gap's two edge courses, the
best-VMG courses, and switch to the other one on its layline. The autopilot keeps the
current tack or gybe until the mark crosses the layline, so it tacks or jibes once per
leg, not at every wind shift. The edges are interpolated in the observed true wind speed.
With ``tack_cone_deg`` it plays the shifts on a beat: it tacks as soon as the mark lies
more than that angle beyond the wind on the other tack's side (a header swings it there),
so it sails the lifted tack within a cone about the line to the mark, as a racing sailor
does; the layline rule is the widest cone.

**Sheet.** The boom goes where the polar found the fastest trim for the observed apparent
wind angle and wind speed ("trim to the apparent wind"), and is eased by ``ease_gain`` times
the heel beyond ``ease_heel_deg`` when a gust heels the boat, to stay upright.

**Rudder.** Proportional to the heading error with yaw-rate damping, reversed while the
boat moves astern (in irons after a slow tack the rudder acts the other way).

**Jib** (a sloop, BeachballSail-v2). Trimmed with the main on the leeward sheet, as the
polar sails it: pulled as far as the main is in. Stopped head to wind (the apparent wind
within ``irons_awa_deg`` of the bow, slower than ``irons_speed_mps``) the rudder cannot
turn the boat, so the autopilot backs the jib on the side the wind should come from on
the new course and lets the main out: the wind pushes the bow round (seed §9).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from bbgym.physics.common import wrap_angle
from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.polar import compute_polar

from .sail_simple import (
    OBS_AWA_COS,
    OBS_AWA_SIN,
    OBS_HEEL,
    OBS_MARK_COS,
    OBS_MARK_SIN,
    OBS_SURGE,
    OBS_TWA_COS,
    OBS_TWA_SIN,
    as_batch,
    trimmed_jib,
)

# More observation indices and scales (see the BeachballSail-v0 docstring).
OBS_TWS = 5
OBS_YAW_RATE = 8
WIND_SCALE_MPS = 15.0
BOAT_SPEED_SCALE_MPS = 6.0
YAW_RATE_SCALE_RPS = 1.5

DEFAULT_WIND_SPEEDS_MPS = (1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 9.0, 11.0)
GRID_RAD = np.radians(np.arange(0.0, 180.5, 1.0))
"""Regular 1 deg grid of the lookup tables (course over ground, apparent wind angle)."""


@dataclass(frozen=True)
class SailingTables:
    """What the autopilot knows of the boat, per wind speed (rows) from its polars.

    Angles are measured from the direction the true wind comes from, on one side (the
    boat is symmetric), in radians.
    """

    wind_speeds_mps: np.ndarray
    """``(S,)`` wind speeds of the polars."""
    upwind_edge_rad: np.ndarray
    """``(S,)`` course over ground of the best upwind VMG: the upwind layline angle."""
    downwind_edge_rad: np.ndarray
    """``(S,)`` course of the best downwind VMG (``pi``: running dead downwind is best)."""
    heading_for_course_rad: np.ndarray
    """``(S, G)`` heading that makes good the course ``GRID_RAD[g]`` (leeway corrected)."""
    boom_for_awa_rad: np.ndarray
    """``(S, G)`` fastest boom angle at apparent wind angle ``GRID_RAD[g]``."""
    best_vmg_mps: np.ndarray
    """``(S,)`` best upwind velocity made good."""


def _hull_edges(cog: np.ndarray, speed: np.ndarray) -> tuple[float, float]:
    """Upwind and downwind edges of the convex hull of the polar's ground velocities.

    ``cog``/``speed`` describe one side; the other side is the mirror image. The hull's
    vertex with the smallest course angle bounds the upwind gap, the one with the largest
    the downwind gap.
    """
    points = np.concatenate(
        [
            np.stack([speed * np.cos(cog), speed * np.sin(cog)], axis=1),
            np.stack([speed * np.cos(cog), -speed * np.sin(cog)], axis=1),
            np.zeros((1, 2)),
        ]
    )
    hull = _convex_hull(points)
    angles = np.abs(np.arctan2(hull[:, 1], hull[:, 0]))
    radii = np.hypot(hull[:, 0], hull[:, 1])
    angles = angles[radii > 1e-9]
    return float(angles.min()), float(angles.max())


def _convex_hull(points: np.ndarray) -> np.ndarray:
    """Vertices of the convex hull of 2D points (Andrew's monotone chain)."""
    pts = sorted(map(tuple, np.round(points, 12)))

    def cross(o: tuple, a: tuple, b: tuple) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    def chain(seq: list) -> list:
        out: list = []
        for p in seq:
            while len(out) >= 2 and cross(out[-2], out[-1], p) <= 0.0:
                out.pop()
            out.append(p)
        return out

    lower, upper = chain(pts), chain(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


@functools.lru_cache(maxsize=8)
def sailing_tables(
    params: DinghyParams,
    wind_speeds_mps: tuple[float, ...] = DEFAULT_WIND_SPEEDS_MPS,
    angle_step_deg: float = 2.0,
) -> SailingTables:
    """Compute the polar at each wind speed and derive the autopilot's tables (cached)."""
    headings = np.radians(np.arange(0.0, 180.0 + 1e-9, angle_step_deg))
    sheets = np.linspace(0.0, 1.0, 21)
    rows: dict[str, list] = {k: [] for k in ("up", "down", "heading", "boom", "vmg")}
    for wind in wind_speeds_mps:
        polar = compute_polar(params, wind, headings, sheets, duration_s=60.0)
        speed = polar.boat_speed_mps
        vmg = np.clip(polar.vmg_mps, -speed, speed)
        cross = np.sqrt(np.maximum(speed**2 - vmg**2, 0.0))
        cog = np.arctan2(cross, vmg)  # course over ground, from the wind
        up, down = _hull_edges(cog, speed)
        # Headings that sail (make way ahead, from the best-VMG one down to a run); their
        # courses grow with the heading, which the interpolation needs.
        sailing = (headings >= headings[np.argmax(vmg)] - 1e-9) & (speed > 0.05)
        course = np.maximum.accumulate(cog[sailing])
        rows["heading"].append(np.interp(GRID_RAD, course, headings[sailing]))
        # Steady apparent wind of each heading, boat-frame: wind from the heading's angle,
        # boat moving ahead with leeway to leeward.
        leeway = np.nan_to_num(polar.leeway_rad)
        wind_x, wind_y = -wind * np.cos(headings), -wind * np.sin(headings)
        boat_x, boat_y = speed * np.cos(leeway), -speed * np.sin(leeway)
        awa = np.arctan2(-(wind_y - boat_y), -(wind_x - boat_x))
        boom = params.sheet_min_rad + polar.sheet * (params.sheet_max_rad - params.sheet_min_rad)
        order = np.argsort(awa[sailing])
        rows["boom"].append(np.interp(GRID_RAD, awa[sailing][order], boom[sailing][order]))
        rows["up"].append(up)
        rows["down"].append(down)
        rows["vmg"].append(float(vmg.max()))
    return SailingTables(
        wind_speeds_mps=np.asarray(wind_speeds_mps, dtype=np.float64),
        upwind_edge_rad=np.array(rows["up"]),
        downwind_edge_rad=np.array(rows["down"]),
        heading_for_course_rad=np.array(rows["heading"]),
        boom_for_awa_rad=np.array(rows["boom"]),
        best_vmg_mps=np.array(rows["vmg"]),
    )


def _lookup(
    table: np.ndarray, speeds: np.ndarray, wind: np.ndarray, angle: np.ndarray
) -> np.ndarray:
    """Bilinear lookup of ``table[S, G]`` at wind speeds ``wind`` and angles ``angle``."""
    s = np.clip(np.interp(wind, speeds, np.arange(speeds.size)), 0, speeds.size - 1)
    s0 = np.minimum(s.astype(np.int64), speeds.size - 2)
    fs = s - s0
    g = np.clip(np.abs(angle) / (GRID_RAD[1] - GRID_RAD[0]), 0, GRID_RAD.size - 1)
    g0 = np.minimum(g.astype(np.int64), GRID_RAD.size - 2)
    fg = g - g0
    low = table[s0, g0] * (1 - fg) + table[s0, g0 + 1] * fg
    high = table[s0 + 1, g0] * (1 - fg) + table[s0 + 1, g0 + 1] * fg
    return low * (1 - fs) + high * fs


class VMGAutopilot:
    """The polar-based sailing oracle: ``autopilot(obs) -> action``.

    Accepts one observation ``(16,)`` (returns ``(2,)``) or a batch ``(N, 16)`` (returns
    ``(N, 2)``), float32. Keeps each env's tack and gybe between calls; call :meth:`reset`
    at the start of an episode (``reset(i)`` for env ``i`` of a batch).

    Args:
        dinghy: the env's boat (``env.unwrapped.task.params``); defaults to the preset's.
        wind_speeds_mps: wind speeds at which polars are computed (interpolated between).
        min_run_angle_deg: never steer a course closer than this to dead downwind: a run
            in gusts and shifts risks sailing by the lee into an unplanned jibe.
        rudder_gain: rudder per radian of heading error.
        yaw_damping: rudder per rad/s of yaw rate (stops weaving after a tack).
        ease_heel_deg: heel (deg) beyond which the boom is eased.
        ease_gain: boom eased (rad) per radian of heel beyond ``ease_heel_deg``.
        irons_awa_deg: apparent wind angle (deg) within which a slow sloop is in irons
            and backs its jib.
        irons_speed_mps: boat speed (m/s) below which a sloop within ``irons_awa_deg``
            of the wind is in irons.
        tack_cone_deg: on a beat, tack once the mark lies more than this beyond the true
            wind on the other tack's side (module docstring); ``None``: at the layline.
    """

    def __init__(
        self,
        dinghy: DinghyParams | None = None,
        wind_speeds_mps: tuple[float, ...] = DEFAULT_WIND_SPEEDS_MPS,
        min_run_angle_deg: float = 10.0,
        rudder_gain: float = 2.0,
        yaw_damping: float = 0.5,
        ease_heel_deg: float = 25.0,
        ease_gain: float = 3.0,
        irons_awa_deg: float = 30.0,
        irons_speed_mps: float = 0.8,
        tack_cone_deg: float | None = None,
    ) -> None:
        self.params = dinghy or DinghyParams()
        self.tables = sailing_tables(self.params, tuple(float(w) for w in wind_speeds_mps))
        self.max_run = math.pi - math.radians(min_run_angle_deg)
        self.rudder_gain = float(rudder_gain)
        self.yaw_damping = float(yaw_damping)
        self.ease_heel = math.radians(ease_heel_deg)
        self.ease_gain = float(ease_gain)
        self.irons_awa = math.radians(irons_awa_deg)
        self.irons_speed = float(irons_speed_mps)
        if tack_cone_deg is not None and not 0.0 <= tack_cone_deg <= 90.0:
            raise ValueError(f"tack_cone_deg must be in [0, 90] deg, got {tack_cone_deg!r}")
        self.tack_cone = None if tack_cone_deg is None else math.radians(tack_cone_deg)
        self.sloop = self.params.rig == "sloop"
        self._side = np.zeros(0)  # +1 / -1 per env: the remembered tack or gybe, 0 = none
        self._backing = np.zeros(0, dtype=bool)  # a sloop backing its jib, per env

    @classmethod
    def for_env(cls, env: Any, **kwargs: Any) -> VMGAutopilot:
        """An autopilot for ``env``'s boat (a single or vector BeachballSail env).

        The first autopilot of a boat in a process computes its polar (a minute of sailing
        at each heading, sheet and wind speed: about 6 s for BeachballSail-v2 on an idle
        2-core machine, longer on a busy one); a wait over 2 s is said on stderr
        (:func:`bbgym.backends.announced`, silenced by ``BBGYM_QUIET=1``).

        Args:
            env: the env (its ``unwrapped.task.params`` is the boat).
            **kwargs: the autopilot's other arguments (:class:`VMGAutopilot`).

        Returns:
            The autopilot.
        """
        from bbgym.backends import announced

        spec = getattr(env, "spec", None)
        name = getattr(spec, "id", None) or type(env.unwrapped).__name__
        with announced(f"VMGAutopilot: computing the boat's polar for {name}"):
            return cls(env.unwrapped.task.params, **kwargs)

    def reset(self, index: int | np.ndarray | None = None) -> None:
        """Forget the tack/gybe of every env, or only of ``index``."""
        if index is None:
            self._side = np.zeros(0)
            self._backing = np.zeros(0, dtype=bool)
        else:
            if self._side.size:
                self._side[index] = 0.0
            if self._backing.size:
                self._backing[index] = False

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        o, single = as_batch(obs)
        wind = o[:, OBS_TWS] * WIND_SCALE_MPS
        rudder, course = self._rudder(o, wind)
        sheet = self._sheet(o, wind)
        columns = [rudder, sheet]
        if self.sloop:
            columns = [rudder, *self._sloop_sheets(o, sheet, course)]
        actions = np.stack(columns, axis=1).astype(np.float32)
        return actions[0] if single else actions

    def _sloop_sheets(
        self, o: np.ndarray, sheet: np.ndarray, course: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Main and jib sheets of a sloop: the jib trimmed with the main; in irons, the jib
        backed and the main out until the bow is well off the wind or the boat moves."""
        awa = np.arctan2(o[:, OBS_AWA_SIN], o[:, OBS_AWA_COS])
        surge = o[:, OBS_SURGE] * BOAT_SPEED_SCALE_MPS
        if self._backing.shape != awa.shape:
            self._backing = np.zeros(awa.shape, dtype=bool)
        stopped = (np.abs(awa) < self.irons_awa) & (surge < self.irons_speed)
        free = (np.abs(awa) > self.irons_awa + math.radians(25.0)) | (
            surge > 1.5 * self.irons_speed
        )
        self._backing = stopped | (self._backing & ~free)
        # A course counterclockwise of the wind (> 0) has the wind from starboard: back the
        # jib on the starboard sheet (-1), so the wind pushes the bow to port, onto it. The
        # main goes out: sheeted, it would turn the bow back into the wind.
        backed = np.where(course > 0.0, -1.0, 1.0)
        main = np.where(self._backing, 1.0, sheet)
        return main, np.where(self._backing, backed, trimmed_jib(o, sheet))

    def target_course(self, obs: np.ndarray) -> np.ndarray:
        """Course over ground to steer, ``(N,)`` rad from the true wind's direction (signed,
        + = counterclockwise); updates the remembered tack/gybe."""
        o = as_batch(obs)[0]
        t = self.tables
        wind = o[:, OBS_TWS] * WIND_SCALE_MPS
        twa = np.arctan2(o[:, OBS_TWA_SIN], o[:, OBS_TWA_COS])
        mark = wrap_angle(np.arctan2(o[:, OBS_MARK_SIN], o[:, OBS_MARK_COS]) - twa)
        bow = wrap_angle(-twa)
        up = np.interp(wind, t.wind_speeds_mps, t.upwind_edge_rad)
        down = np.minimum(np.interp(wind, t.wind_speeds_mps, t.downwind_edge_rad), self.max_run)
        if self._side.shape != mark.shape:
            self._side = np.zeros(mark.shape)
        in_gap = (np.abs(mark) < up) | (np.abs(mark) > down)
        # Outside a gap the side is the mark's; inside, a side once chosen is kept until the
        # mark leaves the gap across the other edge (the layline). A first choice is the side
        # the bow is on, so a boat does not start with a tack or jibe.
        mark_side = np.where(mark >= 0.0, 1.0, -1.0)
        bow_side = np.where(bow >= 0.0, 1.0, -1.0)
        first = np.where(self._side == 0.0, bow_side, self._side)
        if self.tack_cone is not None:
            # The mark beyond the cone on the other tack's side: that tack is lifted now.
            beating = np.abs(mark) < up
            first = np.where(beating & (first * mark < -self.tack_cone), -first, first)
        self._side = np.where(in_gap, first, mark_side)
        course = np.clip(np.abs(mark), up, down)
        return self._side * course

    def _rudder(self, o: np.ndarray, wind: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The rudder, and the course it steers (:meth:`target_course`)."""
        course = self.target_course(o)
        heading = np.sign(course) * _lookup(
            self.tables.heading_for_course_rad, self.tables.wind_speeds_mps, wind, course
        )
        twa = np.arctan2(o[:, OBS_TWA_SIN], o[:, OBS_TWA_COS])
        error = wrap_angle(heading + twa)  # desired heading relative to the bow, + = port
        yaw_rate = o[:, OBS_YAW_RATE] * YAW_RATE_SCALE_RPS
        command = self.rudder_gain * error - self.yaw_damping * yaw_rate
        astern = o[:, OBS_SURGE] < 0.0
        return np.clip(np.where(astern, -command, command), -1.0, 1.0), course

    def _sheet(self, o: np.ndarray, wind: np.ndarray) -> np.ndarray:
        p = self.params
        awa = np.abs(np.arctan2(o[:, OBS_AWA_SIN], o[:, OBS_AWA_COS]))
        boom = _lookup(self.tables.boom_for_awa_rad, self.tables.wind_speeds_mps, wind, awa)
        heel = np.abs(o[:, OBS_HEEL]) * p.capsize_heel_rad
        boom = boom + self.ease_gain * np.maximum(heel - self.ease_heel, 0.0)
        boom = np.clip(boom, p.sheet_min_rad, p.sheet_max_rad)
        return -1.0 + 2.0 * (boom - p.sheet_min_rad) / (p.sheet_max_rad - p.sheet_min_rad)
