"""Small looping GIFs of long episodes: :class:`GifWriter`.

Three things keep a GIF small (a minute of a scene or a sailing episode: a few MB at most):

* **a frame budget**: past ``max_frames`` frames the writer keeps every second one (then
  every fourth, ...), each kept frame shown for the time of those it stands for, so the
  animation still plays in real time, at a lower frame rate. A held frame (``periods`` > 1:
  the end of a throw) and the last frame are always kept.
* **one palette for all frames**: the first frame's colours (median cut) and a fixed cube of
  colours for whatever comes later, every frame mapped to it without dithering. Pixels that
  did not change then keep their index, so each frame stores only the box that changed
  (Pillow's delta frames), and flat or smoothly shaded areas compress well.
* a frame identical to the one before is merged into it (its time added).
* **a size budget**: a GIF over ``max_bytes`` (2.8 MB) is written again with every second
  frame, until it fits.

Pillow only (the ``plots`` extra's, or the ``render`` extra's).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

MAX_GIF_FRAMES = 300
"""Frames a GIF keeps at most (by default): 30 s at 10 fps, 15 s at 20 fps."""
FIRST_FRAME_COLORS = 192
"""Palette entries taken by the first frame's colours..."""
CUBE_LEVELS = (0, 85, 170, 255)
"""...and a 4 x 4 x 4 cube of evenly spaced colours (64 entries) for colours that come later."""
MAX_GIF_BYTES = 2_800_000
"""A GIF larger than this is written again with every second frame (in real time still)."""
SLOW_WRITE_S = 2.0
"""Writing a GIF longer than this says so on stderr."""


def shared_palette(first: np.ndarray) -> Any:
    """A ``P`` image holding the palette every frame is mapped to: ``first``'s
    FIRST_FRAME_COLORS colours and the cube."""
    from PIL import Image

    image = Image.fromarray(np.asarray(first, dtype=np.uint8)).convert("RGB")
    own = image.quantize(FIRST_FRAME_COLORS, method=Image.Quantize.MEDIANCUT)
    colors = list(own.getpalette() or [])[: 3 * FIRST_FRAME_COLORS]
    colors += [0] * (3 * FIRST_FRAME_COLORS - len(colors))
    for r in CUBE_LEVELS:
        for g in CUBE_LEVELS:
            for b in CUBE_LEVELS:
                colors += [r, g, b]
    palette = Image.new("P", (1, 1))
    palette.putpalette(colors[:768])
    return palette


class GifWriter:
    """Collects frames and writes a looping GIF of at most ``max_frames`` frames at ``fps``.

    ``writer(frame, periods)`` adds an ``(H, W, 3)`` uint8 frame shown ``periods`` frame
    periods; ``close()`` writes the file. Frames are kept as palette images (a third of the
    memory of RGB); memory stays within ``max_frames`` of them, however long the episode.
    """

    def __init__(
        self,
        path: Path,
        fps: float,
        max_frames: int = MAX_GIF_FRAMES,
        max_bytes: int | None = MAX_GIF_BYTES,
    ) -> None:
        from PIL import Image

        if max_frames < 2:
            raise ValueError(f"max_frames must be >= 2, got {max_frames}")
        self._image = Image
        self.path, self.fps, self.max_frames = Path(path), fps, int(max_frames)
        self.max_bytes = max_bytes
        self.images: list[Any] = []
        self.durations: list[int] = []
        """Each kept frame's time on screen (ms)."""
        self.held: list[bool] = []
        self.stride = 1
        """Every ``stride``-th frame added is kept (doubled each time the budget fills)."""
        self.added = 0
        self._palette: Any = None
        self._pending: tuple[Any, float, bool] | None = None
        self._pending_index = 0

    def __call__(self, frame: np.ndarray, periods: int = 1) -> None:
        rgb = np.asarray(frame, dtype=np.uint8)
        if self._palette is None:
            self._palette = shared_palette(rgb)
        image = self._image.fromarray(rgb).convert("RGB")
        mapped = image.quantize(palette=self._palette, dither=self._image.Dither.NONE)
        if self._pending is not None:
            self._settle(*self._pending, index=self._pending_index)
        self._pending = (mapped, periods * 1000.0 / self.fps, periods > 1)
        self._pending_index = self.added
        self.added += 1

    def keeps(self, held: bool = False) -> bool:
        """Whether the next frame added could be kept: the first, a held one, or one on
        the stride. A frame it would not keep need not be drawn: :meth:`skip` stands for it,
        with the same file as a result (the stride only grows, so a frame off it now is
        off it when it settles).

        Args:
            held: Whether the frame is shown longer than one period.

        Returns:
            False where the frame would only add its time to the frame before it.
        """
        return held or (not self.images and self._pending is None) or self.added % self.stride == 0

    def skip(self, periods: int = 1) -> None:
        """Add a frame that :meth:`keeps` says is not kept, without its image: its time goes
        to the frame kept before it, as :meth:`__call__` would have done. Never the last
        frame (that one is always kept).

        Args:
            periods: The frame periods it is shown.

        Raises:
            ValueError: If the frame would be kept (:meth:`keeps` is True for it).
        """
        if self.keeps(periods > 1):
            raise ValueError("skip() of a frame the GIF keeps: add its image")
        if self._pending is not None:
            self._settle(*self._pending, index=self._pending_index)
            self._pending = None
        self.durations[-1] += periods * 1000.0 / self.fps
        self.added += 1

    def _settle(self, image: Any, ms: float, held: bool, index: int) -> None:
        """Keep a frame that waited (on the stride, held, or the first), else add its time
        to the frame kept before it."""
        if self.images and not held and index % self.stride != 0:
            self.durations[-1] += ms
            return
        self.images.append(image)
        self.durations.append(ms)
        self.held.append(held)
        if len(self.images) > self.max_frames - 1:  # room for the last frame, always kept
            self._halve()

    def _halve(self) -> None:
        """Keep every other frame (a held one over its neighbour), each taking the time of
        the pair, and keep every ``2 * stride``-th frame from now on."""
        images, durations, held = [], [], []
        for k in range(0, len(self.images), 2):
            pair = range(k, min(k + 2, len(self.images)))
            keep = next((j for j in pair if self.held[j]), k)
            images.append(self.images[keep])
            durations.append(sum(self.durations[j] for j in pair))
            held.append(any(self.held[j] for j in pair))
        self.images, self.durations, self.held = images, durations, held
        self.stride *= 2

    def close(self) -> None:
        if self._pending is not None:  # the last frame: always kept
            image, ms, held = self._pending
            self.images.append(image)
            self.durations.append(ms)
            self.held.append(True)  # kept through any halving below
            self._pending = None
        if not self.images:
            raise ValueError("no frames to write")
        start = time.perf_counter()
        self._save()
        while (
            self.max_bytes is not None
            and self.path.stat().st_size > self.max_bytes
            and len(self.images) > 2
        ):
            size = self.path.stat().st_size
            self._halve()
            message = (
                f"{self.path}: {size} bytes, over {self.max_bytes}: written again with "
                f"{len(self.images)} frames"
            )
            print(message, file=sys.stderr)
            self._save()
        took = time.perf_counter() - start
        if took > SLOW_WRITE_S:
            message = f"wrote {len(self.images)} GIF frames to {self.path} in {took:.1f} s"
            print(message, file=sys.stderr)

    def _save(self) -> None:
        # GIF times are in hundredths of a second: round the running total, not each frame
        ends = np.rint(np.cumsum(self.durations) / 10.0) * 10.0
        durations = np.diff(ends, prepend=0.0).astype(int).tolist()
        durations = [max(d, 10) for d in durations]
        self.images[0].save(
            self.path,
            save_all=True,
            append_images=self.images[1:],
            duration=durations if len(durations) > 1 else durations[0],
            loop=0,
            optimize=False,
        )
