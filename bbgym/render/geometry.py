"""Pure clipping geometry on pixel coordinates (no pygame): what :class:`SafeDraw` needs to
hand pygame only coordinates it can take, and where an off-screen marker's arrow goes.

pygame's drawing calls take C ints (``pygame.gfxdraw`` even 16-bit ones) and raise
``OverflowError`` past them; a huge circle or dashed ring can also take forever. So shapes are
clipped to :func:`safe_box` (the surface grown by SAFE_EXTENT_FACTOR of its size, within
GFX_SAFE_PX), keeping the visible part exact.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

Vec2 = tuple[float, float]
Color = tuple[int, int, int]
Box = tuple[float, float, float, float]  # x0, y0, x1, y1 in pixels (x1 > x0, y1 > y0)
RectLike = Sequence[float]  # x, y, width, height in pixels (a tuple or a pygame.Rect)

# --- safe drawing limits ---------------------------------------------------------------------
SAFE_EXTENT_FACTOR = 10.0  # shapes are clipped to the surface grown by 10 surface sizes...
GFX_SAFE_PX = 16_000.0  # ...but never past this: gfxdraw takes 16-bit ints (+-32767)
# Farther points are first pinned here (each axis), only so the clipping arithmetic cannot
# overflow; a line from a point in view keeps its direction exactly up to this.
PIN_PX = 1.0e150
ARC_MAX_ERROR_PX = 0.25  # a huge circle drawn as a polygon strays at most this far from it
ARC_MAX_POINTS = 4096


def safe_box(size: tuple[int, int]) -> Box:
    """The box shapes are clipped to: the surface grown by SAFE_EXTENT_FACTOR times its larger
    side on every side, but nowhere past +-GFX_SAFE_PX (16-bit gfxdraw stays well in range)."""
    width, height = size
    big = float(max(width, height))
    grow = max(min(SAFE_EXTENT_FACTOR * big, GFX_SAFE_PX - big), 0.0)
    return (-grow, -grow, width + grow, height + grow)


def is_finite_px(p: Sequence[float]) -> bool:
    """Both coordinates are finite numbers."""
    return math.isfinite(p[0]) and math.isfinite(p[1])


def in_box(p: Sequence[float], box: Box) -> bool:
    """``p`` lies in ``box`` (edges included); False for NaN."""
    return box[0] <= p[0] <= box[2] and box[1] <= p[1] <= box[3]


def pin_px(p: Sequence[float]) -> Vec2:
    """``p`` with each coordinate held within +-PIN_PX: within it the clip arithmetic below
    is exact to far under a pixel, and a line from a point in view keeps its direction."""
    return (min(max(float(p[0]), -PIN_PX), PIN_PX), min(max(float(p[1]), -PIN_PX), PIN_PX))


def clip_segment(a: Sequence[float], b: Sequence[float], box: Box) -> tuple[Vec2, Vec2] | None:
    """The part of segment ``a``-``b`` inside ``box`` (Liang-Barsky), or None if none is.

    An endpoint inside the box comes back unchanged, so a clipped polyline joins up exactly.
    """
    if not (is_finite_px(a) and is_finite_px(b)):
        return None
    a, b = pin_px(a), pin_px(b)
    dx, dy = b[0] - a[0], b[1] - a[1]
    t0, t1 = 0.0, 1.0
    edges = ((-dx, a[0] - box[0]), (dx, box[2] - a[0]), (-dy, a[1] - box[1]), (dy, box[3] - a[1]))
    for p, q in edges:
        if p == 0.0:
            if q < 0.0:
                return None  # parallel to this edge and outside it
            continue
        t = q / p
        if p < 0.0:
            t0 = max(t0, t)
        else:
            t1 = min(t1, t)
        if t0 > t1:
            return None
    start = a if t0 == 0.0 else _into(box, (a[0] + t0 * dx, a[1] + t0 * dy))
    end = b if t1 == 1.0 else _into(box, (a[0] + t1 * dx, a[1] + t1 * dy))
    return start, end


def _into(box: Box, p: Vec2) -> Vec2:
    """A point clipped onto an edge, held inside the box: from far endpoints (1e12 px) the
    interpolation's rounding alone can leave it a fraction of a pixel outside."""
    return (min(max(p[0], box[0]), box[2]), min(max(p[1], box[1]), box[3]))


def clip_polyline(points: Iterable[Sequence[float]], box: Box) -> list[list[Vec2]]:
    """The parts of an open polyline inside ``box``, as runs of two or more points.

    A non-finite point breaks the line there (nothing is drawn to or from it).
    """
    runs: list[list[Vec2]] = []
    run: list[Vec2] = []
    prev: Sequence[float] | None = None
    for p in points:
        if not is_finite_px(p):
            prev = None
            run = _flush(runs, run)
            continue
        if prev is not None:
            seg = clip_segment(prev, p, box)
            if seg is None:
                run = _flush(runs, run)
            elif run and run[-1] == seg[0]:
                run.append(seg[1])
            else:
                _flush(runs, run)
                run = [seg[0], seg[1]]
        prev = p
    _flush(runs, run)
    return runs


def _flush(runs: list[list[Vec2]], run: list[Vec2]) -> list[Vec2]:
    if len(run) >= 2:
        runs.append(run)
    return []


def clip_polygon(points: Iterable[Sequence[float]], box: Box) -> list[Vec2]:
    """The polygon cut to ``box`` (Sutherland-Hodgman): inside the box it covers exactly the
    same pixels; new edges run along the box's edges, which lie far off the surface. Empty if
    nothing is inside or a vertex is not finite."""
    pts = [pin_px(p) if is_finite_px(p) else None for p in points]
    if not pts or any(p is None for p in pts):
        return []
    out: list[Vec2] = pts  # type: ignore[assignment]
    for axis, bound, keep_above in (
        (0, box[0], True),
        (0, box[2], False),
        (1, box[1], True),
        (1, box[3], False),
    ):
        src, out = out, []
        for i, cur in enumerate(src):
            prev = src[i - 1]
            cur_in = cur[axis] >= bound if keep_above else cur[axis] <= bound
            prev_in = prev[axis] >= bound if keep_above else prev[axis] <= bound
            if cur_in != prev_in:
                t = (bound - prev[axis]) / (cur[axis] - prev[axis])
                cut = [prev[0] + t * (cur[0] - prev[0]), prev[1] + t * (cur[1] - prev[1])]
                cut[axis] = bound
                out.append((cut[0], cut[1]))
            if cur_in:
                out.append(cur)
        if not out:
            return []
    return out


def arc_span(center: Vec2, rx: float, ry: float, box: Box) -> tuple[float, float] | None:
    """Where the ellipse ``(cx + rx cos t, cy + ry sin t)`` may cross ``box``: an interval of
    ``t`` (at most 2 pi long) outside which its outline is certainly outside the box; None when
    the outline misses the box (the box is wholly outside the ellipse or wholly inside it)."""
    cx, cy = center
    # In units of the radii the ellipse is the unit circle about the origin.
    u0, u1 = (box[0] - cx) / rx, (box[2] - cx) / rx
    v0, v1 = (box[1] - cy) / ry, (box[3] - cy) / ry
    near_u, near_v = min(max(0.0, u0), u1), min(max(0.0, v0), v1)
    if math.hypot(near_u, near_v) > 1.0:
        return None
    if math.hypot(max(abs(u0), abs(u1)), max(abs(v0), abs(v1))) < 1.0:
        return None
    if u0 <= 0.0 <= u1 and v0 <= 0.0 <= v1:
        return (-math.pi, math.pi)
    # Seen from outside a convex box, its corners lie within half a turn of its middle.
    ref = math.atan2(0.5 * (v0 + v1), 0.5 * (u0 + u1))
    offsets = [
        (math.atan2(v, u) - ref + math.pi) % (2.0 * math.pi) - math.pi
        for u in (u0, u1)
        for v in (v0, v1)
    ]
    return (ref + min(offsets), ref + max(offsets))


def ellipse_covers(center: Vec2, rx: float, ry: float, box: Box) -> bool:
    """The filled ellipse covers the whole box."""
    cx, cy = center
    far_u = max(abs(box[0] - cx), abs(box[2] - cx)) / rx
    far_v = max(abs(box[1] - cy), abs(box[3] - cy)) / ry
    return math.hypot(far_u, far_v) <= 1.0


def arc_points(center: Vec2, rx: float, ry: float, span: tuple[float, float]) -> list[Vec2]:
    """Points along the ellipse over ``span`` of its parameter, close enough together that the
    polyline strays at most ARC_MAX_ERROR_PX from the curve (up to ARC_MAX_POINTS points)."""
    t0, t1 = span
    step = math.sqrt(8.0 * ARC_MAX_ERROR_PX / max(rx, ry, 1.0))
    n = min(max(math.ceil((t1 - t0) / step), 8), ARC_MAX_POINTS)
    cx, cy = center
    return [
        (cx + rx * math.cos(t0 + (t1 - t0) * k / n), cy + ry * math.sin(t0 + (t1 - t0) * k / n))
        for k in range(n + 1)
    ]


# --- where an off-screen marker goes ---------------------------------------------------------


def is_outside(p: Sequence[float], rect: RectLike, pad: float = 0.0) -> bool:
    """``p`` is outside ``rect`` grown by ``pad`` on every side, so a thing of that half-size
    centred there cannot be seen; False for a non-finite point (there is nowhere to point)."""
    if not is_finite_px(p):
        return False
    x, y, w, h = rect
    return not (x - pad <= p[0] < x + w + pad and y - pad <= p[1] < y + h + pad)


def edge_marker_tip(
    target_px: Sequence[float], rect: RectLike, margin_px: float
) -> tuple[Vec2, Vec2]:
    """Where an arrow to ``target_px`` goes: (tip, unit direction from the rect's centre to the
    target), the tip on the rect's edge inset by ``margin_px``."""
    x, y, w, h = rect
    cx, cy = x + w / 2.0, y + h / 2.0
    tx, ty = pin_px(target_px)
    dx, dy = tx - cx, ty - cy
    norm = math.hypot(dx, dy)
    if norm < 1e-9:
        return (cx, cy), (1.0, 0.0)
    ux, uy = dx / norm, dy / norm
    half_w, half_h = max(w / 2.0 - margin_px, 0.0), max(h / 2.0 - margin_px, 0.0)
    # Scale the direction until it hits the inset rectangle.
    scales = []
    if abs(ux) > 1e-12:
        scales.append(half_w / abs(ux))
    if abs(uy) > 1e-12:
        scales.append(half_h / abs(uy))
    scale = min(scales)
    return (cx + ux * scale, cy + uy * scale), (ux, uy)
