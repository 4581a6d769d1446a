"""Merging the `--stats` JSON of a frame's region jobs into one JSON for the frame.

Every numeric field of `zigzag render --stats` (host/app/render_stats_json.cpp) has one rule,
by dotted path (a rule on a dict covers everything under it):
- summed: counts (pixels, rays, zones, margin rays) and times. The parts' rays exceed a whole
  frame's by the level-1 corners along their seams, which each part traces for itself.
- pixel-weighted: per-pixel values and fractions, averaged weighted by each region's pixels.
- maximum: memory_estimate_bytes. Each region's estimate is for its own process, and the
  regions need not run at the same time, so the frame's honest figure is the largest one
  (a sum would claim memory no process needed; a full-frame render needs more than either).
- recomputed here: mrays_per_s (rays / render time), region (the union), output.
Everything else (scene, camera, frame, size, settings, triangle and light counts, BVH shape,
threads) is the same in every part and taken from the first; a value that differs between
parts is listed under farm.differing rather than hidden.
The result also says how the frame was made (`farm`: regions, job times, workers).
"""
from __future__ import annotations

import operator

SUMMED = {"pixels", "rays", "time_s", "bvh.build_s", "adaptive.zones_traced",
          "adaptive.zones_interpolated", "adaptive.margin_rays", "adaptive.time_s",
          "aov.primary_hit_rays", "aov.primary_hit_s", "nan_radiance", "layer_limit",
          "capped_radiance"}
PIXEL_WEIGHTED = {"rays_per_pixel", "padded", "geo_fraction", "adaptive.by_level", "adaptive.padded",
                  "adaptive.level2_fraction", "adaptive.level3_fraction",
                  "adaptive.vertical_fraction", "adaptive.geo_fraction",
                  "adaptive.hidden_fraction", "adaptive.specular_fraction",
                  "adaptive.gap_fraction"}
MAXIMUM = {"memory_estimate_bytes"}
RECOMPUTED = {"mrays_per_s", "region", "output"}
# The numbers that are the same in every region of a frame (tests/farm/test_stats.py checks
# that each numeric field of a real stats JSON is in exactly one of these sets).
SAME = {"camera", "width", "height", "frame", "scene_time_s", "fps", "threads", "spp",
        "triangles", "dropped_degenerate_triangles", "lights", "max_depth", "adaptive.eps",
        "adaptive.eps_specular", "bvh.nodes", "bvh.leaves", "bvh.max_depth", "bvh.sah_cost",
        "edge_settings"}


def _number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _combine(a, b, op):
    """a op b through nested dicts and equal-length lists; anything else keeps a."""
    if isinstance(a, dict) and isinstance(b, dict):
        return {k: _combine(a[k], b[k], op) if k in a and k in b else a.get(k, b.get(k))
                for k in {**a, **b}}
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        return [_combine(x, y, op) for x, y in zip(a, b)]
    if _number(a) and _number(b):
        return op(a, b)
    return a


def _scale(v, s):
    if isinstance(v, dict):
        return {k: _scale(x, s) for k, x in v.items()}
    if isinstance(v, list):
        return [_scale(x, s) for x in v]
    return v * s if _number(v) else v


def _rule(path: str) -> str | None:
    parts = path.split(".")
    for n in range(len(parts), 0, -1):
        prefix = ".".join(parts[:n])
        for rule, paths in (("sum", SUMMED), ("pixels", PIXEL_WEIGHTED), ("max", MAXIMUM)):
            if prefix in paths:
                return rule
    return None


def _fold(values: list, op):
    acc = values[0]
    for v in values[1:]:
        acc = _combine(acc, v, op)
    return acc


def _merge_value(path: str, values: list, weights: list[float], differing: list[str]):
    rule = _rule(path)
    if rule == "sum":
        return _fold(values, operator.add)
    if rule == "pixels":
        total = sum(weights) or 1.0
        return _fold([_scale(v, w / total) for v, w in zip(values, weights)], operator.add)
    if rule == "max":
        return _fold(values, max)
    if all(isinstance(v, dict) for v in values):
        return _merge_level(values, weights, path + ".", differing)
    if path not in RECOMPUTED and any(v != values[0] for v in values[1:]):
        differing.append(path)
    return values[0]


def _merge_level(parts: list[dict], weights: list[float], prefix: str, differing: list[str]) -> dict:
    out: dict = {}
    keys = list(dict.fromkeys(k for p in parts for k in p))
    for key in keys:
        present = [(p[key], w) for p, w in zip(parts, weights) if key in p]
        out[key] = _merge_value(prefix + key, [v for v, _ in present], [w for _, w in present],
                                differing)
    return out


def merge_stats(parts: list[dict], pixels: list[int], *, output: str, frame: int | None,
                job_seconds: list[float], workers: list[str], regions: list | None) -> dict:
    """One frame's stats from its jobs' stats (one job: that job's stats, annotated)."""
    present = [(p, w) for p, w in zip(parts, pixels) if p]
    differing: list[str] = []
    if present:
        merged = _merge_level([p for p, _ in present], [float(w) for _, w in present], "",
                              differing)
    else:
        merged = {}
    rays = merged.get("rays", {}).get("total")
    render_s = merged.get("time_s", {}).get("render")
    if rays is not None and render_s:
        merged["mrays_per_s"] = rays / render_s * 1e-6
    if regions:
        # The frame's stats cover the union of its parts (the whole frame).
        merged["region"] = [min(r[0] for r in regions), min(r[1] for r in regions),
                            max(r[2] for r in regions), max(r[3] for r in regions)]
    merged["output"] = output
    if frame is not None:
        merged["frame"] = frame
    merged["farm"] = {"jobs": len(parts), "regions": regions, "job_seconds": job_seconds,
                      "workers": workers}
    if differing:
        merged["farm"]["differing"] = differing
    return merged
