"""Running the real `zigzag` command: one render or analytic run, timed, with its --stats JSON.

Time is measured three ways for every run: the process wall clock, the process CPU time
(user + sys of the child and its threads, from wait4), and the per-stage wall times the
renderer writes into --stats. Peak memory is the child's ru_maxrss.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import subprocess
import time
from pathlib import Path


@dataclasses.dataclass
class RunResult:
    wall_s: float            # process wall clock
    cpu_s: float             # user + sys CPU of the process (all its threads)
    maxrss_mb: float         # peak resident memory
    stats: dict              # the --stats JSON (render) or --json (analytic)


def run_timed(cmd: list[str], log: Path | None = None) -> tuple[float, float, float]:
    """Runs cmd to completion; returns (wall s, cpu s, peak MB). Raises on failure."""
    start = time.perf_counter()
    out = open(log, "w") if log else subprocess.DEVNULL
    try:
        proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT)
        # wait4 gives the rusage of this one child, not of all children so far.
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
    finally:
        if log:
            out.close()
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        detail = log.read_text()[-2000:] if log and log.exists() else ""
        raise RuntimeError(f"command failed ({proc.returncode}): {' '.join(cmd)}\n{detail}")
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


def render(zigzag: Path, scene: Path, size: int, threads: int, args: list[str],
           out_image: Path, stats: Path, aov_rays: Path | None = None) -> RunResult:
    """One `zigzag render` of camera 0 of a scene at size x size."""
    cmd = [str(zigzag), "render", str(scene), "-q", "--width", str(size), "--height", str(size),
           "--threads", str(threads), "-o", str(out_image), "--stats", str(stats), *args]
    if aov_rays is not None:
        cmd += ["--aov", "rays", str(aov_rays)]
    wall, cpu, mem = run_timed(cmd, stats.with_suffix(".log"))
    return RunResult(wall, cpu, mem, json.loads(stats.read_text()))


def analytic(zigzag: Path, image: str, size: int, threads: int, args: list[str],
             out_json: Path) -> RunResult:
    """One `zigzag analytic` run: adaptive plus the 1 spp / lattice / 5x5 grid baselines."""
    cmd = [str(zigzag), "analytic", "--image", image, "--size", str(size),
           "--threads", str(threads), "--json", str(out_json), *args]
    wall, cpu, mem = run_timed(cmd, out_json.with_suffix(".log"))
    return RunResult(wall, cpu, mem, json.loads(out_json.read_text()))


def file_digest(paths: list[Path]) -> str:
    h = hashlib.sha256()
    for p in paths:
        h.update(p.name.encode())
        h.update(p.read_bytes())
    return h.hexdigest()


def scene_files(scene: Path, assets: Path) -> list[Path]:
    """The rig plus the glTF it names and the buffers/images that glTF references."""
    rig = json.loads(scene.read_text())
    files = [scene]
    model = rig.get("model")
    if not model:
        return files
    gltf = assets / model[len("assets:"):] if model.startswith("assets:") else scene.parent / model
    files.append(gltf)
    if gltf.suffix == ".gltf":
        doc = json.loads(gltf.read_text())
        for item in doc.get("buffers", []) + doc.get("images", []):
            uri = item.get("uri", "")
            if uri and not uri.startswith("data:"):
                files.append(gltf.parent / uri)
    return files


def missing_assets(scene: Path, assets: Path) -> str | None:
    """A message naming the missing third-party model, or None when the scene can load."""
    rig = json.loads(scene.read_text())
    model = rig.get("model", "")
    if model.startswith("assets:") and not (assets / model[len("assets:"):]).exists():
        return f"{scene.name}: model {model} not found under {assets}"
    return None


def reference_key(zigzag: Path, scene: Path, assets: Path, size: int, spp: int) -> str:
    """Cache key: scene files + the renderer binary (its shading) + size + sample count."""
    h = hashlib.sha256()
    h.update(file_digest(scene_files(scene, assets)).encode())
    h.update(file_digest([zigzag]).encode())
    h.update(f"{size}:{spp}:stratified".encode())
    return h.hexdigest()[:20]


def cached_reference(zigzag: Path, scene: Path, assets: Path, size: int, spp: int,
                     threads: int, cache: Path) -> tuple[Path, dict]:
    """The stratified spp-ray reference EXR of a scene, rendered once per key."""
    cache.mkdir(parents=True, exist_ok=True)
    key = reference_key(zigzag, scene, assets, size, spp)
    exr = cache / f"{scene.stem}_{size}_{spp}_{key}.exr"
    stats = exr.with_suffix(".json")
    if not (exr.exists() and stats.exists()):
        tmp = exr.with_name("tmp_" + exr.name)
        args = ["--aa", "uniform", "--spp", str(spp), "--pattern", "stratified",
                "--assets", str(assets)]
        render(zigzag, scene, size, threads, args, tmp, stats)
        tmp.rename(exr)
    return exr, json.loads(stats.read_text())
