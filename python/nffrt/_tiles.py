"""Regions of a split render and their assembly: the float counterpart of
``nffrt render --region`` and ``nffrt merge``.

Every pixel's value depends only on its absolute coordinates (sample positions
are hashed from them), so regions rendered apart and placed together equal the
whole render, bit for bit.
"""

from __future__ import annotations

from typing import Iterable, NamedTuple, Tuple

import numpy as np

from . import _nffrt


class Region(NamedTuple):
    """Columns ``x0..x1`` and rows ``y0..y1`` of an image (half-open: ``x1`` and
    ``y1`` are not included), as ``Scene.render(region=...)`` takes them."""

    x0: int
    y0: int
    x1: int
    y1: int

    @property
    def width(self) -> int:
        return self.x1 - self.x0

    @property
    def height(self) -> int:
        return self.y1 - self.y0

    def overlaps(self, other: "Region") -> bool:
        """True when the two regions share a pixel."""
        return (
            self.x0 < other.x1 and other.x0 < self.x1 and self.y0 < other.y1 and other.y0 < self.y1
        )

    def __str__(self) -> str:
        return f"{self.x0},{self.y0},{self.x1},{self.y1}"


def tiles(width: int, height: int, n: int) -> list[Region]:
    """``n`` bands of whole rows of a ``width`` x ``height`` image, top to bottom,
    their heights differing by at most one (``n`` from 1 to ``height``)."""
    return [Region(*r) for r in _nffrt.bands(width, height, n)]


def merge(
    pieces: Iterable[Tuple[Tuple[int, int, int, int], np.ndarray]],
) -> np.ndarray:
    """Assembles ``(region, array)`` pairs, in any order, into the full image.

    Each array must have shape ``(y1 - y0, x1 - x0, 3)``; the full image is as wide
    and tall as the regions reach, and they must not overlap and must cover it, as
    ``nffrt merge`` checks its tiles (``ValueError`` naming the offending regions or
    an uncovered pixel otherwise). The result is a new ``float32`` array.
    """
    placed: list[tuple[Region, np.ndarray]] = []
    for k, piece in enumerate(pieces):
        try:
            region, array = piece
            r = Region(*(int(v) for v in region))
        except (TypeError, ValueError) as e:
            raise ValueError(f"piece {k}: expected (region, array), region (x0, y0, x1, y1): {e}") from None
        if r.x0 < 0 or r.y0 < 0 or r.x0 >= r.x1 or r.y0 >= r.y1:
            raise ValueError(f"piece {k}: region {r} is empty or negative (x1 and y1 are exclusive)")
        array = np.asarray(array)
        if array.shape != (r.height, r.width, 3):
            raise ValueError(
                f"piece {k}: an array of shape {array.shape} cannot be region {r} "
                f"(expected {(r.height, r.width, 3)})"
            )
        placed.append((r, array))
    if not placed:
        raise ValueError("no pieces to merge")
    width = max(r.x1 for r, _ in placed)
    height = max(r.y1 for r, _ in placed)
    out = np.zeros((height, width, 3), dtype=np.float32)
    covered = np.zeros((height, width), dtype=bool)
    for k, (r, array) in enumerate(placed):
        if covered[r.y0 : r.y1, r.x0 : r.x1].any():
            other = next(o for o, _ in placed[:k] if o.overlaps(r))
            raise ValueError(f"regions {other} and {r} overlap")
        covered[r.y0 : r.y1, r.x0 : r.x1] = True
        out[r.y0 : r.y1, r.x0 : r.x1] = array
    if not covered.all():
        y, x = (int(v) for v in np.argwhere(~covered)[0])
        raise ValueError(
            f"the regions cover {int(covered.sum())} of the {width * height} pixels of the "
            f"{width}x{height} image, e.g. pixel ({x}, {y}) is in none"
        )
    return out

