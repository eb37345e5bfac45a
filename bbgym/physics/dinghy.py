"""What a dinghy is: its constants (:class:`DinghyParams`, with their accepted intervals)
and its state (:class:`DinghyState`), the events a step reports, and boats to start from.

The laws that move it are :mod:`bbgym.physics.sailing`; their integration in time is
:mod:`bbgym.physics.sailing_step`. Frames: world x east, y north, angles counterclockwise
from +x. Body frame x forward (surge ``u``), y to port (sway ``v``). Heel ``> 0``: port side
down. Boom angle is measured from the aft-pointing centerline, ``> 0``: boom swung out to
port.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import AIR_DENSITY_KGM3, WATER_DENSITY_KGM3
from bbgym.physics.namespace import Array, replaced
from bbgym.physics.validation import check_choice, check_fields, interval, param

SAIL_MODELS = ("lift", "seed", "cambered")
RIGS = ("cat", "sloop")
"""``"cat"``: one sail whose force acts at the hull's centre of lateral resistance, so only
the rudder steers (the first sailing versions). ``"sloop"``: a main and a jib (foresail), each
force at its centre of effort: the sails steer too (seed §9 "Controlling the sail")."""


@dataclass(frozen=True)
class DinghyParams:
    """Physical constants of a Laser-like single-handed dinghy, SI units.

    The defaults are the default preset (``configs/beachball_sail.yaml``), calibrated so the
    polar matches a real dinghy's (see ``bbgym polar`` and ``tests/sail/test_polar.py``).

    Accepted intervals (checked on construction by :func:`check_fields`; errors name
    ``DinghyParams.<field>``). They span a 20 kg sailboard-like hull to a few-tonne 15 m
    keelboat; bounds are where the model stops meaning anything, and 0 is allowed where it
    is a meaningful degenerate boat (no windage, no centreboard, no damping: the implicit
    integration needs no damping to stay stable). Every combination is stable at any
    ``dt <= 0.25 s`` (``tests/sail/test_sailing_stability.py``). Cross-field rules:
    ``sheet_min_rad < sheet_max_rad <= pi/2``, ``jib_sheet_min_rad < jib_sheet_max_rad``,
    ``capsize_heel_rad < pi/2``. The fields marked (sloop) act only with ``rig="sloop"``,
    those marked (cambered) only with ``sail_model="cambered"``.

    ======================  ================  =============================================
    field                   interval          why the bounds
    ======================  ================  =============================================
    mass_kg                 [20, 5000]        sailboard with sailor .. few-tonne keelboat
    yaw_inertia_kgm2        [1, 1e5]          ``m k^2``, k 0.2 m .. 4.5 m
    heel_inertia_kgm2       [1, 1e5]          same span about the roll axis
    hull_length_m           [1, 15]           dinghy .. 15 m keelboat (drawing only)
    hull_beam_m             [0.3, 6]          (drawing only)
    sail_area_m2            [0.5, 150]        kite-sized .. keelboat main and jib
    sail_cn_peak            [0.1, 3]          normal coefficients of real sails: 0.5 .. 2
    sail_stall_rad          [2, 45] deg       where attached flow can separate
    sail_stall_width_rad    [1e-4, 0.5]       abrupt (a step) .. very gradual stall
    sail_cn_flat            [0.1, 3]          flat plate broadside: about 1.2
    sail_drag_coefficient   [0.1, 3]          (seed model) flat plate: about 1.1
    sail_cl_peak            [0.1, 3]          (cambered) lift of real sails: 1 .. 2
    sail_drag_parasitic     [0, 0.5]          (cambered) a clean foil .. a flogging sail
    sail_drag_induced       [0, 1]            (cambered) ``1 / (pi AR)``: AR 0.3 .. any
    sail_ce_height_m        [0.1, 25]         centre of effort above the heel axis
    sail_ce_aft_m           [0.05, 10]        centre of effort aft of the mast
    mast_ahead_m            [-5, 10]          (sloop) mast ahead of the centreboard's centre
    jib_area_m2             [0.1, 100]        (sloop) a small foresail .. a genoa
    jib_tack_ahead_m        [0, 15]           (sloop) forestay ahead of the centreboard
    jib_ce_aft_m            [0.05, 10]        (sloop) centre of effort aft of the tack
    jib_ce_height_m         [0.1, 25]         (sloop) centre of effort above the heel axis
    jib_sheet_min_rad       [0, 90] deg       (sloop) jib sheeted in .. square
    jib_sheet_max_rad       (0, 90] deg       (sloop) jib eased out
    boom_length_m           [0.3, 10]         (drawing only)
    boom_impact_heel_arm_m  [0, 25]           0: a jibe gives no roll jolt
    boom_inertia_kgm2       [0.05, 1e4]       a sailboard rig .. a keelboat's main
    boom_air_damping        [0, 1e4]          0: no air damping of the swing
    by_the_lee_rad          [0, 45] deg       0: the sail is blown across at once
    sheet_min_rad           [0, 90] deg       boom on the centreline .. square
    sheet_max_rad           (0, 90] deg       (past 90 deg the boom would point forward)
    hull_drag_forward       [1e-3, 2]         skin of a 0.5 m^2 board .. a keelboat's hull
    hull_wave_speed_mps     [0.5, 20]         ``sqrt(g L / 2 pi)`` of 0.2 m .. a planing hull
    hull_planing_speed_mps  [0, 30]           0: no planing (wave drag grows forever)
    hull_drag_backward      [1e-3, 5]         as forward (0 would sail astern without limit)
    hull_drag_sideways      [1e-3, 30]        hull and foils broadside
    keel_lift_slope         [0, 2e4]          0: no centreboard (a raft)
    windage                 [0, 20]           0: no windage
    rudder_max_rad          [1, 60] deg       past 60 deg a rudder only brakes
    rudder_moment_coeff     [0, 1e5]          0: no rudder
    yaw_damping_linear      [0, 1e5]          0: no damping
    yaw_damping_quadratic   [0, 1e5]          0: no damping
    crew_righting_nm        [0, 5e4]          0: no crew hiking .. a keelboat's rail crew
    crew_response_rad       [0.005, 1]        heel that hikes the crew out
    crew_time_s             [0.01, 30]        reaction time of the crew
    hull_righting_nm        [0, 5e5]          0: no form stability .. a ballasted keel
    heel_damping            [0, 1e5]          0: no damping
    capsize_heel_rad        [3 deg, 90 deg)   a boat on its side has capsized
    ======================  ================  =============================================
    """

    sail_model: str = "lift"
    """``"lift"``: flat-plate normal coefficient with stall; ``"seed"``: drag formula (§9);
    ``"cambered"``: lift and drag of a cambered sail (the force leans forward of the
    normal)."""
    rig: str = "cat"
    """``"cat"``: one sail acting at the centreboard (the first versions); ``"sloop"``: main
    and jib, each acting at its centre of effort (:data:`RIGS`)."""
    mass_kg: float = param(135.0, interval(20.0, 5000.0))
    """Hull (59 kg) plus helmsman (76 kg). Accepted: [20, 5000]."""
    yaw_inertia_kgm2: float = param(180.0, interval(1.0, 1e5))
    """Moment of inertia about the vertical axis. Accepted: [1, 1e5]."""
    heel_inertia_kgm2: float = param(120.0, interval(1.0, 1e5))
    """Moment of inertia about the heel (roll) axis. Accepted: [1, 1e5]."""
    hull_length_m: float = param(4.2, interval(1.0, 15.0))
    """Drawing only. Accepted: [1, 15]."""
    hull_beam_m: float = param(1.4, interval(0.3, 6.0))
    """Drawing only. Accepted: [0.3, 6]."""

    sail_area_m2: float = param(7.06, interval(0.5, 150.0))
    """Accepted: [0.5, 150]."""
    sail_cn_peak: float = param(1.5, interval(0.1, 3.0))
    """Lift model: normal-force coefficient at the stall angle (attached flow). Accepted:
    [0.1, 3]."""
    sail_stall_rad: float = param(math.radians(16.0), interval(math.radians(2.0), math.pi / 4))
    """Lift model: angle of attack where the flow separates. Accepted: [2, 45] deg."""
    sail_stall_width_rad: float = param(math.radians(3.0), interval(1e-4, 0.5))
    """Lift model: how abruptly the attached flow gives way to separated flow. Accepted:
    [1e-4, 0.5]."""
    sail_cn_flat: float = param(1.3, interval(0.1, 3.0))
    """Lift model: normal coefficient of separated flow at 90 deg (a flat plate's drag).
    Accepted: [0.1, 3]."""
    sail_drag_coefficient: float = param(1.1, interval(0.1, 3.0))
    """Seed model: drag coefficient of a flat surface facing the wind (§8: about 1.1).
    Accepted: [0.1, 3]."""
    sail_cl_peak: float = param(1.4, interval(0.1, 3.0))
    """Cambered model: lift coefficient of attached flow at ``sail_stall_rad`` (the flow
    then separates toward ``sail_cn_flat``). Accepted: [0.1, 3]."""
    sail_drag_parasitic: float = param(0.03, interval(0.0, 0.5))
    """Cambered model: drag coefficient of the sail at zero lift (skin friction, mast).
    Accepted: [0, 0.5]."""
    sail_drag_induced: float = param(0.08, interval(0.0, 1.0))
    """Cambered model: induced drag per lift squared, ``C_D = C_D0 + k C_L^2`` with
    ``k = 1 / (pi AR)``; a Laser's sail (AR about 3.7, doubled by its mirror in the water)
    about 0.04, more with twist. Accepted: [0, 1]."""
    sail_ce_height_m: float = param(2.9, interval(0.1, 25.0))
    """Height of the sail's centre of effort above the heel axis. Accepted: [0.1, 25]."""
    sail_ce_aft_m: float = param(1.0, interval(0.05, 10.0))
    """Distance of the centre of effort from the mast along the boom. Accepted: [0.05, 10]."""
    mast_ahead_m: float = param(0.6, interval(-5.0, 10.0))
    """Sloop: how far the mast stands ahead of the hull's centre of lateral resistance (the
    centreboard). With the main's centre of effort ``sail_ce_aft_m`` aft of the mast, a
    main sheeted in pulls the stern to leeward: weather helm. Accepted: [-5, 10]."""
    jib_area_m2: float = param(1.3, interval(0.1, 100.0))
    """Sloop: area of the jib. Accepted: [0.1, 100]."""
    jib_tack_ahead_m: float = param(1.9, interval(0.0, 15.0))
    """Sloop: how far the jib's tack (the forestay at the bow) is ahead of the centre of
    lateral resistance. Accepted: [0, 15]."""
    jib_ce_aft_m: float = param(0.5, interval(0.05, 10.0))
    """Sloop: distance of the jib's centre of effort from its tack along its foot.
    Accepted: [0.05, 10]."""
    jib_ce_height_m: float = param(1.6, interval(0.1, 25.0))
    """Sloop: height of the jib's centre of effort above the heel axis. Accepted:
    [0.1, 25]."""
    jib_sheet_min_rad: float = param(math.radians(10.0), interval(0.0, math.pi / 2))
    """Sloop: jib angle off the centreline with a sheet fully in (on that sheet's side,
    leeward or, backed, windward). Accepted: [0, 90] deg, below jib_sheet_max_rad."""
    jib_sheet_max_rad: float = param(math.radians(60.0), interval(0.0, math.pi / 2, low_open=True))
    """Sloop: how far out the jib may go with its sheet fully eased. Accepted: (0, 90] deg."""

    boom_length_m: float = param(2.7, interval(0.3, 10.0))
    """Drawing only. Accepted: [0.3, 10]."""
    boom_impact_heel_arm_m: float = param(2.9, interval(0.0, 25.0))
    """Height above the heel axis where a jibing sail's momentum is stopped. Accepted:
    [0, 25].

    Most of the swinging mass and air is the cloth, high on the mast; when the sheet stops
    the boom the mast stops the sail, so the roll impulse is the sail's angular momentum
    times this height over ``sail_ce_aft_m``."""
    boom_inertia_kgm2: float = param(15.0, interval(0.05, 1e4))
    """Boom and sail about the mast. Accepted: [0.05, 1e4]."""
    boom_air_damping: float = param(25.0, interval(0.0, 1e4))
    """Quadratic air damping of a swinging sail, torque = -k * rate * |rate| (N m s^2).
    Accepted: [0, 1e4]."""
    by_the_lee_rad: float = param(math.radians(10.0), interval(0.0, math.pi / 4))
    """How far by the lee (wind from aft, on the boom's side) the sail holds before it is
    blown across in a jibe. Accepted: [0, 45] deg."""
    sheet_min_rad: float = param(math.radians(4.0), interval(0.0, math.pi / 2))
    """Boom angle with the sheet fully in. Accepted: [0, 90] deg, below sheet_max_rad."""
    sheet_max_rad: float = param(math.radians(85.0), interval(0.0, math.pi / 2, low_open=True))
    """Boom angle with the sheet fully out (free to swing to the shroudless stop). Accepted:
    (0, 90] deg."""

    hull_drag_forward: float = param(0.007, interval(1e-3, 2.0))
    """C_d * A (m^2) of the hull moving ahead: small. Accepted: [1e-3, 2]."""
    hull_wave_speed_mps: float = param(2.4, interval(0.5, 20.0))
    """Speed where wave-making doubles the forward drag: ``drag * (1 + (u / u_w)^2)``.
    Accepted: [0.5, 20].

    A 4 m hull makes a bow wave as long as itself near ``sqrt(g L / 2 pi)`` ~ 2.6 m/s;
    past it the boat climbs its own wave and the drag grows much faster than ``u^2``."""
    hull_planing_speed_mps: float = param(0.0, interval(0.0, 30.0))
    """Speed past which a planing hull rises out of its wave: the wave drag levels off at
    ``(u_p / u_w)^2`` times the skin drag, ``drag * (1 + (u/u_w)^2 / (1 + (u/u_p)^2))``.
    0: a displacement hull, whose wave drag keeps growing (the first versions). Accepted:
    [0, 30]."""
    hull_drag_backward: float = param(0.08, interval(1e-3, 5.0))
    """C_d * A (m^2) moving astern: larger (transom first). Accepted: [1e-3, 5]."""
    hull_drag_sideways: float = param(1.2, interval(1e-3, 30.0))
    """C_d * A (m^2) of hull and foils moving straight sideways: large. Accepted:
    [1e-3, 30]."""
    keel_lift_slope: float = param(600.0, interval(0.0, 2e4))
    """Side force of the centreboard per (forward speed * sideways speed), N s^2/m^2.
    Accepted: [0, 2e4].

    The centreboard is a foil: its side force is ``1/2 rho A C_L_alpha * u * v``
    (``A`` 0.35 m^2, ``C_L_alpha`` about 5 /rad plus the hull's share), so leeway is
    small and almost independent of speed."""
    windage: float = param(1.0, interval(0.0, 20.0))
    """C_d * A (m^2) of hull, mast and crew in the apparent wind. Accepted: [0, 20]."""

    rudder_max_rad: float = param(math.radians(30.0), interval(math.radians(1.0), math.pi / 3))
    """Accepted: [1, 60] deg."""
    rudder_moment_coeff: float = param(200.0, interval(0.0, 1e5))
    """Yaw moment per rudder angle and forward speed squared, N m / (rad m^2/s^2).
    Accepted: [0, 1e5]."""
    yaw_damping_linear: float = param(500.0, interval(0.0, 1e5))
    """Hydrodynamic yaw damping per forward speed, N m s / (rad m/s). Accepted: [0, 1e5]."""
    yaw_damping_quadratic: float = param(400.0, interval(0.0, 1e5))
    """Yaw damping at any speed (the hull's end plates), N m s^2/rad^2. Accepted:
    [0, 1e5]."""

    crew_righting_nm: float = param(600.0, interval(0.0, 5e4))
    """Helmsman fully hiked: 76 kg * g * 0.94 m. Accepted: [0, 5e4]."""
    crew_response_rad: float = param(math.radians(8.0), interval(0.005, 1.0))
    """Heel at which the helmsman is about 3/4 hiked out. Accepted: [0.005, 1]."""
    crew_time_s: float = param(1.0, interval(0.01, 30.0))
    """Time constant of the helmsman moving across the boat. Accepted: [0.01, 30]."""
    hull_righting_nm: float = param(150.0, interval(0.0, 5e5))
    """Form stability, moment = -k sin(heel). Accepted: [0, 5e5]."""
    heel_damping: float = param(350.0, interval(0.0, 1e5))
    """N m s/rad. Accepted: [0, 1e5]."""
    capsize_heel_rad: float = param(
        math.radians(60.0), interval(math.radians(3.0), math.pi / 2, high_open=True)
    )
    """Heel past which the boat capsizes. Accepted: [3, 90) deg."""

    def __post_init__(self) -> None:
        check_fields(self)
        check_choice("DinghyParams.sail_model", self.sail_model, SAIL_MODELS)
        check_choice("DinghyParams.rig", self.rig, RIGS)
        if not self.jib_sheet_min_rad < self.jib_sheet_max_rad:
            raise ValueError(
                "DinghyParams.jib_sheet_min_rad must be < jib_sheet_max_rad, got "
                f"{self.jib_sheet_min_rad!r}, {self.jib_sheet_max_rad!r}"
            )
        if not self.sheet_min_rad < self.sheet_max_rad <= math.pi / 2:
            raise ValueError(
                "DinghyParams.sheet_min_rad must be < sheet_max_rad <= pi/2, got "
                f"{self.sheet_min_rad!r}, {self.sheet_max_rad!r}"
            )
        if self.capsize_heel_rad >= math.pi / 2:
            raise ValueError(
                f"DinghyParams.capsize_heel_rad must be < pi/2, got {self.capsize_heel_rad!r}"
            )
        # Products of parameters the physics needs every substep, computed once (the single
        # env runs on Python floats, where each multiplication costs as much as a sin).
        # Not fields: equality, hashing and repr see the parameters only.
        excess = self.sail_cn_peak / math.sin(self.sail_stall_rad) - self.sail_cn_flat
        half_rho = 0.5 * WATER_DENSITY_KGM3
        derived = {
            "_sail_q": 0.5 * AIR_DENSITY_KGM3 * self.sail_area_m2,
            "_jib_q": 0.5 * AIR_DENSITY_KGM3 * self.jib_area_m2,
            "_jib_heel_ratio": self.jib_ce_height_m / self.sail_ce_height_m,
            "_minus_sin_by_the_lee": -math.sin(self.by_the_lee_rad),
            # Lift model: C_N / sin(alpha) = flat + half_excess * (1 - tanh(x / 2)).
            "_lift": (
                self.sail_stall_rad,
                0.5 / self.sail_stall_width_rad,
                self.sail_cn_flat,
                0.5 * excess,
                -0.25 * excess / self.sail_stall_width_rad,
            ),
            "_hull": (
                half_rho * (self.hull_drag_forward - self.hull_drag_backward),
                half_rho * self.hull_drag_backward,
                1.0 / (self.hull_wave_speed_mps * self.hull_wave_speed_mps),
                half_rho * self.hull_drag_sideways,
            ),
            # 1 / u_p^2 (0: no planing). Below 1e-6 m/s the wave drag is under 1e-11 of the
            # skin drag at any speed, so u_p is taken as 1e-6 there: 1 / u_p^2 stays finite
            # in float32 (1e12), and u^2 / u_p^2 never makes inf * 0 at rest.
            "_inv_planing_sq": (
                1.0 / max(self.hull_planing_speed_mps, 1e-6) ** 2
                if self.hull_planing_speed_mps
                else 0.0
            ),
            # Cambered model: attached lift slope a = C_L / sin(alpha) and k a^2.
            "_cambered": (
                self.sail_cl_peak / math.sin(self.sail_stall_rad),
                self.sail_drag_induced * (self.sail_cl_peak / math.sin(self.sail_stall_rad)) ** 2,
            ),
            "_roll_arm": self.boom_impact_heel_arm_m / self.sail_ce_aft_m,
        }
        for name, value in derived.items():
            object.__setattr__(self, name, value)

    def replace(self, **changes: object) -> DinghyParams:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)


class DinghyState(NamedTuple):
    """State of a batch of dinghies; every field has shape ``(batch,)`` (or is a Python
    float for one boat). Immutable: a step makes a new state."""

    x_m: Array
    y_m: Array
    heading_rad: Array
    vx_mps: Array
    vy_mps: Array
    yaw_rate_rps: Array
    heel_rad: Array
    heel_rate_rps: Array
    boom_rad: Array
    boom_rate_rps: Array
    crew_out: Array
    """Helmsman's position, -1 (hiked to port) .. +1 (hiked to starboard)."""
    capsized: Array
    """Bool; once capsized the boat stays down (the sail lies in the water)."""


class StepEvents(NamedTuple):
    """What happened during one :func:`step`, per boat."""

    jibes: Array
    """Boom crossings of the centerline with the apparent wind from aft (int)."""
    jibe_severity_rps: Array
    """Largest boom angular speed at such a crossing (0 if none)."""
    tacks: Array
    """Bow crossings of the true wind direction (int, 0 or 1)."""


def dinghy_moving(
    heading_rad: Array, speed_mps: Array, boom_rad: Array, xp: Any = np
) -> DinghyState:
    """Upright boats at the origin moving straight ahead at ``speed_mps``, the boom at
    ``boom_rad`` (arrays of one shape, any namespace)."""
    zeros = 0.0 * heading_rad
    return DinghyState(
        x_m=zeros,
        y_m=zeros,
        heading_rad=heading_rad,
        vx_mps=speed_mps * xp.cos(heading_rad),
        vy_mps=speed_mps * xp.sin(heading_rad),
        yaw_rate_rps=zeros,
        heel_rad=zeros,
        heel_rate_rps=zeros,
        boom_rad=boom_rad,
        boom_rate_rps=zeros,
        crew_out=zeros,
        capsized=zeros > 0.0,
    )


def dinghy_at_rest(
    batch: int,
    x_m: Any = 0.0,
    y_m: Any = 0.0,
    heading_rad: Any = 0.0,
    speed_mps: Any = 0.0,
    boom_rad: Any = 0.0,
) -> DinghyState:
    """A NumPy batch of upright boats moving straight ahead at ``speed_mps``."""

    def full(v: object) -> np.ndarray:
        return np.broadcast_to(np.asarray(v, dtype=np.float64), (batch,)).copy()

    boat = dinghy_moving(full(heading_rad), full(speed_mps), full(boom_rad))
    return replaced(boat, x_m=full(x_m), y_m=full(y_m))
