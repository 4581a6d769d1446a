"""Merging the stats of a frame's region jobs into one JSON per frame."""
import json
import os
import subprocess

import pytest

from conftest import REAL_ZIGZAG, ROOT
from zigzag_farm import stats
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


def real_shaped(i, pixels, x0, x1):
    """A region's stats as `zigzag render --region ... --stats` writes them (the field set of
    host/app/render_stats_json.cpp), with values that differ by region where they can."""
    return {
        "scene": "default", "camera": 0, "output": f"/w/part{i}.exr", "width": 64, "height": 64,
        "region": [x0, 0, x1, 64], "pixels": pixels, "animated": False, "frame": 0,
        "scene_time_s": 0.0, "fps": 24.0, "threads": 2, "aa": "adaptive",
        "adaptive": {"eps": 0.05, "eps_specular": 0.01, "tables": "tuned", "filter": "box",
                     "highlights": True, "by_level": [1.0 + i, 0.5 * i, 2.0],
                     "padded": 0.01 * i, "level2_fraction": 0.1 * i, "level3_fraction": 0.2,
                     "vertical_fraction": 0.05 * i, "zones_traced": 100 * (i + 1),
                     "zones_interpolated": 10 * i, "margin_rays": 7 * i,
                     "geo_fraction": 0.3 * i, "hidden_fraction": 0.02 * i,
                     "specular_fraction": 0.1 + 0.1 * i, "gap_fraction": 0.01 * (3 - i),
                     "time_s": {"level1_corners": 0.1 * (i + 1), "levels_2_3": 0.2,
                                "mitchell_filter": 0.0}},
        "triangles": 1724, "dropped_degenerate_triangles": 0, "lights": 2, "max_depth": 2,
        "effects": ["shadows", "reflection"], "rays_per_pixel": 4.0 + i,
        "rays": {"primary": 1000 * (i + 1), "shadow": 500, "reflection": 20 * i,
                 "refraction": 3, "continuation": 0, "total": 1523 + 1020 * i},
        "nan_radiance": i % 2,
        "layer_limit": 3 * i,
        "capped_radiance": 5 * i,
        "bvh": {"nodes": 278, "leaves": 532, "max_depth": 11, "sah_cost": 12.75, "build_s": 0.001},
        "time_s": {"load": 0.1, "bvh": 0.001, "render": 0.5 + i, "frame": 0.6 + i, "write": 0.01,
                   "total": 0.8 + i, "edges": {"device_wait": 0.02, "upload": 0.001, "prepare": 0.002,
                                               "raster": 0.01, "compute": 0.003, "readback": 0.0,
                                               "total": 0.017}},
        "memory_estimate_bytes": 200_000_000 + 1_000_000 * i * (3 - i), "edges": "vulkan",
        "geo_fraction": 0.3 * i,
        "edge_settings": {"supersample": 4, "normal_angle_deg": 25.0, "depth_rel": 0.02, "material": True},
        "mrays_per_s": 3.0 + i, "vulkan_device": "llvmpipe",
    }


def leaves(d, prefix=""):
    for k, v in d.items():
        if isinstance(v, dict):
            yield from leaves(v, prefix + k + ".")
        else:
            yield prefix + k, v


def test_four_real_shaped_regions_merge_by_the_class_of_each_field():
    bounds = [(0, 10), (10, 30), (30, 40), (40, 64)]
    pixels = [(x1 - x0) * 64 for x0, x1 in bounds]
    parts = [real_shaped(i, px, x0, x1) for i, (px, (x0, x1)) in enumerate(zip(pixels, bounds))]
    m = merge_stats(parts, pixels, output="/o/f.png", frame=0, job_seconds=[1, 2, 3, 4],
                    workers=["a", "b", "c", "d"], regions=[[x0, 0, x1, 64] for x0, x1 in bounds])
    by_path = [dict(leaves(p)) for p in parts]
    merged = dict(leaves(m))

    def weighted(path):
        return sum(p[path] * w for p, w in zip(by_path, pixels)) / sum(pixels)

    # Summed: counts and times.
    assert m["pixels"] == 64 * 64
    for path in ["rays.primary", "rays.reflection", "rays.total", "adaptive.zones_traced",
                 "adaptive.zones_interpolated", "adaptive.margin_rays", "adaptive.time_s.level1_corners",
                 "time_s.render", "time_s.edges.raster", "bvh.build_s", "nan_radiance", "layer_limit",
                 "capped_radiance"]:
        assert merged[path] == pytest.approx(sum(p[path] for p in by_path)), path
    # Pixel-weighted: per-pixel values and fractions.
    for path in ["rays_per_pixel", "geo_fraction", "adaptive.padded", "adaptive.level2_fraction",
                 "adaptive.vertical_fraction", "adaptive.geo_fraction", "adaptive.hidden_fraction",
                 "adaptive.specular_fraction", "adaptive.gap_fraction"]:
        assert merged[path] == pytest.approx(weighted(path)), path
    assert m["adaptive"]["by_level"] == pytest.approx(
        [sum(p["adaptive"]["by_level"][k] * w for p, w in zip(parts, pixels)) / sum(pixels) for k in range(3)])
    # The largest: memory (each region's process needs its own; they need not run together).
    assert m["memory_estimate_bytes"] == max(p["memory_estimate_bytes"] for p in parts) > parts[0]["memory_estimate_bytes"]
    # Recomputed for the frame.
    assert m["mrays_per_s"] == pytest.approx(m["rays"]["total"] / m["time_s"]["render"] * 1e-6)
    assert m["region"] == [0, 0, 64, 64] and m["output"] == "/o/f.png"
    # The same in every region: taken as is, and nothing was found to differ.
    for path in ["width", "height", "triangles", "bvh.nodes", "adaptive.eps", "edge_settings.supersample", "threads"]:
        assert merged[path] == by_path[0][path], path
    assert "differing" not in m["farm"]


def test_a_field_that_should_be_equal_but_differs_is_reported():
    a, b = real_shaped(0, 640, 0, 10), real_shaped(1, 1280, 10, 30)
    b["triangles"] = 1
    m = merge_stats([a, b], [640, 1280], output="/o/f.png", frame=0, job_seconds=[1, 1],
                    workers=["a", "b"], regions=[[0, 0, 10, 64], [10, 0, 30, 64]])
    assert m["farm"]["differing"] == ["triangles"] and m["triangles"] == 1724


def rule_sets_of(path):
    parts = path.split(".")
    prefixes = {".".join(parts[:n]) for n in range(1, len(parts) + 1)}
    return [name for name, paths in (("SUMMED", stats.SUMMED), ("PIXEL_WEIGHTED", stats.PIXEL_WEIGHTED),
                                      ("MAXIMUM", stats.MAXIMUM), ("RECOMPUTED", stats.RECOMPUTED),
                                      ("SAME", stats.SAME)) if prefixes & paths]


def test_every_numeric_field_of_the_real_renderers_stats_has_exactly_one_rule(tmp_path):
    if not os.access(REAL_ZIGZAG, os.X_OK):
        pytest.skip(f"no {REAL_ZIGZAG}")
    out, js = str(tmp_path / "x.exr"), str(tmp_path / "x.json")
    p = subprocess.run([REAL_ZIGZAG, "render", os.path.join(ROOT, "scenes", "default.json"), "-o", out,
                        "--width", "32", "--height", "32", "--region", "0,0,16,32", "--stats", js, "-q"],
                       capture_output=True, text=True)
    if p.returncode != 0:
        pytest.skip(f"the real renderer cannot render here: {p.stderr}")
    real = json.load(open(js))
    numeric = [path for path, v in leaves(real)
               if isinstance(v, (int, float, list)) and not isinstance(v, bool)
               and not (isinstance(v, list) and not all(isinstance(x, (int, float)) for x in v))]
    unruled = {path: rule_sets_of(path) for path in numeric if len(rule_sets_of(path)) != 1}
    assert unruled == {}
    # ... and the merge test above covers every one of them.
    assert set(numeric) - set(dict(leaves(real_shaped(0, 1, 0, 1)))) == set()
