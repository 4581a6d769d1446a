"""Plots (matplotlib, Agg): error vs time and vs rays/px with the Pareto front, stage bars,
the table tuner's Pareto curve."""
from __future__ import annotations

import csv
import math
from pathlib import Path

import matplotlib.pyplot as plt

# Stacked, so they must not overlap: the frame holds the visibility map and the render, which
# run side by side (the map is drawn over the frame's bar, not on top of it).
STAGES = [("load_s", "load"), ("bvh_s", "BVH"), ("image_s", "frame (map + trace + AA + filter)"),
          ("write_s", "write")]


def finite(v) -> bool:
    return isinstance(v, (int, float)) and math.isfinite(v) and v > 0


def pareto_front(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Points not dominated in (cost, error), both minimised, sorted by cost."""
    front, best = [], math.inf
    for x, y in sorted(points):
        if y < best:
            front.append((x, y))
            best = y
    return front


def series(rows: list[dict]) -> dict[str, list[dict]]:
    """Rows grouped into curves; `none` (1 ray/px) starts every uniform curve."""
    groups: dict[str, list[dict]] = {}
    none = [r for r in rows if r["mode"] == "none"]
    for r in rows:
        if r["mode"] == "adaptive" or r["mode"] == "uniform" and r["pattern"] != "lattice":
            groups.setdefault(r["family"], []).append(r)
    for name, members in groups.items():
        if name.startswith("uniform"):
            members[:0] = none
            members.sort(key=lambda r: r["rays_per_px"])
        else:
            members.sort(key=lambda r: r["eps"])
    return groups


def style(family: str) -> dict:
    if family.startswith("uniform grid"):
        return {"color": "tab:blue", "marker": "s", "ls": "-"}
    if family.startswith("uniform stratified"):
        return {"color": "tab:cyan", "marker": "D", "ls": "-"}
    colors = {"paper": "tab:red", "tuned": "tab:green", "all": "tab:purple"}
    table = family.split()[1].split("/")[0]
    marker = "o" if "/vulkan/" in family else "^"
    ls = "-" if family.endswith("box") and "geo paper" in family else ":"
    return {"color": colors.get(table, "tab:gray"), "marker": marker, "ls": ls}


def error_axes(ax, rows: list[dict], xkey: str, ykey: str) -> None:
    for name, members in series(rows).items():
        pts = [(r[xkey], r[ykey]) for r in members if finite(r.get(xkey)) and finite(r.get(ykey))]
        if pts:
            st = style(name)
            if len(pts) == 1:
                st["ls"] = "none"
            ax.plot(*zip(*pts), label=name, ms=4, lw=1.2, **st)
    for r in rows:
        if r["mode"] == "none" and finite(r.get(xkey)) and finite(r.get(ykey)):
            ax.plot(r[xkey], r[ykey], "kx", ms=7, label="1 ray/px")
        if r["pattern"] == "lattice" and finite(r.get(xkey)) and finite(r.get(ykey)):
            ax.plot(r[xkey], r[ykey], "k*", ms=10, label="uniform 25 lattice")
    front = pareto_front([(r[xkey], r[ykey]) for r in rows if finite(r.get(xkey)) and finite(r.get(ykey))])
    if front:
        ax.step(*zip(*front), where="post", color="k", lw=0.8, ls="--", alpha=0.6)
        ax.plot(*zip(*front), "o", mfc="none", mec="k", ms=9, label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.25)


def scene_error_plot(rows: list[dict], scene: str, out: Path) -> Path:
    rows = [r for r in rows if r["scene"] == scene]
    timed = any(finite(r.get("image_s")) for r in rows)
    has = {k: any(finite(r.get(k)) for r in rows) for k in ("rmse_display", "flip")}
    xs = ([("image_s", "frame time: visibility map and render [s]")] if timed else []) + [("rays_per_px", "primary rays / pixel")]
    # Display RMSE is the metric of the targets and of the rule that picks the defaults.
    ys = ([("rmse", "RMSE (linear HDR)")] + ([("rmse_display", "RMSE (display, the targets')")] if has["rmse_display"] else [])
          + ([("flip", "mean FLIP (display)")] if has["flip"] else []))
    fig, axes = plt.subplots(len(ys), len(xs), figsize=(5.2 * len(xs), 3.3 * len(ys)), squeeze=False)
    for i, (yk, yl) in enumerate(ys):
        for j, (xk, xl) in enumerate(xs):
            error_axes(axes[i][j], rows, xk, yk)
            axes[i][j].set_xlabel(xl)
            axes[i][j].set_ylabel(yl)
    handles, labels = axes[0][-1].get_legend_handles_labels()
    uniq = dict(zip(labels, handles))
    ncol = 3 if len(xs) > 1 else 1  # one column of plots (no times: the star) is too narrow for three
    fig.legend(uniq.values(), uniq.keys(), loc="lower center", ncol=ncol, fontsize=7, frameon=False)
    fig.suptitle(f"{scene}: error vs cost (uniform and adaptive; dashed = Pareto front)", fontsize=12 if ncol > 1 else 9)
    # The legend's own height in inches below the axes, whatever the number of rows of plots.
    legend_in = 0.3 + 0.19 * math.ceil(len(uniq) / ncol)
    width, height = fig.get_size_inches()
    fig.set_size_inches(width, height + legend_in)
    fig.tight_layout(rect=(0, legend_in / (height + legend_in), 1, 1 - 0.23 / (height + legend_in)))
    path = out / f"error_{scene}.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def stage_bars(rows: list[dict], picks: dict[str, str], out: Path) -> Path:
    """Stacked wall seconds per stage for a few settings in every rendered scene."""
    scenes = list(dict.fromkeys(r["scene"] for r in rows if finite(r.get("total_s"))))
    fig, axes = plt.subplots(1, len(scenes), figsize=(2.6 * len(scenes) + 1, 4), squeeze=False, sharey=False)
    colors = ["#bbbbbb", "#8c564b", "#1f77b4", "#2ca02c"]
    for ax, scene in zip(axes[0], scenes):
        by_label = {r["setting"]: r for r in rows if r["scene"] == scene}
        names = [n for n in picks if picks[n] in by_label]
        bottom = [0.0] * len(names)
        for (key, label), color in zip(STAGES, colors):
            vals = [float(by_label[picks[n]].get(key) or 0.0) for n in names]
            if key == "image_s":
                frame_bottom = list(bottom)
            ax.bar(names, vals, bottom=bottom, color=color, label=label)
            bottom = [b + v for b, v in zip(bottom, vals)]
        edges = [float(by_label[picks[n]].get("edges_s") or 0.0) for n in names]
        ax.bar(names, edges, bottom=frame_bottom, width=0.3, color="#ff7f0e",
               label="visibility map (its own thread, within the frame)")
        ax.set_title(scene)
        ax.tick_params(axis="x", rotation=60, labelsize=7)
        ax.set_ylabel("wall s (median)")
    axes[0][0].legend(fontsize=7)
    fig.suptitle("Time per stage (from --stats)")
    fig.tight_layout()
    path = out / "stages.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def tuner_pareto(csv_path: Path, out: Path) -> Path | None:
    if not csv_path.exists():
        return None
    rows = list(csv.DictReader(open(csv_path)))
    fig, ax = plt.subplots(figsize=(5.5, 4))
    tuned = sorted((float(r["rays_per_px_held_out"]), float(r["error_held_out"]))
                   for r in rows if r["set"] == "tuned")
    ax.plot(*zip(*tuned), "o-", color="tab:green", label="tuned (one λ each), held-out")
    for r in rows:
        if r["set"] in ("paper", "all"):
            ax.plot(float(r["rays_per_px_held_out"]), float(r["error_held_out"]), "s", ms=8,
                    label=f"{r['set']} tables", color="tab:red" if r["set"] == "paper" else "tab:purple")
    ax.set_xlabel("rays / pixel on the tuner's population (edge pixels only)")
    ax.set_ylabel("mean |error| vs 25-point lattice")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=8)
    ax.set_title("Table tuner: Pareto curve (held-out configurations)")
    fig.tight_layout()
    path = out / "tuner_pareto.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def all_plots(rows: list[dict], out: Path, tuner_csv: Path, chosen: str) -> list[tuple[str, Path]]:
    from settings import PAPER_POINT, LATTICE25
    import dataclasses
    figs = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        figs.append((f"error vs cost: {scene}", scene_error_plot(rows, scene, out)))
    picks = {"1 ray/px": "none", "uniform grid 25": "uniform-grid-25", "lattice 25": LATTICE25.label,
             "adaptive (the paper's eps 0.1)": PAPER_POINT.label,
             "adaptive edges off": dataclasses.replace(PAPER_POINT, edges="off").label}
    if chosen not in picks.values():
        picks["adaptive (recommended)"] = chosen
    if any(finite(r.get("total_s")) for r in rows):
        figs.append(("time per stage", stage_bars(rows, picks, out)))
    t = tuner_pareto(tuner_csv, out)
    if t:
        figs.append(("table tuner Pareto curve", t))
    return figs
