"""Running a plan on a Dask client: submit what the manifest does not prove done, follow the
futures, record each finished job, assemble frames, report failures while the rest go on.
"""
from __future__ import annotations

import dataclasses
import os
import re
import time
from dataclasses import dataclass, field

from distributed import wait

from . import job, tasks
from .cluster import RENDER_RESOURCE, render_slots
from .manifest import Manifest
from .plan import FrameJob, Plan, RenderJob
from .progress import Progress
from .regions import split_frame
from .stats import merge_stats

POLL_S = 0.5
RESULT_TIMEOUT_S = 30.0  # fetching one finished job's result (a small dict)
RUNNING_EVERY_S = 1.0  # how often the progress line asks the scheduler what is running


@dataclass
class RunSettings:
    zigzag: str
    timeout: float | None = None
    retries: int = 2
    keep_parts: bool = False
    # Options for every render that do not change its bytes and so stay out of the job keys
    # (--threads: the renderer's images are bit-identical for any thread count).
    runtime_args: tuple[str, ...] = ()
    # Seconds without any render worker after which the jobs left fail (None: wait for ever).
    no_workers_s: float | None = None
    # The folders of region parts to remove once empty, deepest first: those the run made, never
    # one that was there before (a --work-dir the user made). None: the parts' own folders.
    work_folders: tuple[str, ...] | None = None


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
    failed_frames: int = 0  # images of the plan that failed
    failed_scenes: int = 0  # scenes that did not load (no images planned for them)
    jobs_run: list[str] = field(default_factory=list)
    job_seconds: list[float] = field(default_factory=list)
    wall_s: float = 0.0

    def as_json(self) -> dict:
        return {"frames": self.frames, "skipped": self.skipped, "rendered": self.rendered,
                "failed_frames": self.failed_frames, "failed_scenes": self.failed_scenes,
                "jobs_run": len(self.jobs_run),
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
            # The user's options last: one left without its value (`-- --assets`) then takes
            # none of the driver's (it took `--threads` as its folder) and zigzag says so.
            "output": j.output, "args": [*s.runtime_args, *j.args], "timeout": s.timeout}


def merge_key(f: FrameJob) -> str:
    return "zz-merge-" + f.key[len("zz-frame-"):]


def merge_spec(f: FrameJob, s: RunSettings) -> dict:
    frame = "" if f.frame is None else f" frame {f.frame}"
    return {"key": merge_key(f), "what": f"merge {f.scene_name}{frame} camera {f.camera}",
            "zigzag": s.zigzag, "parts": [p.output for p in f.parts], "output": f.output,
            "timeout": s.timeout}


def _temporaries_of(path: str) -> re.Pattern:
    """The names of exactly this output's temporaries (never another output's: `shot.png`
    must not match `.shot.v2.*.tmp.png`, the temporary of shot.v2.png):
    - the job's own, job.temporary_name: ".STEM.TAG.tmp.EXT" (TAG = HOST-PID-UUID8, no dots;
      STEM and EXT without braces, job.plain_name),
      and its stats ".STEM.TAG.tmp.EXT.stats.json";
    - zigzag's temporaries of those (core/atomic_file: "." + stem + ".zz-PID-RANDOM16-N" + ext):
      "..STEM.TAG.tmp.zz-PID-RANDOM16-N.EXT" and "..STEM.TAG.tmp.EXT.stats.zz-PID-RANDOM16-N.json".
    zigzag cuts a temporary's name that would pass 255 bytes; plan.MAX_OUTPUT_NAME and
    job.MAX_TAG_HOST keep these short of that, so every one has this form."""
    stem, ext = os.path.splitext(job.plain_name(os.path.basename(path)))
    ours = rf"{re.escape(stem)}\.[^./]+-\d+-[0-9a-f]{{8}}\.tmp"
    zz, ext = r"\.zz-\d+-[0-9a-f]{16}-\d+", re.escape(ext)
    return re.compile(rf"\.{ours}{ext}(\.stats\.json)?|\.\.{ours}({zz}{ext}|{ext}\.stats{zz}\.json)")


def remove_stale_temporaries(f: FrameJob) -> None:
    """Temporary files left by a run or an attempt that was killed (this frame's names only)."""
    for path in [f.output, f.stats, *(p.output for p in f.parts)]:
        if path is None:
            continue
        folder = os.path.dirname(path)
        try:
            names = os.listdir(folder)
        except OSError:
            continue
        pattern = _temporaries_of(path)
        for name in names:
            if pattern.fullmatch(name):
                try:
                    os.remove(os.path.join(folder, name))
                except OSError:
                    pass


def remove_other_region_parts(f: FrameJob) -> None:
    """Parts of this frame's output that a run with another region count left (interrupted
    before its merge): named for this frame, output and options, with a count, or a
    region, the frame does not have now."""
    names = f.part_names
    if names is None:
        return
    try:
        entries = os.listdir(names.folder)
    except OSError:
        return
    mine = {p.output for p in f.parts}
    splits: dict[int, list] = {}
    for name in entries:
        parsed = names.index_and_count(name)
        if parsed is None:
            continue
        index, count = parsed
        if count not in splits:
            try:
                splits[count] = split_frame(names.width, names.height, count)
            except ValueError:
                splits[count] = []
        path = os.path.join(names.folder, name)
        if index < len(splits[count]) and path not in mine and names.path(index, count, splits[count][index]) == path:
            try:
                os.remove(path)
            except OSError:
                pass


def _failure_message(exc: BaseException) -> str:
    try:
        from distributed.scheduler import KilledWorker
    except ImportError:
        KilledWorker = ()
    if isinstance(exc, KilledWorker):
        # Dask charges every job on the worker, the ones waiting in its queue too.
        return (f"its worker died {exc.allowed_failures + 1} time(s) while it ran or waited there "
                f"(distributed.scheduler.allowed-failures = {exc.allowed_failures}); a re-run renders it")
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
        """The frames to render: not every requested output of theirs is on disk as recorded."""
        todo = [f for f in self.plan.frames
                if not self._complete(f) and not self._complete_stats_only(f)]
        self.outcome.skipped = len(self.plan.frames) - len(todo)
        return todo

    def needs_cluster(self) -> bool:
        """Whether a pending frame has a job for Dask to run: not only frames an earlier run's
        recorded job completes (their stats written) or write-protected images (reported)."""
        return any(self._without_job(f) is None for f in self.pending_frames())

    def _without_job(self, f: FrameJob) -> str | None:
        """Why a pending frame needs no job: "recorded" (a whole frame whose render job is
        recorded with its image on disk: rendered before the last driver died, or only its
        stats are missing), "protected" (its image is write-protected: reported, not
        rendered); None: it has jobs to run."""
        if not f.merged and self.manifest.done(f.parts[0].key):
            return "recorded"
        return "protected" if self._protected(f) else None

    @staticmethod
    def _protected(f: FrameJob) -> str | None:
        """The frame's image or stats file the user write-protected: its stats would be
        refused after the render (job.write_json_atomically), so it is not rendered."""
        return next((p for p in (f.output, f.stats) if p and job.write_protected(p)), None)

    def _complete(self, f: FrameJob) -> bool:
        """The image and (when asked for) the stats file exist and match the manifest."""
        if not self.manifest.done(f.key):  # checks the image and the stats it recorded
            return False
        return f.stats is None or self.manifest.get(f.key).get("stats_file") == f.stats

    def _complete_stats_only(self, f: FrameJob) -> bool:
        """A frame whose image is complete but whose stats file is missing, changed or newly
        asked for: write it from the recorded jobs' stats, without rendering again."""
        if not self.manifest.done(f.key, image_only=True):
            return False
        records = [self.manifest.get(p.key) for p in f.parts]
        if not all(r and r.get("stats") for r in records):
            return False
        try:
            self._finish_frame(f, self.manifest.get(f.key), rendered=False)
        except OSError:
            return False  # rendered again: the failure to write is reported then
        return True

    # -- frames assembled on the driver ---------------------------------------------
    def _finish_frame(self, f: FrameJob, merge_result: dict | None, rendered: bool = True) -> None:
        records = [self.manifest.get(p.key) or {} for p in f.parts]
        pixels = [p.region.pixels if p.region else 1 for p in f.parts]
        stats = merge_stats([r.get("stats") for r in records], pixels, output=f.output,
                            frame=f.frame, job_seconds=[r.get("seconds") for r in records],
                            workers=[r.get("worker") for r in records],
                            regions=[list(p.region.bounds) for p in f.parts] if f.merged else None)
        stats_record = job.write_json_atomically(f.stats, stats) if f.stats else None
        image = merge_result if merge_result is not None else records[0]
        self.manifest.record(f.key, "frame", image, stats_file=f.stats,
                             also=[stats_record] if stats_record else [])
        self.outcome.rendered += rendered
        # An attempt lost with its worker (SIGKILL, node gone) cannot clean up after itself;
        # once the frame is recorded, whatever temporary it left is an orphan.
        remove_stale_temporaries(f)
        if not self.s.keep_parts:
            remove_other_region_parts(f)
            for p in f.parts if f.merged else ():  # its own parts, merged now
                try:
                    os.remove(p.output)
                except FileNotFoundError:
                    pass

    # -- the Dask part --------------------------------------------------------------
    def run(self, client) -> Outcome:
        """client: a Dask client, or None when not needs_cluster()."""
        start = time.monotonic()
        todo = self.pending_frames()
        futures = {}  # key -> (future, kind, frame, render job or None)
        failed_frames: set[str] = set()
        for f in todo:
            remove_stale_temporaries(f)
            part_futures = []
            without_job = self._without_job(f)
            if without_job == "recorded":
                try:
                    self._finish_frame(f, None, rendered=False)
                    self.outcome.skipped += 1  # complete from an earlier run's job: nothing rendered now
                except OSError as e:  # the stats cannot be written: reported, never a traceback
                    failed_frames.add(f.key)
                    self.outcome.failures.append(Failure(describe(f.parts[0]), f.key, f"{e.strerror or e}: {e.filename}"))
                continue
            # An image still to write, write-protected: its job would refuse it after the render.
            if without_job == "protected":
                failed_frames.add(f.key)
                self.outcome.failures.append(Failure(
                    describe(dataclasses.replace(f.parts[0], region=None)), f.key,
                    f"{self._protected(f)}: the file is write-protected (make it writable to let the farm replace it); "
                    "not rendered"))
                continue
            if client is None:  # needs_cluster() saw no job here: the files changed since
                failed_frames.add(f.key)
                self.outcome.failures.append(Failure(describe(dataclasses.replace(f.parts[0], region=None)), f.key,
                                                     "its files changed while the run started; a re-run renders it"))
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
        failed_jobs: set[str] = set()  # parts come before their merge in `pending`
        done = failed = 0
        pending = dict(futures)
        try:
            running, asked, no_workers_since = 0, 0.0, None
            order = {key: i for i, key in enumerate(futures)}

            def fail(key, kind, f, p, message):
                failed_jobs.add(key)
                failed_frames.add(f.key)
                if kind == "merge" and any(q.key in failed_jobs for q in f.parts):
                    return  # the failed part is the one to report
                what = describe(p) if p else merge_spec(f, self.s)["what"]
                self.outcome.failures.append(Failure(what, key, message))
                progress.message(f"zigzag-farm: FAILED {what}: {indent(message)}")

            while pending:
                finished = {k: pending.pop(k) for k in [k for k, (fut, *_) in pending.items() if fut.done()]}
                results, lost = {}, {}
                for key, entry in finished.items():
                    fut = entry[0]
                    if fut.status != "finished":
                        continue  # an error or a cancel: _collect reports it
                    try:  # bounded: a result lost since done() is being made again, and a
                        # gather would wait for that (for ever, were every worker gone)
                        results[key] = fut.result(timeout=RESULT_TIMEOUT_S)
                    except Exception:
                        if fut.status == "finished" or not fut.done():
                            lost[key] = entry  # looked at again next round
                        # else its re-run failed: _collect reports the future's error
                for key in lost:
                    del finished[key]
                if lost:  # back in submission order: parts before their merge
                    pending = dict(sorted({**pending, **lost}.items(), key=lambda kv: order[kv[0]]))
                for key, (fut, kind, f, p) in finished.items():
                    error = self._collect(fut, results.get(key), kind, f, p)
                    # Recorded: the result is no longer wanted. A wanted result held by a
                    # worker that dies is made again (distributed's memory -> released ->
                    # waiting), so every frame a lost worker had finished would be rendered
                    # twice, its parts brought back after their merge. A merge still holds its
                    # parts through its own dependencies.
                    fut.release()
                    if error is None:
                        done += 1
                    else:
                        failed += 1
                        fail(key, kind, f, p, _failure_message(error))
                if time.monotonic() - asked >= RUNNING_EVERY_S:
                    running, render_workers = self._running(client, pending)
                    asked = time.monotonic()
                    if render_workers != 0:  # None: the scheduler did not answer, not "none"
                        no_workers_since = None
                    elif no_workers_since is None:
                        no_workers_since = asked
                    elif self.s.no_workers_s is not None and asked - no_workers_since > self.s.no_workers_s:
                        # Every worker is gone (walltime, node failure) and none came back:
                        # waiting on would hang for ever. The jobs left fail, and a re-run
                        # renders only them.
                        message = (f"no worker offering render=1 for {self.s.no_workers_s:g} s "
                                   "(all lost?); a re-run renders what is missing")
                        client.cancel([fut for fut, *_ in pending.values()])
                        for key, (fut, kind, f, p) in pending.items():
                            failed += 1
                            fail(key, kind, f, p, message)
                        pending.clear()
                progress.update(done=done, failed=failed, running=min(running, len(pending)))
                if pending:
                    # Wakes as soon as any job ends; the timeout only refreshes the progress line.
                    try:
                        wait([fut for fut, *_ in pending.values()], timeout=POLL_S,
                             return_when="FIRST_COMPLETED")
                    except TimeoutError:
                        pass
        except BaseException:
            if pending:  # none: no client either (needs_cluster)
                client.cancel([fut for fut, *_ in pending.values()])  # tasks kill their renderers
            raise
        finally:
            progress.update(done=done, failed=failed, running=0, force=True)
            progress.finish()
        self._remove_empty_work_folders()
        self.outcome.failed_frames = len(failed_frames)
        self.outcome.wall_s = time.monotonic() - start
        return self.outcome

    def _collect(self, fut, result: dict | None, kind: str, f: FrameJob,
                 p: RenderJob | None) -> BaseException | None:
        """Record a finished job (and its frame when that is complete) -> None, or the error."""
        if fut.status != "finished":
            return fut.exception() if fut.status == "error" else RuntimeError(f"job {fut.status}")
        if result.get("error"):  # a failure the task returned so that Dask does not retry it
            return job.JobError(result["error"])
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

    def _remove_empty_work_folders(self) -> None:
        """The region parts' folders once their parts are merged and removed (a folder still
        holding anything, another batch's parts or kept parts, stays): only those the run made
        (RunSettings.work_folders), deepest first."""
        if self.s.keep_parts:
            return
        parts_folders = {os.path.dirname(p.output) for f in self.plan.frames if f.merged for p in f.parts}
        if not parts_folders and self.s.work_folders is None:
            return
        for folder in self.s.work_folders if self.s.work_folders is not None else sorted(parts_folders):
            try:
                os.rmdir(folder)
            except OSError:
                pass

    @staticmethod
    def _running(client, pending) -> tuple[int, int | None]:
        """(jobs rendering now, workers offering render=1 or None if unknown). The scheduler's
        "processing" also holds the jobs a worker was handed but keeps waiting for its render
        slot, so each worker counts at most as many as it has slots (resources={"render": 1}:
        one)."""
        try:
            processing = client.processing()
            workers = client.scheduler_info()["workers"]
        except Exception:
            return 0, None
        running = 0
        for address, keys in processing.items():
            slots = render_slots(workers.get(address, {}), default=1)
            running += min(slots, sum(1 for k in keys if k in pending))
        render_workers = sum(1 for w in workers.values() if render_slots(w) >= 1)
        return running, render_workers
