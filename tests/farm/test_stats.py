"""Merging the stats of a frame's region jobs into one JSON per frame."""
import pytest

from zigzag_farm.stats import merge_stats


def part(primary, total, rpp, render_s, fraction):
    return {"scene": "room", "region": [0, 0, 1, 1], "camera": 0, "width": 128, "height": 128, "triangles": 1000,
            "effects": ["shadows"], "rays_per_pixel": rpp,
            "rays": {"primary": primary, "total": total},
            "adaptive": {"eps": 0.05, "by_level": [1.0, rpp - 1.0, 0.0], "level2_fraction": fraction,
                         "zones_traced": 10, "time_s": {"level1_corners": 0.5}},
            "bvh": {"nodes": 77, "build_s": 0.01},
            "time_s": {"render": render_s, "total": render_s + 0.5}, "mrays_per_s": 1.0}


def test_counts_add_and_per_pixel_values_are_pixel_weighted():
    a, b = part(1000, 3000, 2.0, 1.0, 0.1), part(3000, 5000, 4.0, 3.0, 0.5)
    m = merge_stats([a, b], [1000, 3000], output="/o/x.png", frame=7, job_seconds=[1.5, 3.5],
                    workers=["w1", "w2"], regions=[[0, 0, 10, 100], [10, 0, 40, 100]])
    assert m["rays"] == {"primary": 4000, "total": 8000}
    assert m["time_s"] == {"render": 4.0, "total": 5.0}
    assert m["rays_per_pixel"] == pytest.approx((2.0 * 1000 + 4.0 * 3000) / 4000)
    assert m["adaptive"]["level2_fraction"] == pytest.approx((0.1 * 1000 + 0.5 * 3000) / 4000)
    assert m["adaptive"]["by_level"] == pytest.approx([1.0, 2.5, 0.0])
    assert m["adaptive"]["zones_traced"] == 20
    assert m["adaptive"]["time_s"]["level1_corners"] == pytest.approx(1.0)
    assert m["adaptive"]["eps"] == 0.05 and m["triangles"] == 1000 and m["bvh"]["nodes"] == 77
    assert m["mrays_per_s"] == pytest.approx(8000 / 4.0 * 1e-6)
    assert m["frame"] == 7 and m["output"] == "/o/x.png"
    assert m["region"] == [0, 0, 40, 100]
    assert m["farm"] == {"jobs": 2, "regions": [[0, 0, 10, 100], [10, 0, 40, 100]],
                         "job_seconds": [1.5, 3.5], "workers": ["w1", "w2"]}


def test_a_single_job_keeps_its_stats():
    a = part(1000, 3000, 2.0, 1.0, 0.1)
    m = merge_stats([a], [1], output="/o/x.png", frame=None, job_seconds=[1.0], workers=["w"],
                    regions=None)
    assert m["rays"] == a["rays"] and m["rays_per_pixel"] == 2.0 and m["adaptive"] == a["adaptive"]
    assert "frame" not in m and m["farm"]["jobs"] == 1


def test_jobs_without_stats():
    m = merge_stats([None, None], [1, 1], output="/o/x.png", frame=1, job_seconds=[1, 1],
                    workers=["a", "b"], regions=None)
    assert m["farm"]["jobs"] == 2 and "rays" not in m
