"""Splitting a frame into N regions (a grid, or bands when N has no better factoring).

Region bounds are half-open pixel rectangles, the `zigzag render --region X0,Y0,X1,Y1`
convention. The renderer guarantees any split merges bit-identical to the full frame; the
split here only chooses shapes that keep the work per region even and the regions close to
square (less filter margin per pixel), with edges on the renderer's 64-pixel tile grid when
the frame is big enough.
"""
from __future__ import annotations

from dataclasses import dataclass

TILE = 64  # the renderer's tile size: regions cut on tile edges waste no partial tiles


@dataclass(frozen=True)
class Region:
    x0: int
    y0: int
    x1: int
    y1: int

    @property
    def bounds(self) -> tuple[int, int, int, int]:
        return (self.x0, self.y0, self.x1, self.y1)

    @property
    def pixels(self) -> int:
        return (self.x1 - self.x0) * (self.y1 - self.y0)

    def arg(self) -> str:
        return f"{self.x0},{self.y0},{self.x1},{self.y1}"


def grid_shape(width: int, height: int, n: int) -> tuple[int, int]:
    """(columns, rows) with columns*rows == n whose cells are closest to square."""
    best = None
    for cols in range(1, n + 1):
        if n % cols:
            continue
        rows = n // cols
        if cols > width or rows > height:
            continue
        aspect = (width / cols) / (height / rows)
        score = max(aspect, 1 / aspect)
        if best is None or score < best[0]:
            best = (score, cols, rows)
    if best is None:
        raise ValueError(f"cannot split a {width}x{height} frame into {n} regions")
    return best[1], best[2]


def cuts(length: int, count: int, quantum: int = TILE) -> list[int]:
    """count+1 increasing edges from 0 to length, even, on multiples of quantum when possible."""
    even = [i * length // count for i in range(count + 1)]
    if length // count < quantum:
        return even
    snapped = [0] + [round(e / quantum) * quantum for e in even[1:-1]] + [length]
    if all(a < b for a, b in zip(snapped, snapped[1:])):
        return snapped
    return even


def split_frame(width: int, height: int, n: int) -> list[Region]:
    """n regions that cover the width x height frame exactly once, row-major order."""
    if n < 1:
        raise ValueError("--regions must be at least 1")
    cols, rows = grid_shape(width, height, n)
    xs, ys = cuts(width, cols), cuts(height, rows)
    return [Region(xs[c], ys[r], xs[c + 1], ys[r + 1]) for r in range(rows) for c in range(cols)]
