"""`zigzag-farm render SCENE... -o PATTERN [options] [-- zigzag render options]`."""
from __future__ import annotations

import argparse
import dataclasses
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

from . import fingerprint
from .fingerprint import HashCache
from .job import is_stream, write_json_atomically, write_protected
from .manifest import Manifest, ManifestBusy, ManifestUnwritable
from .plan import parse_frames, plan_batch
from .pass_through import UsageError, render_options
from .progress import summary
from .scene_info import InfoUsageError, SceneError, scene_infos

# Dask (cluster, runner) is imported by render(), inside main()'s handling of Ctrl-C: its
# imports take seconds, and a Ctrl-C during them printed a traceback.

USAGE_ERROR = 2
LAST_FRAME = 100_000_000  # zigzag render --frame's range
MAX_FRAME_SIDE = 16384  # zigzag's --width / --height (scene/scene.h kMaxImageSide)


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
    r.add_argument("--camera", default="0", metavar="N|NAME|all",
                   help="a camera by index or name, as zigzag info lists them, or all (default 0)")
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
                   help="how long to wait for the first worker of --scheduler/--slurm, and (--scheduler) "
                        "for any worker once all are gone before the jobs left fail (default 120)")
    r.add_argument("-q", "--quiet", action="store_true", help="no progress line")
    return ap


def output_root(pattern: str) -> str:
    """The folder of an output pattern that no {field} changes."""
    static = pattern.split("{", 1)[0]
    return os.path.dirname(static) if "{" in pattern else os.path.dirname(pattern)


# -- checks before anything runs ---------------------------------------------------------

def _check_numbers(o) -> None:
    if o.workers is None:
        o.workers = 1
    for name, value, least in (("--workers", o.workers, 1), ("--slurm", o.slurm, 1),
                               ("--width", o.width, 1), ("--height", o.height, 1),
                               ("--regions", o.regions, 1), ("--retries", o.retries, 0),
                               ("--allowed-failures", o.allowed_failures, 0),
                               ("--slurm-cores", o.slurm_cores, 1)):
        if value is not None and value < least:
            raise UsageError(f"{name} {value}: must be at least {least}")
    for name, value in (("--width", o.width), ("--height", o.height)):
        if value is not None and value > MAX_FRAME_SIDE:
            raise UsageError(f"{name} {value}: the renderer's frames are at most {MAX_FRAME_SIDE} pixels a side")
    for name, value in (("--timeout", o.timeout), ("--wait", o.wait)):
        if value is not None and not value > 0:
            raise UsageError(f"{name} {value:g}: must be more than 0")
    if not o.camera:
        raise UsageError("--camera '': expected an index, a camera's name or all")
    _check_not_empty(o)


def _check_not_empty(o) -> None:
    """An empty value is a mistake (an unset shell variable), not the option left out: tested
    for truth, `--scheduler ""` ran a local cluster and `--frames ""` the whole range."""
    for name in ("scheduler", "frames", "output", "stats", "summary", "manifest", "work_dir", "zigzag",
                 "slurm_queue", "slurm_account", "slurm_walltime", "slurm_memory", "interface"):
        if getattr(o, name) is not None and not getattr(o, name).strip():
            raise UsageError(f"--{name.replace('_', '-')} {getattr(o, name)!r}: needs a value "
                             "(leave the option out for its default)")


def _frames(o) -> list[int] | None:
    if o.frames is None:
        return None
    try:
        frames = parse_frames(o.frames)
    except ValueError as e:
        raise UsageError(f"{e}") from None
    if frames[0] < 0 or frames[-1] > LAST_FRAME:
        raise UsageError(f"--frames {o.frames}: the renderer's frames are 0 to {LAST_FRAME}")
    return frames


def _check_can_write(path: str, what: str) -> None:
    """Fail now, not after the batch: path's folder exists or can be made, and can be written
    to (probed in its nearest existing folder, so that a refused batch creates nothing)."""
    existing = os.path.dirname(os.path.abspath(path))
    while not os.path.exists(existing):
        existing = os.path.dirname(existing)
    if not os.path.isdir(existing):
        raise UsageError(f"cannot write {what} {path}: {existing} is a file, not a folder")
    if os.path.isdir(path):
        raise UsageError(f"cannot write {what} {path}: it is a folder")
    try:
        fd, probe = tempfile.mkstemp(prefix=".zigzag-farm-probe-", dir=existing)
        os.close(fd)
        os.remove(probe)
    except OSError as e:
        raise UsageError(f"cannot write {what} {path}: {e.strerror or e} in {existing}") from None


def _check_outputs_writable(plan, extra: dict[str, str]) -> None:
    """Every file the batch writes (images, stats, parts, summary, manifest) is not a folder,
    and each folder it writes into takes a probe file (once per folder)."""
    seen = set()
    for f in plan.frames:
        if is_stream(f.output):
            raise UsageError(f"-o {f.output}: a device or pipe, not a file: the farm's images are renamed "
                             "into place on the workers; write them to files (--stats and --summary "
                             "may be streams)")
    for path, what in [*plan.claims.items(), *extra.items()]:
        if os.path.isdir(path):
            raise UsageError(f"cannot write {what} {path}: it is a folder")
        if is_stream(path):  # written into, as zigzag render writes streams: no folder to probe
            continue
        folder = os.path.dirname(path)
        if folder not in seen:
            seen.add(folder)
            _check_can_write(path, what)


def _renderer_refusal(stderr: str, code: int) -> str:
    """The renderer's error lines (not its warnings nor CLI11's "Run with --help")."""
    lines = [line for line in stderr.strip().splitlines()
             if line.strip() and not line.startswith("Run with --help")]
    errors = [line.removeprefix("zigzag: error: ") for line in lines if line.startswith("zigzag: error:")]
    return " ".join(errors or lines) or f"exit code {code}"


def _check_with_renderer(zigzag: str, plan, o, opts, timeout: float = 120.0) -> None:
    """`zigzag render --dry-run`, once per scene, as its first job would run but with the
    user's own -o/--stats patterns (which it expands as the farm did) and every pass-through
    option: what the renderer refuses (an image format it cannot write, --aov layers in a
    .png, ...) is a usage error now, naming the user's path, not a failure of every job naming
    a temporary. Also with --regions, whose parts are .exr: the check is of the merged image."""
    seen = set()
    for f in plan.frames:
        scene = f.parts[0].scene
        # A frame whose image or stats the user write-protected (finished frames of a batch
        # run again) would be refused, though the run may only add the others: check a frame
        # it may write; none such, nothing to check.
        if scene in seen or any(write_protected(p) for p in (f.output, f.stats) if p):
            continue
        seen.add(scene)
        cmd = [zigzag, "render", "--dry-run", scene, "-o", o.output, "--camera", str(f.camera), "-q"]
        if o.stats:
            cmd += ["--stats", o.stats]
        if f.frame is not None:
            cmd += ["--frame", str(f.frame)]
        cmd += [*opts.runtime_args, *opts.key_args]
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, stdin=subprocess.DEVNULL)
        except (OSError, subprocess.TimeoutExpired) as e:
            raise UsageError(f"cannot check the batch with {zigzag} render --dry-run: {e}") from None
        if p.returncode != 0:
            raise UsageError(f"zigzag render refuses {scene}: {_renderer_refusal(p.stderr, p.returncode)}")


def _find_zigzag(given: str | None) -> str:
    candidate = given or os.environ.get("ZIGZAG") or shutil.which("zigzag")
    if not candidate or not os.access(candidate, os.X_OK):
        raise UsageError(f"no zigzag renderer found ({candidate or 'not on PATH'}): "
                         "use --zigzag PATH or set $ZIGZAG")
    return os.path.abspath(candidate)


def _folders_to_make(folder: str) -> list[str]:
    """folder and those of its parents that do not exist yet, deepest first: what a run that
    writes into it makes, and may remove again (never a folder that was there before)."""
    made = []
    while not os.path.exists(folder) and os.path.dirname(folder) != folder:
        made.append(folder)
        folder = os.path.dirname(folder)
    return made


def _client(o):
    from . import cluster
    if o.scheduler is not None:
        return cluster.existing_scheduler(o.scheduler, o.wait)
    if o.slurm is not None:
        return cluster.slurm_cluster(o.slurm, o.wait, queue=o.slurm_queue, account=o.slurm_account,
                                     walltime=o.slurm_walltime, memory=o.slurm_memory,
                                     cores=o.slurm_cores, interface=o.interface)
    return cluster.local_cluster(o.workers, o.allowed_failures)


_terminated = False
_stopping = False
STOP_TIMEOUT_S = 60.0  # the longest the driver takes to stop once signalled (seconds, normally)


def _stop(signum, frame):
    """The first SIGINT or SIGTERM stops the run: jobs cancelled, the cluster closed, then exit
    130, or 143 (128 + SIGTERM) as zigzag render does: main() tells the two apart by the flag,
    as the exception may be raised again on its way (Dask's sync re-raises what interrupted
    it). Later ones are the same request, not acted on: a KeyboardInterrupt raised again inside
    Dask's teardown broke its locks ("release unlocked lock", a traceback at exit, a hang). A
    teardown that still hangs is cut short by _stop_or_give_up."""
    global _terminated, _stopping
    if _stopping:
        return
    _stopping = True
    _terminated = signum == signal.SIGTERM
    threading.Thread(target=_stop_or_give_up, daemon=True, name="zigzag-farm stop").start()
    raise KeyboardInterrupt


def _stop_or_give_up() -> None:
    """STOP_TIMEOUT_S after the signal, a driver still stopping (the cluster's close wedged)
    kills its own processes (workers; their renderers die with them) and exits."""
    time.sleep(STOP_TIMEOUT_S)
    import psutil
    print(f"zigzag-farm: the cluster did not close within {STOP_TIMEOUT_S:g} s; its workers were killed",
          file=sys.stderr, flush=True)
    for child in psutil.Process().children(recursive=True):
        try:
            child.kill()
        except psutil.Error:
            pass
    os._exit(128 + signal.SIGTERM if _terminated else 130)


def _scenes(zigzag: str, paths: list[str], info_args: list[str], hashes: HashCache):
    """-> (SceneInfo with its files' content digest for each scene that loads, failures)."""
    from .runner import Failure
    failures = []
    infos = []
    for path, info in scene_infos(zigzag, paths, info_args):
        if isinstance(info, InfoUsageError):
            raise UsageError(str(info))
        if isinstance(info, SceneError):
            failures.append(Failure(path, "scene", str(info)))
            print(f"zigzag-farm: FAILED {path}: {info}", file=sys.stderr)
        else:
            infos.append(dataclasses.replace(info, content=fingerprint.digest(list(info.files), hashes)))
    return infos, failures


def render(o) -> int:
    from . import cluster
    from .runner import RunSettings, Runner, indent
    _check_numbers(o)
    frames = _frames(o)
    opts = render_options(o, o.pass_through)
    zigzag = _find_zigzag(o.zigzag)
    if o.slurm is not None:
        try:
            cluster.check_slurm(memory=o.slurm_memory, cores=o.slurm_cores)
        except cluster.ClusterError as e:
            raise UsageError(f"{e}") from None

    root = output_root(o.output)
    manifest_path = os.path.abspath(o.manifest or os.path.join(root, ".zigzag-farm-manifest.jsonl"))
    work_dir = os.path.abspath(o.work_dir or os.path.join(root, ".zigzag-farm-parts"))
    hashes = HashCache(os.path.join(os.path.dirname(manifest_path), fingerprint.CACHE_NAME))
    # Removed once empty: the folders of a --work-dir the run makes; the default one, the
    # farm's by its name, even when an earlier run left it.
    work_folders = _folders_to_make(work_dir)
    if not o.work_dir and work_dir not in work_folders:
        work_folders.insert(0, work_dir)

    infos, scene_failures = _scenes(zigzag, o.scenes, opts.info_args, hashes)
    try:
        plan = plan_batch(infos, o.output, frames=frames, camera=o.camera, regions=o.regions,
                          work_dir=work_dir, stats=o.stats, args=tuple(opts.key_args),
                          fingerprint=fingerprint.digest([zigzag], hashes))
        extra = {manifest_path: "the manifest", hashes.path: "the hash cache"}
        if o.summary:
            extra[os.path.abspath(o.summary)] = "the summary"
        for path, what in extra.items():
            plan.claim(path, what)
    except ValueError as e:
        raise UsageError(f"{e}") from None
    _check_outputs_writable(plan, {})
    if o.summary and write_protected(o.summary):  # refused once the batch ran, else (exit 1)
        raise UsageError(f"--summary {o.summary}: the file is write-protected (make it writable to let "
                         "the farm replace it)")
    _check_with_renderer(zigzag, plan, o, opts)

    try:
        manifest = Manifest(manifest_path)
    except ManifestBusy as e:
        raise UsageError(f"{e}") from None
    except OSError as e:
        raise UsageError(f"cannot open the manifest {manifest_path}: {e.strerror or e}") from None
    if manifest.skipped:  # one line, however many: their jobs are simply rendered again
        print(f"zigzag-farm: warning: {manifest_path}: skipped {manifest.skipped} damaged record(s) "
              "(what only they proved done is rendered again)", file=sys.stderr)
    hashes.save()
    with manifest, open(os.devnull, "w") as devnull:
        runner = Runner(plan, manifest, RunSettings(zigzag=zigzag, timeout=o.timeout,
                                                    retries=o.retries, keep_parts=o.keep_parts,
                                                    runtime_args=tuple(opts.runtime_args),
                                                    # Only --scheduler: a LocalCluster's nannies
                                                    # restart workers, and Slurm resubmits ended
                                                    # jobs that may wait in its queue.
                                                    no_workers_s=o.wait if o.scheduler else None,
                                                    work_folders=tuple(work_folders)),
                        progress_stream=devnull if o.quiet else None, live=False if o.quiet else None)
        if runner.needs_cluster():
            try:
                with _client(o) as client:
                    outcome = runner.run(client)
            except cluster.ClusterError as e:
                raise UsageError(f"{e}") from None
        elif runner.pending_frames():  # only what earlier runs' records complete, or refuse
            outcome = runner.run(None)
        else:
            outcome = runner.outcome
    outcome.failures[:0] = scene_failures
    outcome.failed_scenes = len(scene_failures)
    print(summary(frames=outcome.frames, skipped=outcome.skipped, rendered=outcome.rendered,
                  failed=outcome.failed_frames, failed_scenes=outcome.failed_scenes,
                  jobs_run=len(outcome.jobs_run), job_seconds=outcome.job_seconds,
                  wall_s=outcome.wall_s), file=sys.stderr)
    for f in outcome.failures:
        print(f"zigzag-farm: failed: {f.what}: {indent(f.message)}", file=sys.stderr)
    if o.summary and not _write_summary(o.summary, outcome):
        return 1
    return 1 if outcome.failures else 0


def _write_summary(path: str, outcome) -> bool:
    """Written whole to a temporary and renamed: a failed write keeps an earlier summary."""
    try:
        write_json_atomically(path, outcome.as_json())
        return True
    except OSError as e:  # checked before the run; the disk can still fill up since
        print(f"zigzag-farm: error: cannot write the summary {path}: {e.strerror or e}",
              file=sys.stderr)
        return False


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    pass_through: list[str] = []
    if "--" in argv:
        cut = argv.index("--")
        argv, pass_through = argv[:cut], argv[cut + 1:]
    o = _parser().parse_args(argv)
    o.pass_through = pass_through
    signal.signal(signal.SIGTERM, _stop)
    # Only Python's own handler is replaced: an ignored SIGINT (a background job) stays ignored.
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _stop)
    try:
        return render(o)
    except UsageError as e:
        print(f"zigzag-farm: error: {e}", file=sys.stderr)
        return USAGE_ERROR
    except KeyboardInterrupt:
        if _stopping:  # to the end: Python's exit puts back the default, which would kill it
            for sig in (signal.SIGINT, signal.SIGTERM):
                signal.signal(sig, signal.SIG_IGN)
        how, code = ("terminated (SIGTERM)", 128 + signal.SIGTERM) if _terminated else ("interrupted", 130)
        print(f"zigzag-farm: {how}; finished jobs are recorded, a re-run renders the rest", file=sys.stderr)
        return code
    except ManifestUnwritable as e:  # not "finished jobs are recorded": they are not
        print(f"zigzag-farm: error: {e}; the run stopped, and the images it finished since are "
              "unrecorded (a re-run renders them again)", file=sys.stderr)
        return 1
    except Exception as e:  # e.g. the scheduler lost for good: one line, not a traceback
        print(f"zigzag-farm: {internal_error_line(e)}; finished jobs are recorded, a re-run renders the rest",
              file=sys.stderr)
        return 1  # as a failed job: worth a re-run (2 means bad options)


def internal_error_line(e: Exception) -> str:
    """What ended the run, in one line: Dask's cancellation of every pending job when the
    scheduler is lost lists each job's key, one per line (review: 4 lines for 12 jobs)."""
    if type(e).__name__ in ("FuturesCancelledError", "FutureCancelledError"):
        reasons = sorted({str(getattr(g, "reason", "unknown")) for g in getattr(e, "error_groups", [e])})
        if reasons == ["scheduler-connection-lost"]:
            return "lost the Dask scheduler: its pending jobs were cancelled"
        return f"the pending jobs were cancelled ({', '.join(reasons)})"
    text = " ".join(str(e).split())
    return f"internal error: {type(e).__name__}: {text[:300] + '...' if len(text) > 300 else text}"


if __name__ == "__main__":
    sys.exit(main())
