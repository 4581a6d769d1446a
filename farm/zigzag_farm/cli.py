"""`zigzag-farm render SCENE... -o PATTERN [options] [-- zigzag render options]`."""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import signal
import sys

from . import cluster
from .manifest import Manifest, ManifestBusy
from .plan import parse_frames, plan_batch
from .progress import summary
from .runner import Failure, RunSettings, Runner, indent
from .scene_info import SceneError, scene_infos

USAGE_ERROR = 2


class UsageError(Exception):
    """Bad options or setup: a one-line error and exit code 2."""


def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="zigzag-farm", description=__doc__)
    sub = ap.add_subparsers(dest="command", required=True)
    r = sub.add_parser("render", help="render frames, cameras and regions of scenes as Dask jobs",
                       epilog="Options after `--` go to every `zigzag render` call "
                              "(e.g. -- --aa uniform --spp 16).")
    r.add_argument("scenes", nargs="+", metavar="SCENE")
    r.add_argument("-o", "--output", required=True, metavar="PATTERN",
                   help="output image per frame: {scene}, {camera}, {frame}, {frame:04}")
    r.add_argument("--frames", metavar="A-B[xS]",
                   help="frames to render (default: an animated scene's own range, else a still)")
    r.add_argument("--camera", default="0", metavar="N|all")
    r.add_argument("--regions", type=int, default=1, metavar="N",
                   help="split each image into N regions rendered as separate jobs, then merged")
    r.add_argument("--width", type=int, help="frame width (default: the scene's)")
    r.add_argument("--height", type=int, help="frame height (default: the scene's)")
    r.add_argument("--stats", metavar="PATTERN", help="one merged stats JSON per image")
    where = r.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="a LocalCluster of N single-job workers on this machine, on 127.0.0.1 (default 1)")
    where.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="an existing Dask scheduler")
    where.add_argument("--slurm", type=int, metavar="JOBS",
                       help="JOBS Slurm jobs of one worker each (dask-jobqueue; see README)")
    r.add_argument("--slurm-queue")
    r.add_argument("--slurm-account")
    r.add_argument("--slurm-walltime", metavar="HH:MM:SS")
    r.add_argument("--slurm-memory", metavar="SIZE", help="per worker job, e.g. 8GB")
    r.add_argument("--slurm-cores", type=int, help="cores per worker job (the renderer uses them all)")
    r.add_argument("--interface", help="network interface the Slurm scheduler and workers use (e.g. ib0)")
    r.add_argument("--zigzag", metavar="PATH",
                   help="the renderer (default: $ZIGZAG, else zigzag on PATH); the same path on every worker")
    r.add_argument("--timeout", type=float, metavar="S", help="kill a job running longer than S seconds")
    r.add_argument("--retries", type=int, default=2, help="re-runs of a job that failed (default 2)")
    r.add_argument("--allowed-failures", type=int, default=3,
                   help="worker deaths a job may cause before it is failed (LocalCluster; default 3)")
    r.add_argument("--manifest", metavar="FILE",
                   help="record of finished jobs (default: .zigzag-farm-manifest.jsonl in the output folder)")
    r.add_argument("--work-dir", metavar="DIR", help="where region parts wait for their merge")
    r.add_argument("--keep-parts", action="store_true", help="keep region parts after merging")
    r.add_argument("--summary", metavar="FILE.json", help="write the run's summary as JSON")
    r.add_argument("--wait", type=float, default=120.0, metavar="S",
                   help="how long to wait for the first worker of --scheduler/--slurm")
    r.add_argument("-q", "--quiet", action="store_true", help="no progress line")
    return ap


def output_root(pattern: str) -> str:
    """The folder of an output pattern that no {field} changes."""
    static = pattern.split("{", 1)[0]
    return os.path.dirname(static) if "{" in pattern else os.path.dirname(pattern)


def _pass_through_value(args: list[str], name: str) -> int | None:
    for i, a in enumerate(args):
        if a == name and i + 1 < len(args):
            return int(args[i + 1])
        if a.startswith(name + "="):
            return int(a.split("=", 1)[1])
    return None


def _find_zigzag(given: str | None) -> str:
    candidate = given or os.environ.get("ZIGZAG") or shutil.which("zigzag")
    if not candidate or not os.access(candidate, os.X_OK):
        raise UsageError(f"no zigzag renderer found ({candidate or 'not on PATH'}): "
                         "use --zigzag PATH or set $ZIGZAG")
    return os.path.abspath(candidate)


def _fingerprint(zigzag: str, scenes: list[str]) -> str:
    """What else decides the output bytes: the renderer binary and the scene files."""
    h = hashlib.sha256()
    for path in [zigzag, *scenes]:
        try:
            with open(path, "rb") as f:
                h.update(hashlib.sha256(f.read()).digest())
        except OSError:
            h.update(path.encode())
    return h.hexdigest()[:16]


def _client(o, render_args: list[str]):
    if o.scheduler:
        return cluster.existing_scheduler(o.scheduler, o.wait)
    if o.slurm is not None:
        return cluster.slurm_cluster(o.slurm, o.wait, queue=o.slurm_queue, account=o.slurm_account,
                                     walltime=o.slurm_walltime, memory=o.slurm_memory,
                                     cores=o.slurm_cores, interface=o.interface)
    return cluster.local_cluster(o.workers or 1, o.allowed_failures)


def _sigterm(signum, frame):
    raise KeyboardInterrupt


def render(o) -> int:
    split = o.pass_through
    zigzag = _find_zigzag(o.zigzag)
    if o.regions < 1:
        raise UsageError("--regions must be at least 1")
    if o.camera != "all" and not o.camera.isdigit():
        raise UsageError(f"--camera {o.camera}: expected an index or all")
    try:
        frames = parse_frames(o.frames) if o.frames else None
    except ValueError as e:
        raise UsageError(f"{e}")
    width = o.width or _pass_through_value(split, "--width")
    height = o.height or _pass_through_value(split, "--height")
    render_args = list(split)
    if o.width and "--width" not in split:
        render_args += ["--width", str(o.width)]
    if o.height and "--height" not in split:
        render_args += ["--height", str(o.height)]
    local_workers = o.workers or 1
    if o.scheduler is None and o.slurm is None and "--threads" not in split:
        # Workers of a LocalCluster share this machine's cores.
        render_args += ["--threads", str(max(1, (os.cpu_count() or 1) // local_workers))]

    root = output_root(o.output)
    manifest_path = o.manifest or os.path.join(root, ".zigzag-farm-manifest.jsonl")
    work_dir = os.path.abspath(o.work_dir or os.path.join(root, ".zigzag-farm-parts"))

    failures: list[Failure] = []
    infos = []
    for path, info in scene_infos(zigzag, o.scenes, width, height):
        if isinstance(info, SceneError):
            failures.append(Failure(path, "scene", str(info)))
            print(f"zigzag-farm: FAILED {path}: {info}", file=sys.stderr)
        else:
            infos.append(info)
    try:
        plan = plan_batch(infos, o.output, frames=frames, camera=o.camera, regions=o.regions,
                          work_dir=work_dir, stats=o.stats, args=tuple(render_args),
                          fingerprint=_fingerprint(zigzag, [i.path for i in infos]))
    except ValueError as e:
        raise UsageError(f"{e}")

    try:
        manifest = Manifest(manifest_path)
    except ManifestBusy as e:
        raise UsageError(f"{e}")
    with manifest:
        runner = Runner(plan, manifest, RunSettings(zigzag=zigzag, timeout=o.timeout,
                                                    retries=o.retries), live=False if o.quiet else None)
        if o.quiet:
            runner.progress_stream = open(os.devnull, "w")
        todo = runner.pending_frames()
        if todo:
            try:
                with _client(o, render_args) as client:
                    outcome = runner.run(client)
            except cluster.ClusterError as e:
                raise UsageError(f"{e}")
        else:
            outcome = runner.outcome
    outcome.failures[:0] = failures
    outcome.failed_frames += len(failures)
    print(summary(frames=outcome.frames, skipped=outcome.skipped, rendered=outcome.rendered,
                  failed=outcome.failed_frames, jobs_run=len(outcome.jobs_run),
                  job_seconds=outcome.job_seconds, wall_s=outcome.wall_s), file=sys.stderr)
    for f in outcome.failures:
        print(f"zigzag-farm: failed: {f.what}: {indent(f.message)}", file=sys.stderr)
    if o.summary:
        os.makedirs(os.path.dirname(os.path.abspath(o.summary)), exist_ok=True)
        with open(o.summary, "w") as fh:
            json.dump(outcome.as_json(), fh, indent=2)
    return 1 if outcome.failures else 0


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    pass_through: list[str] = []
    if "--" in argv:
        cut = argv.index("--")
        argv, pass_through = argv[:cut], argv[cut + 1:]
    o = _parser().parse_args(argv)
    o.pass_through = pass_through
    signal.signal(signal.SIGTERM, _sigterm)
    try:
        return render(o)
    except UsageError as e:
        print(f"zigzag-farm: error: {e}", file=sys.stderr)
        return USAGE_ERROR
    except KeyboardInterrupt:
        print("zigzag-farm: interrupted; finished jobs are recorded, a re-run renders the rest",
              file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
