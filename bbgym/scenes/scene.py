"""What a scene is: a small physics setup of the course text, pure and batched, that runs,
draws and measures what the text claims.

A scene is declared like an env family's spec: a :class:`Scene` names its parameters (a
frozen dataclass with accepted intervals, :mod:`bbgym.physics.validation`), its initial
state (an immutable NamedTuple of arrays, one row per body), its step (a pure function over
the array namespace ``xp``: the same source runs on NumPy and on torch, as the envs' cores
do), what it measures each step (energy, momentum, heights: the figures the text's claim
is about) and what a frame shows. :func:`simulate` runs it; :mod:`bbgym.scenes.view` draws
it; ``bbgym scene`` does both from the command line.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.validation import build_params

BACKENDS = ("numpy", "torch")


def state_fields(*parts: type | str) -> type:
    """A NamedTuple base for a scene's state that holds a physics state and more: the
    fields of each NamedTuple class in ``parts`` in turn and each string as a field of its
    own, every one an array. The scene's class subclasses it (its docstring, and
    ``__slots__ = ()`` to stay a plain tuple), so the physics state's fields are listed in
    one place, and ``BallState(*state[:13])`` reads them back::

        class RollingBalls(state_fields(BallState, "moving_s")):
            \"\"\"The envs' ball state and how long each ball has moved.\"\"\"

            __slots__ = ()

    Args:
        parts: NamedTuple classes (their fields, in order) and field names.

    Returns:
        A NamedTuple class with those fields.
    """
    names: list[str] = []
    for part in parts:
        names.extend((part,) if isinstance(part, str) else part._fields)
    return NamedTuple("StateFields", [(name, Any) for name in names])


class Circle(NamedTuple):
    """A ball in a frame: centre and radius in metres, its colour and a short label."""

    x_m: float
    y_m: float
    radius_m: float
    color: tuple[int, int, int]
    label: str = ""


class Segment(NamedTuple):
    """A line in a frame (an arrow's shaft, a target's post), ends in metres."""

    x0_m: float
    y0_m: float
    x1_m: float
    y1_m: float
    color: tuple[int, int, int]
    width_px: int = 3


class Frame(NamedTuple):
    """What one frame of a scene shows, in the scene's side view (x right, y up)."""

    circles: list[Circle]
    segments: list[Segment] = []
    lines: list[str] = []
    """Text under the title: the measures the claim is about, now."""


class SceneFunctions(NamedTuple):
    """A scene's pure functions over its parameters and its batched state (on NumPy or
    torch, through ``xp``), as a task core's are over an env's
    (:class:`bbgym.envs.functional.TaskCore`: ``initial``, ``advance``, ``measure``)."""

    initial: Callable[[Any, Any], Any]
    """``initial(params, xp) -> state``."""
    step: Callable[[Any, Any, Any], Any]
    """``step(params, state, xp) -> state``: one time step of ``params.dt_s``."""
    measures: Callable[[Any, Any, Any], dict[str, Any]]
    """``measures(params, state, xp) -> {name: array (bodies,)}``."""
    frame: Callable[[Any, Any], Frame]
    """``frame(params, state) -> Frame`` (NumPy state)."""


@dataclass(frozen=True)
class Scene:
    """A scene of the course: its name, the text's section, what the text claims and what
    the tests check, and its pure functions."""

    name: str
    section: str
    """The course text's section, ``"§3"``."""
    title: str
    claim: str
    """What the text says the demo shows, as the test asserts it (one sentence)."""
    params: type
    """A frozen dataclass of the scene's parameters (SI units, accepted intervals)."""
    functions: SceneFunctions
    """Its initial state, step, measures and frame."""
    view_box_m: Callable[[Any], tuple[float, float, float, float]]
    """``view_box_m(params) -> (x_min, x_max, y_min, y_max)``: what the view shows."""
    duration_s: Callable[[Any], float]
    """``duration_s(params)``: how long a run lasts by default (its steps: this over
    ``params.dt_s``, rounded up)."""
    bodies: tuple[str, ...] = field(default=())
    """Each body's (row's) name, for the measures' table."""
    test: str = ""
    """The test that checks the claim (a function of ``tests/scenes/test_scenes*.py``)."""
    floor: bool = True
    """The view draws a floor at y = 0."""
    body_names: Callable[[Any], tuple[str, ...]] | None = None
    """``body_names(params)``, where the rows depend on the parameters (else ``bodies``)."""

    @property
    def initial(self) -> Callable[[Any, Any], Any]:
        """``initial(params, xp) -> state``."""
        return self.functions.initial

    @property
    def step(self) -> Callable[[Any, Any, Any], Any]:
        """``step(params, state, xp) -> state``: one time step of ``params.dt_s``."""
        return self.functions.step

    @property
    def measures(self) -> Callable[[Any, Any, Any], dict[str, Any]]:
        """``measures(params, state, xp) -> {name: array (bodies,)}``."""
        return self.functions.measures

    @property
    def frame(self) -> Callable[[Any, Any], Frame]:
        """``frame(params, state) -> Frame`` (NumPy state)."""
        return self.functions.frame

    def names(self, params: Any) -> tuple[str, ...]:
        """Each row's name for these parameters."""
        return self.body_names(params) if self.body_names is not None else self.bodies

    def make_params(self, values: Mapping[str, Any] | Any = None) -> Any:
        """The scene's parameters from ``None`` (defaults), a mapping or an instance; an
        error names ``<scene>.<field>``."""
        return build_params(self.params, self.name, values)


class Trajectory(NamedTuple):
    """A run of a scene: its parameters, the last state and each measure per step
    ``(steps + 1, bodies)`` (row 0 the initial state), as NumPy arrays."""

    params: Any
    state: Any
    measures: dict[str, np.ndarray]
    times_s: np.ndarray


def namespace(backend: str) -> Any:
    """The array namespace of ``backend`` (``"numpy"`` or ``"torch"``, the torch extra)."""
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {list(BACKENDS)}, got {backend!r}")
    if backend == "numpy":
        return np
    from bbgym.backends import resolve_backend

    return resolve_backend("torch", dtype="float64").xp


def to_numpy(value: Any) -> np.ndarray:
    """A NumPy copy of a NumPy or torch array."""
    from bbgym.backends import to_numpy as convert

    return np.asarray(convert(value), dtype=np.float64)


def simulate(
    scene: Scene,
    params: Mapping[str, Any] | Any = None,
    steps: int | None = None,
    backend: str = "numpy",
    on_step: Callable[[Any, Any], None] | None = None,
) -> Trajectory:
    """Run ``scene`` for ``steps`` steps (default its own) on ``backend`` in float64,
    recording its measures at every step; ``on_step(params, state)`` sees each state (the
    initial one first) as a copy in NumPy float64 arrays, whatever the backend."""
    p = scene.make_params(params)
    if steps is None:
        steps = math.ceil(scene.duration_s(p) / p.dt_s - 1e-9)
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 0:
        raise ValueError(f"steps must be an int >= 0, got {steps!r}")
    xp = namespace(backend)
    state = scene.initial(p, xp)
    rows: dict[str, list[np.ndarray]] = {}

    def record(state: Any) -> None:
        for name, value in scene.measures(p, state, xp).items():
            rows.setdefault(name, []).append(to_numpy(value))
        if on_step is not None:
            on_step(p, type(state)(*(to_numpy(v) for v in state)))

    record(state)
    for _ in range(steps):
        state = scene.step(p, state, xp)
        record(state)
    measures = {name: np.stack(values) for name, values in rows.items()}
    return Trajectory(p, state, measures, np.arange(steps + 1) * p.dt_s)


def summary_rows(trajectory: Trajectory, bodies: tuple[str, ...]) -> list[tuple[Any, ...]]:
    """``(measure, body, start, end, least, greatest)`` for each measure of each body of a
    run: what ``bbgym scene`` prints and the documentation's tables show."""
    rows = []
    for name, values in trajectory.measures.items():
        for k, body in enumerate(bodies):
            column = values[:, k]
            rows.append(
                (
                    name,
                    body,
                    *(float(v) for v in (column[0], column[-1], column.min(), column.max())),
                )
            )
    return rows
