"""Merging the `--stats` JSON of a frame's region jobs into one JSON for the frame.

Counts (rays, zones, margin rays) and times are summed (the parts' rays exceed a whole
frame's by the level-1 corners along their seams, which each part traces for itself);
per-pixel values and fractions are
averaged weighted by each region's pixel count; everything else (scene, camera, settings,
triangle and light counts, BVH shape) is the same in every part and taken from the first.
The result also says how the frame was made (`farm`: regions, job times, workers).
"""
from __future__ import annotations

SUMMED = {"rays", "time_s", "zones_traced", "zones_interpolated", "margin_rays"}
PIXEL_WEIGHTED = {"rays_per_pixel", "by_level", "level2_fraction", "level3_fraction",
                  "vertical_fraction", "geo_fraction"}


def _add(a, b):
    if isinstance(a, dict) and isinstance(b, dict):
        return {k: _add(a[k], b[k]) if k in a and k in b else a.get(k, b.get(k)) for k in {**a, **b}}
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        return [_add(x, y) for x, y in zip(a, b)]
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        return a + b
    return a


def _scale(v, s):
    if isinstance(v, dict):
        return {k: _scale(x, s) for k, x in v.items()}
    if isinstance(v, list):
        return [_scale(x, s) for x in v]
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return v * s
    return v


def _merge_level(parts: list[dict], weights: list[float]) -> dict:
    total_w = sum(weights) or 1.0
    out: dict = {}
    for key in parts[0]:
        values = [p[key] for p in parts if key in p]
        if key in SUMMED:
            acc = values[0]
            for v in values[1:]:
                acc = _add(acc, v)
            out[key] = acc
        elif key in PIXEL_WEIGHTED:
            acc = _scale(values[0], weights[0] / total_w)
            for v, w in zip(values[1:], weights[1:]):
                acc = _add(acc, _scale(v, w / total_w))
            out[key] = acc
        elif all(isinstance(v, dict) for v in values) and len(values) == len(parts):
            out[key] = _merge_level(values, weights)
        else:
            out[key] = values[0]
    return out


def merge_stats(parts: list[dict], pixels: list[int], *, output: str, frame: int | None,
                job_seconds: list[float], workers: list[str], regions: list | None) -> dict:
    """One frame's stats from its jobs' stats (one job: that job's stats, annotated)."""
    present = [(p, w) for p, w in zip(parts, pixels) if p]
    if present:
        merged = _merge_level([p for p, _ in present], [float(w) for _, w in present])
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
    return merged
