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


def _factor_pairs(n: int):
    """(a, n // a) and (n // a, a) for every divisor a <= sqrt(n): O(sqrt(n)), not O(n)."""
    a = 1
    while a * a <= n:
        if n % a == 0:
            yield a, n // a
            yield n // a, a
        a += 1


def grid_shape(width: int, height: int, n: int) -> tuple[int, int]:
    """(columns, rows) with columns*rows == n whose cells are closest to square."""
    if n > width * height:  # checked first: a huge n must fail at once, not after a search
        raise ValueError(f"cannot split a {width}x{height} frame into {n} regions "
                         f"(it has {width * height} pixels)")
    best = None
    for cols, rows in _factor_pairs(n):
        if cols > width or rows > height:
            continue
        aspect = (width / cols) / (height / rows)
        score = max(aspect, 1 / aspect)
        if best is None or (score, cols) < (best[0], best[1]):
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
