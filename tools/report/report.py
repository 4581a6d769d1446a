#!/usr/bin/env python3
"""The accuracy/time report: renders every benchmark scene with the real `zigzag` command in
uniform and adaptive modes, measures time, rays and error against a reference, and writes
reports/accuracy_vs_time.csv, plots, crops and REPORT.md.

    ./zz report            # 1024^2, full (pruned) grid, 3 timed runs per point
    ./zz report --quick    # 256^2, a few points, 1 run: the smoke test in ./zz test
"""
from __future__ import annotations

import argparse
import csv
import datetime
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import crops  # noqa: E402
import markdown  # noqa: E402
import measure  # noqa: E402
import plots  # noqa: E402
import settings  # noqa: E402
import zzrun  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SCENES = ["room", "glass", "car", "lamp", "vase"]
QUICK_SCENES = ["room", "glass"]


def parse_args(argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", type=Path, default=ROOT / "build", help="build dir holding zigzag")
    p.add_argument("--quick", action="store_true", help="256^2, few points, 1 run (smoke test)")
    p.add_argument("--size", type=int, help="frame size N (N x N); default 1024, quick 256")
    p.add_argument("--runs", type=int, help="timed runs per point (median); default 3, quick 1")
    p.add_argument("--threads", type=int, default=2, help="renderer threads (fixed for all points)")
    p.add_argument("--ref-spp", type=int, help="reference stratified rays/px; default 256, quick 64")
    p.add_argument("--scenes", nargs="*", help=f"subset of {SCENES + ['star']}")
    p.add_argument("--assets", type=Path, default=Path(os.environ.get("ZIGZAG_ASSETS", ROOT.parent / "shared" / "scenes")))
    p.add_argument("--out", type=Path, help="output folder; default reports/ (quick: BUILD/report-quick)")
    p.add_argument("--resume", action="store_true", help="keep points already measured in the work folder")
    p.add_argument("--no-star", action="store_true", help="skip the analytic Siemens star")
    p.add_argument("--report-only", action="store_true",
                   help="no rendering: rewrite the outputs from the rows measured so far (implies --resume)")
    p.add_argument("--note", action="append", default=[], help="a caveat paragraph for REPORT.md (repeatable)")
    p.add_argument("--only", nargs="*", help="measure only these setting labels (see the CSV's setting column)")
    p.add_argument("--no-reference", action="store_true", help="timing and rays only: no reference, no error")
    p.add_argument("--table2-extra", type=Path, nargs="*", default=[],
                   help="accuracy_vs_time.csv of other runs (e.g. a larger frame) to add to Table 2")
    a = p.parse_args(argv)
    a.size = a.size or (256 if a.quick else 1024)
    a.runs = a.runs or (1 if a.quick else 3)
    a.ref_spp = 0 if a.no_reference else a.ref_spp or (64 if a.quick else 256)
    if a.no_reference and not a.out and not a.quick:
        p.error("--no-reference needs --out: its report has no errors and would replace the committed reports/")
    a.out = a.out or (a.build / "report-quick" if a.quick else ROOT / "reports")
    return a


def log(msg: str) -> None:
    print(f"[{datetime.datetime.now():%H:%M:%S}] {msg}", flush=True)


def available_scenes(args) -> tuple[list[Path], list[str]]:
    default = QUICK_SCENES if args.quick else SCENES
    names = [s for s in (args.scenes or default) if s != "star"]
    scenes, skipped = [], []
    for name in names:
        path = ROOT / "scenes" / f"{name}.json"
        why = zzrun.missing_assets(path, args.assets)
        if why:
            log(f"SKIP {why} (put the Khronos models there or pass --assets)")
            skipped.append(why)
        else:
            scenes.append(snapshot(path, args))
    return scenes, skipped


def snapshot(scene: Path, args) -> Path:
    """Copies the rig and its own glTF/buffers (not the shared assets) into the work folder, so
    a scene regenerated while the report runs cannot mix two versions into one comparison."""
    folder = args.work / "scenes"
    folder.mkdir(parents=True, exist_ok=True)
    for f in zzrun.scene_files(scene, args.assets):
        if f.is_relative_to(scene.parent):
            target = folder / f.relative_to(scene.parent)
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(f, target)
    return folder / scene.name


class RowStore:
    """Rows appended to a JSONL file as they are measured, so a long run can --resume.

    `conditions` (scene stem -> what its rows are measured under: the reference's key, i.e. the
    binary, the scene's files, the size and the reference's rays/px, and the threads and runs):
    a resumed row measured under others is dropped and measured again, so one report never mixes
    two renderers, references or settings. None keeps every row (--report-only rewrites the
    outputs of the run that measured them)."""

    def __init__(self, path: Path, resume: bool, conditions: dict[str, str] | None = None):
        self.path = path
        self.rows = []
        if resume and path.exists():
            rows = [json.loads(line) for line in path.read_text().splitlines() if line]
            # Scenes this run does not measure keep their rows (a --scenes subset, missing assets).
            self.rows = [r for r in rows if conditions is None or r["scene"] not in conditions
                         or r.get("conditions") == conditions[r["scene"]]]
            if len(self.rows) < len(rows):
                log(f"--resume: {len(rows) - len(self.rows)} of {len(rows)} rows were measured with another "
                    "zigzag binary, scene file, size, reference, thread or run count; measuring them again")
                path.write_text("".join(json.dumps(r, default=float) + "\n" for r in self.rows))
        elif path.exists():
            path.unlink()

    def has(self, scene: str, setting: str) -> bool:
        return any(r["scene"] == scene and r["setting"] == setting for r in self.rows)

    def add(self, rows: list[dict]) -> None:
        with open(self.path, "a") as f:
            for r in rows:
                f.write(json.dumps(r, default=float) + "\n")
        self.rows += rows


def measure_scenes(ctx, scenes, points, store: RowStore, failed: list[str]) -> dict:
    """Measures every point not in the store; a point that fails is logged and named in `failed`
    (REPORT.md lists them and the run exits 1: its row is missing from every table)."""
    refs_stats = {}
    for scene in scenes:
        t0 = time.time()
        ref = None
        if ctx.ref_spp > 0:
            log(f"{scene.stem}: reference {ctx.ref_spp} rays/px stratified at {ctx.size}^2 (cached)")
            ref = measure.load_reference(ctx, scene)
            refs_stats[scene.stem] = ref.stats
        for s in points:
            if store.has(scene.stem, s.label):
                continue
            try:
                row = measure.measure_render(ctx, scene, s, ref)
            except (RuntimeError, OSError, ValueError) as e:
                log(f"{scene.stem}: {s.label} FAILED: {e}")
                failed.append(f"{scene.stem}: `{s.label}` failed ({e}); its row is missing from every table")
                continue
            store.add([row])
            log(f"{scene.stem}: {s.label:55s} {row['rays_per_px']:6.2f} rays/px "
                f"{row['image_s']:7.3f} s  rmse {row['rmse']:.5f}  flip {row['flip']:.4f}")
        log(f"{scene.stem}: done in {time.time() - t0:.0f} s")
    return refs_stats


def measure_star(ctx, points, store: RowStore, geo_ss: int = 4) -> None:
    baselines_done = store.has("star", "none")
    for s in points:
        if store.has("star", s.label):
            continue
        rows = measure.measure_star(ctx, s, geo_ss)
        keep = [r for r in rows if r["mode"] == "adaptive" or not baselines_done]
        baselines_done = True
        store.add(keep)
        a = rows[0]
        log(f"star: {s.label:55s} {a['rays_per_px']:6.2f} rays/px  rmse {a['rmse']:.5f}")


def write_csv(rows: list[dict], path: Path) -> None:
    keys = list(dict.fromkeys(k for r in rows for k in r))
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: _fmt(r.get(k, "")) for k in keys})


def _fmt(v):
    return f"{v:.6g}" if isinstance(v, float) else v


def environment(args, zigzag: Path) -> dict:
    def git(*cmd):
        try:
            return subprocess.run(["git", "-C", str(ROOT), *cmd], capture_output=True, text=True).stdout.strip()
        except OSError:
            return "?"
    return {"date": f"{datetime.datetime.now():%Y-%m-%d %H:%M}", "commit": git("rev-parse", "--short", "HEAD"),
            "dirty": bool(git("status", "--porcelain", "--", "host", "shaders", "tools", "scenes")),
            "size": args.size, "runs": args.runs, "threads": args.threads, "ref_spp": args.ref_spp,
            "cores": os.cpu_count(), "loadavg": os.getloadavg(), "binary_digest": zzrun.file_digest([zigzag])[:12],
            "quick": args.quick, "argv": " ".join(sys.argv[1:])}


def measured_references(rows: list[dict], cache: Path) -> dict:
    """--report-only: the stats of the references the rows were measured against, found by the key
    and rays/px the rows carry (not this invocation's binary and --ref-spp: a rebuild since, or
    the default --ref-spp, would name other references or none)."""
    refs = {}
    for r in rows:
        key = str(r.get("conditions") or "").split(":")[0]
        if r["scene"] == "star" or r["scene"] in refs or not key:
            continue
        path = cache / f"{r['scene']}_{r['width']}_{r['ref_spp']}_{key}.json"
        if path.exists():
            refs[r["scene"]] = json.loads(path.read_text())
    return refs


def warn_mixed(rows: list[dict]) -> None:
    """Rows kept by --resume (scenes this run did not measure) or rewritten by --report-only may
    come from several binaries or references: REPORT.md's header lists them all; say so here too."""
    for key, what in (("binary", "zigzag binaries"), ("ref_spp", "reference rays/px")):
        values = {str(r.get(key)) for r in rows if r.get(key) not in (None, "") and not (key == "ref_spp" and r["scene"] == "star")}
        if len(values) > 1:
            log(f"WARNING: the rows come from several {what} ({', '.join(sorted(values))}); "
                "REPORT.md's header lists each with its scenes")


def main(argv: list[str]) -> int:
    args = parse_args(argv)
    zigzag = args.build / "zigzag"
    if not zigzag.exists():
        sys.exit(f"report: {zigzag} not found (build first: ./zz build)")
    args.out.mkdir(parents=True, exist_ok=True)
    work = args.build / ("report-work-quick" if args.quick else f"report-work-{args.size}")
    work.mkdir(parents=True, exist_ok=True)
    args.work = work
    env = environment(args, zigzag)
    ctx = measure.Context(zigzag, args.assets, args.size, args.threads, args.runs, work,
                          args.build / "report-cache", args.ref_spp, env["binary_digest"])
    log(f"zigzag {zigzag} ({env['binary_digest']}), {args.size}^2, {args.runs} run(s), "
        f"{args.threads} threads, load {env['loadavg'][0]:.1f}")
    points = settings.uniform_settings(args.quick) + settings.adaptive_settings(args.quick)
    if args.only:
        points = [p for p in points if p.label in args.only]
    scenes, skipped = available_scenes(args)
    failed: list[str] = []
    how = f":{args.threads}t:{args.runs}r"
    ctx.conditions = {s.stem: zzrun.reference_key(zigzag, s, args.assets, args.size, args.ref_spp) + how for s in scenes}
    ctx.conditions["star"] = f"{env['binary_digest']}:{args.size}" + how
    store = RowStore(work / "rows.jsonl", args.resume or args.report_only, None if args.report_only else ctx.conditions)
    if args.report_only:
        refs = measured_references(store.rows, ctx.cache)
    else:
        refs = measure_scenes(ctx, scenes, points, store, failed)
        if not args.no_star and not args.no_reference and (not args.scenes or "star" in args.scenes):
            measure_star(ctx, settings.star_settings(args.quick), store)
    env["loadavg_end"] = os.getloadavg()
    env["notes"] = args.note
    run_file = work / "run.json"
    if args.report_only and run_file.exists():
        env = {**env, **json.loads(run_file.read_text())}  # describe the measuring run, not this one
        env["notes"] = args.note or env.get("notes", [])
    elif not args.report_only:
        run_file.write_text(json.dumps(env))
    rows = store.rows
    warn_mixed(rows)
    write_csv(rows, args.out / "accuracy_vs_time.csv")
    choice = markdown.choose_defaults(rows, markdown.TARGET_SCENES)
    figures = plots.all_plots(rows, args.out, ROOT / "tools" / "table_tuner" / "pareto.csv", choice["label"])
    figures += crops.all_crops(rows, work, args.out, choice)
    extra = [r for f in args.table2_extra for r in csv.DictReader(open(f))]
    markdown.write_report(args.out / "REPORT.md", rows, env, refs, skipped + [f"FAILED: {f}" for f in failed],
                          choice, figures, settings.measured_grid(env["runs"]), extra)
    log(f"wrote {args.out / 'REPORT.md'} and {len(figures)} figures")
    if failed:
        log(f"{len(failed)} point(s) failed: " + "; ".join(failed))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
