"""Fuzzing the course's scenes (``bbgym.scenes``): every parameter over its interval, the
counts capped (:data:`SCENE_MOST_BODIES`), on NumPy and torch."""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import fields
from typing import Any

import numpy as np

from bbgym.fuzz.draws import (
    Draw,
    draw_flag,
    draw_int,
    sample_params,
)
from bbgym.fuzz.envs import (
    _numpy,
)
from bbgym.physics.validation import Interval, interval

# -- the course's scenes --------------------------------------------------------------------------

SCENE_BACKENDS = ("numpy", "torch")
"""The array namespaces :func:`check_scene` runs a scene on (``bbgym.scenes.simulate``'s)."""

SCENE_MOST_BODIES = {"numpy": 256, "torch": 64}
"""The most bodies a scene check draws, by backend: a count field (particles, balls,
points, blocks; a grid's side counts its ``side ** dims`` cells) is drawn up to this or
four times its low end, whichever is larger. The intervals reach 65,536 SPH particles or a
128 x 128 spring grid (the bench's sizes), seconds a step; 256 keep a check of
:data:`SCENE_STEPS` steps on NumPy under about a second, 64 on torch, whose eager step on a
CPU is some hundred small kernels (a dam-break step of 256 particles takes 0.1 s)."""

SCENE_NOT_COUNTS = ("seed",)
"""Integer fields of the scenes' parameters that count nothing the step loops over."""

SCENE_GRID_SIDES = ("size",)
"""Integer fields that are a grid's side: its cells are ``side ** params.shape_dims``."""

SCENE_ORDERED = (
    ("speed_min_mps", "speed_max_mps"),
    ("angle_min_deg", "angle_max_deg"),
    ("mu_kinetic", "mu_static"),
    ("thickness_m", "base_depth_m"),
    ("water_width_m", "box_width_m"),
    ("water_height_m", "box_height_m"),
    ("radius_m", "drop_height_m"),
)
"""Pairs of fields a scene's rule orders (``low <= high``, or ``<``: the water inside the
dam-break's box, a ball dropped from above its radius): drawn, then sorted where the
sorted pair still lies in both intervals, that most draws are run rather than refused
(each rule alone would refuse half)."""

SCENE_SHARES = {"jitter_under_half_spacing": ("jitter_m", "spacing_m", 0.5)}
"""Fields a scene's rule bounds by a share of another (a spring grid's jitter under half
its spacing): half the draws are redrawn under that bound, the other half keep the whole
interval (and are refused where they break the rule). A rule that most draws break would
leave its scene hardly run otherwise (the grids' jitter, in [0, 1] m, against spacings
from 5 cm)."""

SCENE_STEPS = 40
"""Steps of a scene check in the long run."""


def scene_count_caps(params_class: type, most_bodies: int) -> dict[str, Interval]:
    """The intervals :func:`sample_scene_params` draws a scene's counts from: each integer
    field but :data:`SCENE_NOT_COUNTS` up to ``max(most_bodies, 4 * low)`` bodies (a grid
    side of :data:`SCENE_GRID_SIDES` up to the side of that many cells).

    Args:
        params_class: a scene's parameter dataclass.
        most_bodies: the bodies allowed (:data:`SCENE_MOST_BODIES`).

    Returns:
        The capped intervals, by field name (only those the cap narrows).
    """
    caps = {}
    for f in fields(params_class):
        accepted = f.metadata.get("interval")
        if accepted is None or not f.metadata.get("integer") or f.name in SCENE_NOT_COUNTS:
            continue
        dims = getattr(params_class, "shape_dims", 1) if f.name in SCENE_GRID_SIDES else 1
        low = int(accepted.low)
        most = max(most_bodies, 4 * low**dims)
        side = int(math.floor(most ** (1.0 / dims) + 1e-9))
        if side < accepted.high:
            caps[f.name] = interval(low, max(low, side))
    return caps


def _scene_choices(params_class: type) -> dict[str, tuple[int, ...]]:
    """Integer fields whose accepted values are a set inside their interval, as their
    docstrings say: a spring grid's ``neighbours`` (4, 6 or 8 in 2D: no grid has 5 or 7)."""
    if "neighbours" not in {f.name for f in fields(params_class)}:
        return {}
    from bbgym.scenes.springs import neighbour_counts

    accepted = next(f for f in fields(params_class) if f.name == "neighbours").metadata["interval"]
    counts = neighbour_counts(params_class.shape_dims)
    return {"neighbours": tuple(n for n in counts if accepted.contains(n))}


def sample_scene_params(
    scene: Any, draw: Draw, most_bodies: int = SCENE_MOST_BODIES["numpy"]
) -> dict[str, Any]:
    """A scene's parameters: every field over its accepted interval (log-uniform where it
    is positive, ends included), its counts capped (:func:`scene_count_caps`), ordered
    pairs sorted (:data:`SCENE_ORDERED`), a field taking a set of values drawn from it.

    Args:
        scene: a :class:`bbgym.scenes.Scene`.
        draw: draws each number.
        most_bodies: the bodies a count may reach (:data:`SCENE_MOST_BODIES`).

    Returns:
        The parameters by field name, for ``simulate(scene, params)``.
    """
    cls = scene.params
    values = sample_params(draw, cls, scene.name, scene_count_caps(cls, most_bodies))
    for name, choices in _scene_choices(cls).items():
        values[name] = choices[draw_int(draw, f"{scene.name}.{name}", 0, len(choices) - 1)]
    for small, large in SCENE_ORDERED:
        if small in values and large in values:
            lo, hi = sorted((values[small], values[large]))
            if _field_accepts(cls, small, lo) and _field_accepts(cls, large, hi):
                values[small], values[large] = lo, hi
    for share, (small, large, most) in SCENE_SHARES.items():
        if small in values and large in values and draw_flag(draw, f"{scene.name}.{share}"):
            accepted = next(f for f in fields(cls) if f.name == small).metadata["interval"]
            below = interval(accepted.low, min(accepted.high, most * values[large]), high_open=True)
            if below.low < below.high:
                values[small] = draw(f"{scene.name}.{small}", below, False)
    return values


def _field_accepts(cls: type, name: str, value: float) -> bool:
    accepted = next(f for f in fields(cls) if f.name == name).metadata["interval"]
    return accepted.contains(value)


def _refusal_names_another_field(scene: Any, message: str, fields_drawn: list[str]) -> bool:
    """Whether a scene's ``ValueError`` is a documented refusal of a combination: it
    begins with ``<scene>.`` and names a field besides the one it begins with."""
    if not message.startswith(f"{scene.name}."):
        return False
    head = message[len(scene.name) + 1 :]
    first = next(
        (n for n in sorted(fields_drawn, key=len, reverse=True) if head.startswith(n)), None
    )
    others = [n for n in fields_drawn if n != first]
    return any(re.search(rf"\b{re.escape(n)}\b", message) for n in others)


def check_scene(
    name: str, params: Mapping[str, Any], steps: int, backend: str = "numpy"
) -> int | None:
    """Run scene ``name`` with ``params`` (inside their intervals) for ``steps`` steps on
    ``backend`` and check it: every measure finite, one column per body, every float of
    its last state finite. A ``ValueError`` building the parameters that begins with
    ``<scene>.`` and names another field is a documented refusal of a combination
    (``arrow.target_distance_m: out of range at this speed_mps``); any other raises
    ``AssertionError`` (the interval promised a value the scene does not take).

    Args:
        name: a key of ``bbgym.scenes.SCENES``.
        params: the scene's parameters (:func:`sample_scene_params`).
        steps: steps to run.
        backend: one of :data:`SCENE_BACKENDS`.

    Returns:
        ``steps``, or ``None`` where the scene refused the combination.
    """
    from bbgym.scenes import SCENES, simulate

    scene = SCENES[name]
    where = f"scene {name} ({backend})"
    try:
        built = scene.make_params(params)
    except ValueError as error:
        if _refusal_names_another_field(scene, str(error), [f.name for f in fields(scene.params)]):
            return None
        raise AssertionError(
            f"{where}: refused values inside their intervals with {error!r}, "
            f"which names no other field"
        ) from None
    run = simulate(scene, built, steps, backend)
    bodies = len(scene.names(built))
    for measure, values in run.measures.items():
        if values.shape != (steps + 1, bodies):
            raise AssertionError(
                f"{where}: measure {measure} has shape {values.shape}, "
                f"expected {(steps + 1, bodies)}"
            )
        if not np.isfinite(values).all():
            step = int(np.argwhere(~np.isfinite(values))[0][0])
            raise AssertionError(
                f"{where}: non-finite {measure} at step {step}: {values[step].tolist()}"
            )
    for field_name, value in zip(type(run.state)._fields, run.state, strict=True):
        array = np.asarray(_numpy(value))
        if array.dtype.kind in "fc" and not np.isfinite(array).all():
            raise AssertionError(f"{where}: non-finite value in the last state's {field_name}")
    return steps


def installed_scene_backends(backends: tuple[str, ...] | None = None) -> tuple[str, ...]:
    """The :data:`SCENE_BACKENDS` installed here (torch's with the ``torch`` extra).

    Args:
        backends: keep only these (``run``'s vector paths), if given.

    Returns:
        The backends, NumPy first.
    """
    import importlib.util

    have = importlib.util.find_spec("torch") is not None
    return tuple(
        b for b in SCENE_BACKENDS if (b == "numpy" or have) and (backends is None or b in backends)
    )
