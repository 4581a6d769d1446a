"""Region splits: every pixel of the frame in exactly one region, sensible shapes."""
import itertools
import time

import pytest

from zigzag_farm.regions import cuts, grid_shape, split_frame


def covers_exactly_once(regions, width, height):
    area = 0
    for r in regions:
        assert 0 <= r.x0 < r.x1 <= width and 0 <= r.y0 < r.y1 <= height, r
        area += r.pixels
    for a, b in itertools.combinations(regions, 2):
        overlap = (min(a.x1, b.x1) > max(a.x0, b.x0)) and (min(a.y1, b.y1) > max(a.y0, b.y0))
        assert not overlap, (a, b)
    return area == width * height  # no overlaps + full area = an exact cover


@pytest.mark.parametrize("width,height", [(128, 128), (1, 1), (7, 300), (1920, 1080), (16384, 16384), (65, 63)])
@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 6, 7, 12, 16])
def test_split_covers_the_frame_exactly_once(width, height, n):
    if n > width * height:
        return
    try:
        regions = split_frame(width, height, n)
    except ValueError:
        # Only when no factoring fits (e.g. 7 regions of a 1x1 frame).
        assert all(c > width or n // c > height for c in range(1, n + 1) if n % c == 0)
        return
    assert len(regions) == n
    assert covers_exactly_once(regions, width, height)


def test_shapes():
    assert grid_shape(128, 128, 4) == (2, 2)
    assert grid_shape(1920, 1080, 2) == (2, 1)  # two side-by-side halves of a wide frame
    assert grid_shape(1080, 1920, 2) == (1, 2)
    assert grid_shape(128, 128, 3) in ((1, 3), (3, 1))  # a prime: bands
    assert grid_shape(4096, 4096, 16) == (4, 4)


def test_cuts_on_tile_edges_when_big_enough():
    assert cuts(1024, 2) == [0, 512, 1024]
    assert all(c % 64 == 0 for c in cuts(1000, 3)[:-1]) and cuts(1000, 3)[-1] == 1000
    assert cuts(128, 4) == [0, 32, 64, 96, 128]  # regions under a tile: even split
    assert cuts(10, 3) == [0, 3, 6, 10]


def test_impossible_splits_are_refused():
    with pytest.raises(ValueError):
        split_frame(1, 1, 2)
    with pytest.raises(ValueError):
        split_frame(10, 10, 0)


def test_a_huge_region_count_fails_fast():
    started = time.monotonic()
    with pytest.raises(ValueError, match="it has 4096 pixels"):
        split_frame(64, 64, 1_000_000_000)
    # The largest counts a frame allows factor in O(sqrt(n)), not O(n).
    assert grid_shape(16384, 16384, 16384 * 16384) == (16384, 16384)
    assert grid_shape(16384, 16384, 16384 * 16381) == (16381, 16384)  # 16381 is a prime
    assert time.monotonic() - started < 1
