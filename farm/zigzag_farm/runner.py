"""Running a plan on a Dask client: submit what the manifest does not prove done, follow the
futures, record each finished job, assemble frames, report failures while the rest go on.
"""
from __future__ import annotations

import glob
import json
import os
import time
from dataclasses import dataclass, field

from distributed import wait

from . import job, tasks
from .cluster import RENDER_RESOURCE
from .manifest import Manifest
from .plan import FrameJob, Plan, RenderJob
from .progress import Progress
from .stats import merge_stats

POLL_S = 0.5
RUNNING_EVERY_S = 1.0  # how often the progress line asks the scheduler what is running


@dataclass
class RunSettings:
    zigzag: str
    timeout: float | None = None
    retries: int = 2
    keep_parts: bool = False


@dataclass
class Failure:
    what: str
    key: str
    message: str


@dataclass
class Outcome:
    frames: int = 0
    skipped: int = 0
    rendered: int = 0
    failures: list[Failure] = field(default_factory=list)
    failed_frames: int = 0
    jobs_run: list[str] = field(default_factory=list)
    job_seconds: list[float] = field(default_factory=list)
    wall_s: float = 0.0

    def as_json(self) -> dict:
        return {"frames": self.frames, "skipped": self.skipped, "rendered": self.rendered,
                "failed_frames": self.failed_frames, "jobs_run": len(self.jobs_run),
                "job_keys": self.jobs_run, "job_seconds": self.job_seconds,
                "wall_s": self.wall_s,
                "failures": [{"what": f.what, "key": f.key, "message": f.message}
                             for f in self.failures]}


def describe(j: RenderJob) -> str:
    frame = "" if j.frame is None else f" frame {j.frame}"
    region = "" if j.region is None else f" region {j.region.arg()}"
    return f"{j.scene_name}{frame} camera {j.camera}{region}"


def render_spec(j: RenderJob, s: RunSettings) -> dict:
    return {"key": j.key, "what": describe(j), "zigzag": s.zigzag, "scene": j.scene,
            "frame": j.frame, "camera": j.camera,
            "region": list(j.region.bounds) if j.region else None,
            "output": j.output, "args": list(j.args), "timeout": s.timeout}


def merge_key(f: FrameJob) -> str:
    return "zz-merge-" + f.key[len("zz-frame-"):]


def merge_spec(f: FrameJob, s: RunSettings) -> dict:
    frame = "" if f.frame is None else f" frame {f.frame}"
    return {"key": merge_key(f), "what": f"merge {f.scene_name}{frame} camera {f.camera}",
            "zigzag": s.zigzag, "parts": [p.output for p in f.parts], "output": f.output,
            "timeout": s.timeout}


def remove_stale_temporaries(f: FrameJob) -> None:
    """Temporary files left by a run or an attempt that was killed (this batch's names only)."""
    for path in [f.output] + [p.output for p in f.parts]:
        folder, name = os.path.split(path)
        stem, ext = os.path.splitext(name)
        # The job's temporaries (job.temporary_name), and zigzag's own temporaries of those
        # (core/atomic_file: "." + stem + ".zz-PID-N" + ext), one more dot in front.
        ours = f".{glob.escape(stem)}.*.tmp{glob.escape(ext)}*"
        for tmp in glob.glob(os.path.join(glob.escape(folder), ours)) + \
                glob.glob(os.path.join(glob.escape(folder), "." + ours)):
            try:
                os.remove(tmp)
            except OSError:
                pass


def _write_json_atomically(path: str, data: dict) -> None:
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    tmp = job.temporary_name(path)
    with open(tmp, "w") as fh:
        json.dump(data, fh, indent=2)
        fh.write("\n")
    os.replace(tmp, path)


def _failure_message(exc: BaseException) -> str:
    try:
        from distributed.scheduler import KilledWorker
    except ImportError:
        KilledWorker = ()
    if isinstance(exc, KilledWorker):
        return (f"a worker died while running it, {exc.allowed_failures + 1} time(s) in a row "
                f"(distributed.scheduler.allowed-failures = {exc.allowed_failures})")
    if isinstance(exc, job.JobError):
        return str(exc)
    return f"{type(exc).__name__}: {exc}"


def indent(message: str) -> str:
    """A multi-line failure (the renderer's stderr) indented under its first line."""
    return message.strip().replace("\n", "\n    ")


class Runner:
    def __init__(self, plan: Plan, manifest: Manifest, settings: RunSettings, progress_stream=None,
                 live: bool | None = None):
        self.plan, self.manifest, self.s = plan, manifest, settings
        self.progress_stream, self.live = progress_stream, live
        self.outcome = Outcome(frames=len(plan.frames))

    # -- what is left ---------------------------------------------------------------
    def pending_frames(self) -> list[FrameJob]:
        todo = [f for f in self.plan.frames if not self.manifest.done(f.key)]
        self.outcome.skipped = len(self.plan.frames) - len(todo)
        return todo

    # -- frames assembled on the driver ---------------------------------------------
    def _finish_frame(self, f: FrameJob, merge_result: dict | None) -> None:
        records = [self.manifest.get(p.key) or {} for p in f.parts]
        pixels = [p.region.pixels if p.region else 1 for p in f.parts]
        stats = merge_stats([r.get("stats") for r in records], pixels, output=f.output,
                            frame=f.frame, job_seconds=[r.get("seconds") for r in records],
                            workers=[r.get("worker") for r in records],
                            regions=[list(p.region.bounds) for p in f.parts] if f.merged else None)
        if f.stats:
            _write_json_atomically(f.stats, stats)
        image = merge_result if merge_result is not None else records[0]
        self.manifest.record(f.key, "frame", image, stats_file=f.stats)
        self.outcome.rendered += 1
        # An attempt lost with its worker (SIGKILL, node gone) cannot clean up after itself;
        # once the frame is recorded, whatever temporary it left is an orphan.
        remove_stale_temporaries(f)
        if f.merged and not self.s.keep_parts:
            for p in f.parts:
                try:
                    os.remove(p.output)
                except FileNotFoundError:
                    pass

    # -- the Dask part --------------------------------------------------------------
    def run(self, client) -> Outcome:
        start = time.monotonic()
        todo = self.pending_frames()
        futures = {}  # key -> (future, kind, frame, render job or None)
        for f in todo:
            remove_stale_temporaries(f)
            part_futures = []
            if not f.merged and self.manifest.done(f.parts[0].key):
                self._finish_frame(f, None)  # rendered before the last driver died, not recorded
                continue
            for p in f.parts:
                if f.merged and self.manifest.done(p.key):
                    continue  # a part finished before the last driver died
                fut = client.submit(tasks.render_task, render_spec(p, self.s), key=p.key,
                                    resources=RENDER_RESOURCE, retries=self.s.retries)
                futures[p.key] = (fut, "render", f, p)
                part_futures.append(fut)
            if f.merged:
                key = merge_key(f)
                fut = client.submit(tasks.merge_task, merge_spec(f, self.s), *part_futures, key=key,
                                    resources=RENDER_RESOURCE, retries=self.s.retries)
                futures[key] = (fut, "merge", f, None)
        self.outcome.jobs_run = list(futures)
        progress = Progress(len(futures), self.progress_stream, self.live)
        failed_frames: set[str] = set()
        done = failed = 0
        pending = dict(futures)
        try:
            running, asked = 0, 0.0
            while pending:
                finished = {k: pending.pop(k) for k in [k for k, (fut, *_) in pending.items() if fut.done()]}
                # One round trip for all the results that arrived, not one per job.
                ok = [fut for fut, *_ in finished.values() if fut.status == "finished"]
                results = dict(zip((fut.key for fut in ok), client.gather(ok))) if ok else {}
                for key, (fut, kind, f, p) in finished.items():
                    error = self._collect(fut, results.get(key), kind, f, p)
                    if error is None:
                        done += 1
                        continue
                    failed += 1
                    failed_frames.add(f.key)
                    if kind == "merge" and any(futures[q.key][0].status == "error"
                                               for q in f.parts if q.key in futures):
                        continue  # the failed part is the one to report
                    what = describe(p) if p else merge_spec(f, self.s)["what"]
                    self.outcome.failures.append(Failure(what, key, _failure_message(error)))
                    progress.message(f"zigzag-farm: FAILED {what}: {indent(_failure_message(error))}")
                if time.monotonic() - asked >= RUNNING_EVERY_S:
                    running, asked = self._running(client, pending), time.monotonic()
                progress.update(done=done, failed=failed, running=min(running, len(pending)))
                if pending:
                    # Wakes as soon as any job ends; the timeout only refreshes the progress line.
                    try:
                        wait([fut for fut, *_ in pending.values()], timeout=POLL_S,
                             return_when="FIRST_COMPLETED")
                    except TimeoutError:
                        pass
        except BaseException:
            client.cancel([fut for fut, *_ in pending.values()])  # tasks kill their renderers
            raise
        finally:
            progress.update(done=done, failed=failed, running=0, force=True)
            progress.finish()
        self.outcome.failed_frames = len(failed_frames)
        self.outcome.wall_s = time.monotonic() - start
        return self.outcome

    def _collect(self, fut, result: dict | None, kind: str, f: FrameJob,
                 p: RenderJob | None) -> BaseException | None:
        """Record a finished job (and its frame when that is complete) -> None, or the error."""
        if fut.status != "finished":
            return fut.exception() if fut.status == "error" else RuntimeError(f"job {fut.status}")
        self.outcome.job_seconds.append(result["seconds"])
        try:
            if kind == "render":
                self.manifest.record(p.key, "render", result, stats=result.get("stats"),
                                     seconds=result["seconds"], worker=result.get("worker"))
                if not f.merged:
                    self._finish_frame(f, None)
            else:
                self._finish_frame(f, result)
        except OSError as e:  # e.g. the stats folder is not writable
            return e
        return None

    @staticmethod
    def _running(client, pending) -> int:
        # With resources={"render": 1} a worker is handed one job at a time, so the jobs the
        # scheduler has "processing" are the ones running.
        try:
            processing = client.processing()
        except Exception:
            return 0
        return sum(1 for keys in processing.values() for k in keys if k in pending)
