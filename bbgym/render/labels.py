"""Placing text labels beside the things they name so that no two overlap (pure geometry, no
pygame): :func:`place_labels`.

Each label has an anchor (a disc: the thing it names) and a measured size in pixels. The
labels are placed in turn, each at the first of a list of spots around its anchor (below,
above, right, left, then further out, row by row) whose box stays inside the frame and
meets no box already placed nor any obstacle (the anchors' discs, a title band). Where none
is free, the spot that overlaps the least is taken. :func:`boxes_overlap` is the test the
layout (and the tests of the pictures) use.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from bbgym.render.geometry import Box

LABEL_GAP_PX = 2.0
"""Space kept between a label and its anchor's disc."""
MAX_RINGS = 12
"""How many rows out (in label heights) a label may move from its anchor."""


def boxes_overlap(a: Box, b: Box) -> bool:
    """The boxes ``(x0, y0, x1, y1)`` share some area (touching edges do not count)."""
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def overlap_area(a: Box, b: Box) -> float:
    """Area the two boxes share (0 where they do not overlap)."""
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    return max(w, 0.0) * max(h, 0.0)


def disc_box(x: float, y: float, r: float) -> Box:
    """The box around the disc of radius ``r`` at ``(x, y)``."""
    return (x - r, y - r, x + r, y + r)


def candidate_spots(x: float, y: float, r: float, w: float, h: float) -> Iterable[Box]:
    """Boxes of a ``w`` x ``h`` label around the disc at ``(x, y)`` of radius ``r``, nearest
    first: below, above, right, left; then each further out by a label height."""
    g = r + LABEL_GAP_PX
    for ring in range(MAX_RINGS + 1):
        d = ring * (h + 1.0)
        yield (x - w / 2, y + g + d, x + w / 2, y + g + d + h)  # below
        yield (x - w / 2, y - g - d - h, x + w / 2, y - g - d)  # above
        yield (x + g, y - h / 2 + d, x + g + w, y + h / 2 + d)  # right, stepping down
        yield (x - g - w, y - h / 2 + d, x - g, y + h / 2 + d)  # left, stepping down
        if ring:
            yield (x + g, y - h / 2 - d, x + g + w, y + h / 2 - d)  # right, stepping up
            yield (x - g - w, y - h / 2 - d, x - g, y + h / 2 - d)  # left, stepping up


def place_labels(
    anchors: Sequence[tuple[float, float, float]],
    sizes: Sequence[tuple[float, float]],
    bounds: Box,
    obstacles: Sequence[Box] = (),
) -> list[Box]:
    """A box for each label: ``sizes[i]`` (its width and height, measured) beside the disc
    ``anchors[i]`` ``(x, y, radius)``, inside ``bounds`` where it fits, and overlapping no
    other label, no anchor's disc and no ``obstacles`` where any free spot is left."""
    taken: list[Box] = [*obstacles, *(disc_box(*a) for a in anchors)]
    placed: list[Box] = []
    for (x, y, r), (w, h) in zip(anchors, sizes, strict=True):
        best, best_cost = None, float("inf")
        for spot in candidate_spots(x, y, r, w, h):
            # a spot off the frame is pulled back inside it (it may then meet its disc)
            dx = max(bounds[0] - spot[0], 0.0) - max(spot[2] - bounds[2], 0.0)
            dy = max(bounds[1] - spot[1], 0.0) - max(spot[3] - bounds[3], 0.0)
            spot = (spot[0] + dx, spot[1] + dy, spot[2] + dx, spot[3] + dy)
            cost = sum(overlap_area(spot, other) for other in (*taken, *placed))
            if cost < best_cost:
                best, best_cost = spot, cost
            if cost == 0.0:
                break
        assert best is not None
        placed.append(best)
    return placed
