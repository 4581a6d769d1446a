"""Measuring one point (scene x setting): N timed renders, stats, error against the reference."""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from PIL import Image

import metrics
import zzrun
from settings import Setting


@dataclass
class Context:
    zigzag: Path
    assets: Path
    size: int
    threads: int
    runs: int
    work: Path          # scratch: EXRs, stats, display PNGs of every point
    cache: Path         # references, kept across report runs
    ref_spp: int
    binary: str = ""    # the zigzag binary's digest
    # What a row was measured under, per scene stem (report.py's conditions): a resumed row
    # measured under others is dropped and measured again.
    conditions: dict = field(default_factory=dict)


@dataclass
class Reference:
    linear: np.ndarray
    display: np.ndarray
    stats: dict


def exposure_of(scene: Path) -> float:
    return float(json.loads(scene.read_text()).get("exposure", 1.0))


def load_reference(ctx: Context, scene: Path) -> Reference:
    exr, stats = zzrun.cached_reference(ctx.zigzag, scene, ctx.assets, ctx.size, ctx.ref_spp,
                                        ctx.threads, ctx.cache)
    linear = metrics.read_exr(exr)
    disp = metrics.display(linear, exposure_of(scene))
    save_png(disp, ctx.work / scene.stem / "reference.png")
    return Reference(linear, disp, stats)


def save_png(display01: np.ndarray, path: Path) -> None:
    """The display image as an 8-bit PNG: for the crops and for looking at, not for the metrics."""
    path.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(metrics.eight_bit(display01)).save(path)


def stage_times(stats: dict) -> dict:
    """Per-stage wall seconds from --stats. `image_s` is the frame's wall time (visibility map and
    render, which overlap: zigzag makes the map on its own thread while level 1 traces, so their
    sum would count the overlap twice); `edges_s` is the map's own wall time beside level 1."""
    t = stats.get("time_s", {})
    edges = t.get("edges") if isinstance(t.get("edges"), dict) else {}
    out = {"load_s": t.get("load", 0.0), "bvh_s": t.get("bvh", 0.0), "edges_s": edges.get("total", 0.0),
           "render_s": t.get("render", 0.0), "write_s": t.get("write", 0.0),
           "total_s": t.get("total", 0.0)}
    out["image_s"] = t.get("frame", out["edges_s"] + out["render_s"])
    # The wait for the Vulkan device that loading did not hide: before a scene's first frame,
    # outside image_s (a single image pays it, a sequence once).
    out["device_wait_s"] = edges.get("device_wait", 0.0)
    return out


def median_run(runs: list[dict]) -> dict:
    """The run whose frame time (image_s) is the median, the lower of the middle two for an even
    count. A row takes every time from this one run: medians taken key by key would mix runs, so
    the map's time could exceed the frame's or the stages stop adding up."""
    return sorted(runs, key=lambda r: r["timing"]["image_s"])[(len(runs) - 1) // 2]


def measure_render(ctx: Context, scene: Path, setting: Setting, ref: Reference | None) -> dict:
    """Renders one point ctx.runs times; returns its CSV row."""
    folder = ctx.work / scene.stem
    folder.mkdir(parents=True, exist_ok=True)
    exr = folder / f"{setting.label}.exr"
    (folder / f"{setting.label}.png").unlink(missing_ok=True)  # a failed run leaves no older image for the crops
    aov = folder / f"{setting.label}_rays.png" if setting.mode == "adaptive" else None
    args = [*setting.render_args(), "--assets", str(ctx.assets)]
    runs = []
    for i in range(setting.timed_runs(ctx.runs)):
        res = zzrun.render(ctx.zigzag, scene, ctx.size, ctx.threads, args, exr,
                           folder / f"{setting.label}.json", aov if i == 0 else None)
        runs.append({"timing": {**stage_times(res.stats), "wall_s": res.wall_s, "cpu_s": res.cpu_s},
                     "maxrss_mb": res.maxrss_mb, "stats": res.stats})
    linear = metrics.read_exr(exr)
    disp = metrics.display(linear, exposure_of(scene))
    save_png(disp, folder / f"{setting.label}.png")
    exr.unlink()  # display PNG kept for crops; EXRs are large
    median = median_run(runs)
    row = base_row(scene.stem, setting, median["stats"])
    row.update({k: float(v) for k, v in median["timing"].items()})
    row["maxrss_mb"] = max(r["maxrss_mb"] for r in runs)  # peak memory: the largest of the runs, not a time
    row.update({"rmse": np.nan, "psnr": np.nan, "rmse_display": np.nan, "flip": np.nan,
                "binary": ctx.binary, "ref_spp": ctx.ref_spp, "conditions": ctx.conditions.get(scene.stem, "")})
    if ref is not None:  # None: a timing-only run (--no-reference)
        err = metrics.rmse(linear, ref.linear)
        row.update({"rmse": err, "psnr": metrics.psnr(err), "rmse_display": metrics.rmse(disp, ref.display),
                    "flip": metrics.mean_flip(disp, ref.display)})
    return row


def base_row(scene: str, s: Setting, stats: dict) -> dict:
    ad = stats.get("adaptive", {})
    levels = ad.get("by_level", [np.nan] * 3)
    rays = stats.get("rays", {})
    px = stats.get("width", 1) * stats.get("height", 1)
    return {
        "scene": scene, "mode": s.mode, "setting": s.label, "family": s.family,
        "pattern": s.pattern, "spp": s.spp if s.mode != "adaptive" else "",
        "eps": s.eps if s.eps is not None else "",
        "edges": s.edges if s.mode == "adaptive" else "", "filter": s.filter if s.mode == "adaptive" else "",
        "tables": s.tables if s.mode == "adaptive" else "", "geo_policy": s.geo if s.mode == "adaptive" else "",
        "signature": s.signature if s.mode == "adaptive" else "",
        "highlights": s.highlights if s.mode == "adaptive" else "",
        "textures": s.textures if s.mode == "adaptive" else "",
        "curvature": s.curvature if s.mode == "adaptive" else "",
        "material": s.material if s.mode == "adaptive" else "",
        "hdr": s.hdr if s.mode == "adaptive" else "",
        "footprint": s.footprint if s.mode == "adaptive" else "",
        "orient": s.orient if s.mode == "adaptive" else "",
        "zones": s.zones if s.mode == "adaptive" else "",
        "split": s.split if s.mode == "adaptive" else "",
        "eps_specular": s.eps_spec if s.mode == "adaptive" else "",
        "gaps": s.gaps if s.mode == "adaptive" else "",
        "hidden_fraction": ad.get("hidden_fraction", ""),
        "width": stats.get("width"), "height": stats.get("height"),
        "threads": stats.get("threads"), "triangles": stats.get("triangles"),
        "lights": stats.get("lights"), "max_depth": stats.get("max_depth"),
        "rays_per_px": stats.get("rays_per_pixel"),
        "all_rays_per_px": rays.get("total", np.nan) / px,
        "shadow_rays_per_px": rays.get("shadow", np.nan) / px,
        "rays_l1": levels[0], "rays_l2": levels[1], "rays_l3": levels[2],
        "level2_fraction": ad.get("level2_fraction", ""), "level3_fraction": ad.get("level3_fraction", ""),
        "geo_fraction": stats.get("geo_fraction", ""),
    }


def measure_star(ctx: Context, setting: Setting, geo_ss: int) -> list[dict]:
    """The analytic star: adaptive vs exact coverage, plus the harness's own baselines."""
    folder = ctx.work / "star"
    folder.mkdir(parents=True, exist_ok=True)
    res = zzrun.analytic(ctx.zigzag, "star", ctx.size, ctx.threads,
                         setting.analytic_args(geo_ss), folder / f"{setting.label}.json")
    rows = []
    for run in res.stats["runs"]:
        method = run["method"]
        if method == "adaptive":
            s = setting
        else:
            s = {"1spp": Setting("none"), "lattice25": Setting("uniform", 25, "lattice"),
                 "grid5x5": Setting("uniform", 25, "grid")}[method]
        levels = run.get("rays_by_level", [np.nan] * 3)
        row = base_row("star", s, {"width": ctx.size, "height": ctx.size, "threads": ctx.threads,
                                   "rays_per_pixel": run["rays_per_pixel"]})
        row.update({"rays_l1": levels[0], "rays_l2": levels[1], "rays_l3": levels[2],
                    "level2_fraction": run["level2_fraction"], "level3_fraction": run["level3_fraction"],
                    "geo_fraction": run.get("geo_pixels", 0) / ctx.size ** 2 if method == "adaptive" else "",
                    "rmse": run["rmse"], "psnr": metrics.psnr(run["rmse"]), "flip": np.nan,
                    "rmse_display": np.nan, "pixels_off": run.get("pixels_off"),
                    "binary": ctx.binary, "ref_spp": ctx.ref_spp, "conditions": ctx.conditions.get("star", "")})
        rows.append(row)
    return rows
